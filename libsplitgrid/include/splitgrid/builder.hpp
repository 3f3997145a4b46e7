#pragma once

#include <functional>

#include "splitgrid/build_config.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/split_grid.hpp"

namespace sg {

/// Progress callback: fraction of triangles placed in final leaves so far, in [0, 1].
/// Called from the building thread(s) under a lock, at most a few hundred times per build.
using BuildProgress = std::function<void(double fraction_done)>;

/// Builds a Split Grid over `mesh` (docs/SPLIT_GRID.md, "Building a node"; BuildConfig for the
/// parameters).
///
/// - Each node splits the longest axis of the tight box of its triangles clipped to the
///   node's box (the poster says "longest axis of the node's box"; the tight box avoids
///   splitting an axis along which everything is flat or empty).
/// - The bounding planes lo, hi are the extent of those clipped triangles on the split axis.
/// - A triangle is referenced by every cell whose box, padded by `boundary_pad` of the
///   scene's bounding box, its clipped polygon touches (Sutherland-Hodgman in
///   double precision, rounded outward to floats; in subtrees below 4096 triangles a
///   straddling triangle is clipped once to its node's padded box and each cell's piece read
///   from that polygon, the same pieces up to double rounding: docs/SPLIT_GRID.md).
/// - Parallel on oneTBB with config.threads workers; the result is bit-identical for every
///   thread count.
///
/// Preconditions: check_mesh(mesh) passes (throws InputError otherwise); validate(config)
/// passes (throws ConfigError). Zero-area triangles are allowed but never referenced by
/// more cells than they touch. An empty mesh gives a grid with an empty root.
[[nodiscard]] SplitGrid build_split_grid(const MeshView& mesh, const BuildConfig& config,
                                         const BuildProgress& progress = {});

/// build_split_grid into an existing grid, for a scene rebuilt every frame: `grid` becomes
/// exactly what build_split_grid(mesh, config, progress) returns, and the memory of its
/// arrays is reused (they only grow when the new grid needs more). On an exception `grid` is
/// left empty or partly built, and must be rebuilt before use.
void rebuild_split_grid(SplitGrid& grid, const MeshView& mesh, const BuildConfig& config,
                        const BuildProgress& progress = {});

/// Absolute padding (scene units) added around every cell box when the builder decides which
/// triangles a cell references: 2^-20 times the largest coordinate magnitude M of `scene`
/// (8 to 16 float ulps of M), the scene's bounding box before padding, which every builder
/// passes. It absorbs the rounding of the watertight test, which may report a hit a little
/// outside a triangle's true extent: on an axis the ray runs parallel to, up to 4 * 2^-24 M
/// off, where the Split Grid, kd-tree and uniform grid take the cell of the origin's
/// coordinate and widen nothing; on the other axes the walks' own allowance covers it
/// (Padding::conservative; docs/SPLIT_GRID.md, "Why no ray slips through"). The pad grows
/// with M, not with the triangles: where they are small against the scene's extent, every
/// extra ulp of it costs references.
[[nodiscard]] float boundary_pad(const Aabb& scene) noexcept;

/// The box a structure is built in (SplitGrid::root_box, and the kd-tree's and the uniform
/// grid's): the scene's bounding box widened by `pad` (its boundary_pad) on each side, kept
/// finite next to +-FLT_MAX, where the pad is lost rather than turned into infinity.
[[nodiscard]] Aabb padded_root_box(const Aabb& scene, float pad) noexcept;

}  // namespace sg
