#pragma once

#include <cstdint>

#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/split_grid.hpp"

namespace sg {

/// Work done by one query, for heat maps and the cost statistics.
struct TraversalCounters {
    std::uint32_t nodes_visited = 0;     ///< inner nodes whose slab the ray was clipped to
    std::uint32_t cells_visited = 0;     ///< cells stepped through (empty ones included)
    std::uint32_t triangles_tested = 0;  ///< ray/triangle tests run
};

/// Closest hit along `ray` within [t_min, t_max] among the triangles of `mesh` (the mesh the
/// grid was built for). Returns the smallest t found by the watertight test; on equal t the
/// triangle found first wins. Invalid rays (see is_valid) return no hit.
/// Cost: the cells the ray crosses up to the hit, front to back; no recursion, a fixed
/// stack of max_supported_depth + 1 entries.
[[nodiscard]] Hit intersect(const SplitGrid& grid, const MeshView& mesh, const Ray& ray,
                            TraversalCounters* counters = nullptr) noexcept;

/// True if any triangle is hit with t in [t_min, t_max] (shadow rays). Stops at the first hit.
[[nodiscard]] bool occluded(const SplitGrid& grid, const MeshView& mesh, const Ray& ray,
                            TraversalCounters* counters = nullptr) noexcept;

/// Reference answer: tests every triangle of the mesh in id order with the same watertight
/// test. O(triangles) per ray: for tests and the benchmark's correctness checks.
[[nodiscard]] Hit intersect_brute_force(const MeshView& mesh, const Ray& ray) noexcept;
[[nodiscard]] bool occluded_brute_force(const MeshView& mesh, const Ray& ray) noexcept;

}  // namespace sg
