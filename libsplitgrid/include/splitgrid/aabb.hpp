#pragma once

#include <algorithm>
#include <limits>

#include "splitgrid/vec3.hpp"

namespace sg {

/// Axis-aligned box, closed on both sides: a point on a face is inside.
/// An empty box has lower > upper on every axis (the default).
struct Aabb {
    Vec3f lower{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                std::numeric_limits<float>::infinity()};
    Vec3f upper{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                -std::numeric_limits<float>::infinity()};

    [[nodiscard]] constexpr bool is_empty() const noexcept
    {
        return !(lower.x <= upper.x && lower.y <= upper.y && lower.z <= upper.z);
    }
    constexpr void extend(Vec3f p) noexcept
    {
        lower = {std::min(lower.x, p.x), std::min(lower.y, p.y), std::min(lower.z, p.z)};
        upper = {std::max(upper.x, p.x), std::max(upper.y, p.y), std::max(upper.z, p.z)};
    }
    /// Grows by box b, side by side: b's lower corner can only lower this box's lower side
    /// and its upper corner only raise the upper side, so an empty b adds nothing.
    constexpr void extend(const Aabb& b) noexcept
    {
        lower = {std::min(lower.x, b.lower.x), std::min(lower.y, b.lower.y),
                 std::min(lower.z, b.lower.z)};
        upper = {std::max(upper.x, b.upper.x), std::max(upper.y, b.upper.y),
                 std::max(upper.z, b.upper.z)};
    }
    [[nodiscard]] constexpr float extent(int axis) const noexcept
    {
        return upper[axis] - lower[axis];
    }
    /// Axis (0, 1, 2) of the largest extent; the lowest such axis on ties.
    [[nodiscard]] constexpr int longest_axis() const noexcept
    {
        int axis = 0;
        if (extent(1) > extent(axis)) axis = 1;
        if (extent(2) > extent(axis)) axis = 2;
        return axis;
    }
    /// Surface area (0 for an empty or flat-in-two-axes box).
    [[nodiscard]] constexpr double surface_area() const noexcept
    {
        if (is_empty()) return 0.0;
        // Extents in double: a float extent of a box near +-FLT_MAX overflows to infinity.
        const double dx = double(upper.x) - lower.x;
        const double dy = double(upper.y) - lower.y;
        const double dz = double(upper.z) - lower.z;
        return 2.0 * (dx * dy + dy * dz + dz * dx);
    }
    [[nodiscard]] constexpr bool contains(const Aabb& b) const noexcept
    {
        return lower.x <= b.lower.x && lower.y <= b.lower.y && lower.z <= b.lower.z &&
               b.upper.x <= upper.x && b.upper.y <= upper.y && b.upper.z <= upper.z;
    }
    friend constexpr bool operator==(const Aabb&, const Aabb&) = default;
};
static_assert(sizeof(Aabb) == 24, "Aabb must be two packed Vec3f: it is stored in .sg files");

}  // namespace sg
