#pragma once

#include "splitgrid/detail/grid_traversal.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/query_policy.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/traversal_counters.hpp"

namespace sg {

/// Closest hit along `ray` within [t_min, t_max] among the triangles of `mesh` (the mesh the
/// grid was built for). Returns the smallest t found by the watertight test; on equal t the
/// triangle found first wins. Invalid rays (see is_valid) return no hit.
/// Cost: the cells the ray crosses up to the hit, front to back; no recursion, a fixed
/// stack of max_supported_depth + 1 entries; a mailbox of the last 8 triangles tested skips
/// a triangle met again in a neighbouring cell (its answer cannot change).
[[nodiscard]] Hit intersect(const SplitGrid& grid, const MeshView& mesh, const Ray& ray,
                            TraversalCounters* counters = nullptr) noexcept;

/// True if any triangle is hit with t in [t_min, t_max] (shadow rays). Stops at the first hit.
[[nodiscard]] bool occluded(const SplitGrid& grid, const MeshView& mesh, const Ray& ray,
                            TraversalCounters* counters = nullptr) noexcept;

/// The same queries with another triangle-test policy (query_policy.hpp) or without the
/// traversal's conservative widening (Padding::None): for sg-bench's speed/accuracy chart and
/// for tests that count the triangle tests. intersect() is intersect_with<>().
template <class Test = WatertightTest, Padding padding = Padding::Conservative>
[[nodiscard]] Hit intersect_with(const SplitGrid& grid, const MeshView& mesh, const Ray& ray,
                                 TraversalCounters* counters = nullptr) noexcept
{
    Hit miss;
    miss.t = ray.t_max;
    if (!is_valid(ray)) return miss;
    detail::GridTraversal<false, Test, padding> traversal(grid, mesh, ray, counters);
    return traversal.run() ? traversal.hit() : miss;
}
template <class Test = WatertightTest, Padding padding = Padding::Conservative>
[[nodiscard]] bool occluded_with(const SplitGrid& grid, const MeshView& mesh, const Ray& ray,
                                 TraversalCounters* counters = nullptr) noexcept
{
    if (!is_valid(ray)) return false;
    detail::GridTraversal<true, Test, padding> traversal(grid, mesh, ray, counters);
    return traversal.run();
}

/// Reference answer: tests every triangle of the mesh in id order with the same watertight
/// test. O(triangles) per ray: for tests and the benchmark's correctness checks.
[[nodiscard]] Hit intersect_brute_force(const MeshView& mesh, const Ray& ray) noexcept;
[[nodiscard]] bool occluded_brute_force(const MeshView& mesh, const Ray& ray) noexcept;

}  // namespace sg
