#pragma once

#include <cstdint>
#include <span>

#include "splitgrid/mesh.hpp"
#include "splitgrid/query.hpp"
#include "splitgrid/ray.hpp"

namespace sg {

/// The rays occupancy casts from `point` for a structure whose root box is `box`: sample 0
/// along the axis direction that leaves the box soonest (the shortest walk), tilted by 2^-5
/// and 2^-7 towards the other two axes (a ray parallel to two axes makes a BVH visit every
/// box its slab crosses), samples 1 ..
/// nsamples - 1 along directions spread evenly over the sphere (a Fibonacci lattice), the
/// same for every point. Each ray runs over [0, infinity).
[[nodiscard]] Ray occupancy_ray(Vec3f point, const Aabb& box, std::uint32_t sample,
                                std::uint32_t nsamples) noexcept;

/// Inside (1) or outside (0) of the closed mesh, for each point: the parity of the number of
/// triangles a ray from the point crosses (count_intersections), by the majority of
/// `nsamples` rays (occupancy_ray; odd, at least 1). The count is exact (docs/SPLIT_GRID.md,
/// "Exact edge functions"), so the answer is right for every point farther from the surface
/// than 2^-17 times the largest coordinate magnitude of the root box (docs/SPLIT_GRID.md,
/// "Inside or outside"), whatever the rays meet on their way (edges, vertices, triangles seen
/// edge-on); nearer, either answer may come. More rays are a vote only where the mesh is not
/// closed. Valid where every edge is
/// shared by an even number of triangles (edge_report). A point outside the root box is
/// outside without a ray; a point with a NaN or infinite coordinate gets NaN. Writes into `out`
/// (points.size() entries), serially in the calling thread. Throws ConfigError for an even or
/// zero `nsamples`. Defined for SplitGrid, Bvh, KdTree and UniformGrid; `mesh` is the mesh the
/// structure was built on. `test` other than the watertight one is for comparisons (query.hpp).
template <class Structure>
void compute_occupancy(const Structure& structure, const MeshView& mesh,
                       std::span<const Vec3f> points, std::span<float> out,
                       std::uint32_t nsamples = 1, TriangleTest test = TriangleTest::watertight);

}  // namespace sg
