#pragma once

/// The Split Grid's ray queries: closest hit, any hit, and every hit along rays.
///
/// The walk itself is SplitGridWalk in libsplitgrid/src/kernels/split_grid_walk.hpp
/// (docs/SPLIT_GRID.md, "Traversal", has it as pseudo-code). These functions reach it through
/// detail::closest_hits, detail::any_hits, ... (structure_queries.hpp), which
/// src/kernels/dispatch.cpp routes to the table of the active instruction set; each
/// kernels_<isa>.cpp compiles the walk for its instruction set through kernels_isa.inc.
/// docs/ARCHITECTURE.md lists the traversal's files in reading order.

#include <cstdint>
#include <span>

#include "splitgrid/brute_force.hpp"
#include "splitgrid/intersections.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/query.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/structure_queries.hpp"
#include "splitgrid/traversal_counters.hpp"

namespace sg {

/// Closest hit along `ray` within [t_min, t_max] among the triangles of `mesh` (the mesh the
/// grid was built for). Returns the smallest t found by the watertight test; on equal t the
/// smallest triangle id wins, so the answer does not depend on the order of the walk. Invalid rays (see is_valid) return no hit.
/// Cost: the cells the ray crosses up to the hit, front to back; no recursion, a fixed
/// stack of max_supported_depth + 1 entries; a mailbox skips a triangle met again in a
/// neighbouring cell (its answer cannot change); the triangles of a leaf are tested up to
/// eight at a time. Runs the kernels of kernel_isa() (query.hpp). `counters`, when given, gets
/// this query's work added (nodes entered, cells stepped, triangles tested). Precondition:
/// the grid passes check_invariants (the builder's grids do; read_sg_file checks every file).
[[nodiscard]] inline Hit intersect(const SplitGrid& grid, const MeshView& mesh, const Ray& ray,
                                   TraversalCounters* counters = nullptr,
                                   const QueryOptions& options = {}) noexcept
{
    Hit hit;
    detail::closest_hits(grid, mesh, {&ray, 1}, {&hit, 1}, counters, options);
    return hit;
}

/// True if any triangle is hit with t in [t_min, t_max] (shadow rays). Stops at the first hit.
[[nodiscard]] inline bool occluded(const SplitGrid& grid, const MeshView& mesh, const Ray& ray,
                                   TraversalCounters* counters = nullptr) noexcept
{
    std::uint8_t out = 0;
    detail::any_hits(grid, mesh, {&ray, 1}, {&out, 1}, counters);
    return out != 0;
}

/// Closest hits of a batch of rays (`hits` has rays.size() entries), serially in the calling
/// thread: the per-ray dispatch is paid once per batch. `total` gets the work of all rays.
inline void intersect(const SplitGrid& grid, const MeshView& mesh, std::span<const Ray> rays,
                      std::span<Hit> hits, TraversalCounters* total = nullptr,
                      const QueryOptions& options = {}) noexcept
{
    detail::closest_hits(grid, mesh, rays, hits, total, options);
}

/// Any-hit answers of a batch (1 = occluded).
inline void occluded(const SplitGrid& grid, const MeshView& mesh, std::span<const Ray> rays,
                     std::span<std::uint8_t> occluded, TraversalCounters* total = nullptr) noexcept
{
    detail::any_hits(grid, mesh, rays, occluded, total);
}

/// The number of distinct triangles each ray hits with t in [t_min, t_max], into `counts`
/// (rays.size() entries; 0 for an invalid ray), serially in the calling thread. Every triangle
/// is counted once however many cells reference it. With the watertight test (the default) a
/// ray counts what a slightly moved ray counts (ray_triangle.hpp): through an edge or vertex
/// where it crosses the surface, once; so the parity of the count along a ray from a point
/// tells inside from outside of a closed mesh (docs/SPLIT_GRID.md, "Exact edge functions").
/// `test` = TriangleTest::watertight_no_tie_break or moller_trumbore count as those tests do,
/// for comparisons. Cost: the ray's whole walk through [t_min, t_max] (no early end), plus a
/// sort of its hits.
inline void count_intersections(const SplitGrid& grid, const MeshView& mesh,
                                std::span<const Ray> rays, std::span<std::int32_t> counts,
                                TriangleTest test = TriangleTest::watertight) noexcept
{
    detail::count_hits(grid, mesh, rays, counts, test);
}

/// Every hit of each ray with t in [t_min, t_max], each triangle once, sorted by t then
/// triangle id, appended to `out` (IntersectionList: Open3D's layout; the rays are numbered on
/// from out.ray_count()), serially in the calling thread. Throws std::bad_alloc if the lists
/// do not fit in memory.
inline void list_intersections(const SplitGrid& grid, const MeshView& mesh,
                               std::span<const Ray> rays, IntersectionList& out)
{
    detail::all_hits(grid, mesh, rays, out);
}

}  // namespace sg
