#pragma once

#include <cstdint>
#include <limits>
#include <span>

#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/vec3.hpp"

namespace sg {

/// The point of a mesh closest to a query point. `triangle == invalid_triangle` when no
/// triangle lies within the query's max_distance (then distance is +infinity).
struct ClosestPoint {
    /// Euclidean distance from the query point, the float nearest the double computation.
    float distance = std::numeric_limits<float>::infinity();
    std::uint32_t triangle = invalid_triangle;
    /// Barycentrics of `point` on the triangle: u the weight of corner 1, v of corner 2.
    float u = 0.0f;
    float v = 0.0f;
    /// The closest point itself (rounded to float from the double computation).
    Vec3f point{};

    [[nodiscard]] constexpr bool is_hit() const noexcept { return triangle != invalid_triangle; }
};

/// The closest point on the mesh to each point (closest_points), or its distance only.
///
/// The search visits the structure's leaves nearest first and skips every node, cell or box
/// whose distance from the point exceeds that of the best triangle found so far. It is exact
/// (docs/SPLIT_GRID.md, "Closest points") because (1) every point of a triangle lies in the
/// closed box of some leaf that references it (check_coverage verifies it for the Split Grid;
/// the other structures' leaves hold their triangles whole or clipped with the pad), (2) the
/// distance to a box is a lower bound, computed in double from the cell bounds the builder
/// used widened by its boundary_pad, and (3) the search stops only when the next box is
/// farther than the best triangle, measured on whole (not clipped) triangles. Distances are
/// computed in double: the result is the true minimum to within 2^-40 (M + |p|), M the largest
/// coordinate magnitude of the root box, before the rounding to float. A point equally close
/// to several triangles (to within that tolerance) gets the smallest triangle id; an edge or
/// a vertex shared by several triangles gives all of them bit-identical distances (edges are
/// measured from their lexicographically smaller end), so there the smallest id wins exactly.
/// Points with a NaN or infinite coordinate get no hit and a NaN distance. Triangles beyond
/// `max_distance` are not reported (no hit, distance +infinity): the search prunes with it
/// from the start, so far points are cheap. Writes into `out` (points.size() entries),
/// serially in the calling thread. Defined for SplitGrid, Bvh, KdTree and UniformGrid; `mesh`
/// is the mesh the structure was built on.
template <class Structure>
void closest_points(const Structure& structure, const MeshView& mesh,
                    std::span<const Vec3f> points, std::span<ClosestPoint> out,
                    float max_distance = std::numeric_limits<float>::infinity()) noexcept;

/// The signed distance of each point to the closed mesh: the distance of closest_points,
/// negative inside (Open3D's convention), the side from compute_occupancy's exact parity with
/// `nsamples` rays (occupancy.hpp; odd). Points within the band of occupancy.hpp may get
/// either sign; their distance is then below that band. Beyond `max_distance`: +infinity
/// (no side is computed). NaN for a non-finite point. Throws ConfigError for an even or zero
/// nsamples.
template <class Structure>
void signed_distances(const Structure& structure, const MeshView& mesh,
                      std::span<const Vec3f> points, std::span<float> out,
                      std::uint32_t nsamples = 1,
                      float max_distance = std::numeric_limits<float>::infinity());

/// Reference answer: every triangle in id order, with the same distance computation and tie
/// rule. O(triangles) per point: for tests and the benchmark's correctness checks.
[[nodiscard]] ClosestPoint closest_point_brute_force(
    const MeshView& mesh, Vec3f point,
    float max_distance = std::numeric_limits<float>::infinity()) noexcept;

}  // namespace sg
