#pragma once

// The root box of each structure and its largest coordinate magnitude, for the queries that
// are written once for every structure (occupancy, closest points) and the kernels.

#include <algorithm>
#include <cmath>

#include "splitgrid/aabb.hpp"
#include "splitgrid/split_grid.hpp"

namespace sg::detail {

/// The box every query of the structure starts from.
[[nodiscard]] inline const Aabb& root_box(const SplitGrid& grid) noexcept { return grid.root_box; }
template <class Structure>
[[nodiscard]] const Aabb& root_box(const Structure& structure) noexcept
{
    return structure.box();
}

/// Largest coordinate magnitude of `box` (0 for an empty box): the M of the crossing
/// allowance (kernel_ray.hpp) and of the point queries' tolerance.
[[nodiscard]] inline float box_magnitude(const Aabb& box) noexcept
{
    if (box.is_empty()) return 0.0f;
    float m = 0.0f;
    for (int k = 0; k < 3; ++k) m = std::max({m, std::abs(box.lower[k]), std::abs(box.upper[k])});
    return m;
}

}  // namespace sg::detail
