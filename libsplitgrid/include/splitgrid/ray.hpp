#pragma once

#include <cstdint>
#include <limits>

#include "splitgrid/vec3.hpp"

namespace sg {

/// A ray o + t d, searched for hits with t in the closed interval [t_min, t_max].
/// The direction need not be normalised; t is measured in units of |d|.
/// Direction components with magnitude below FLT_MIN (denormals) are treated as zero by
/// every query, so that 1/d never overflows.
/// Range: the ray/triangle test works in float, so products of two coordinate differences
/// must stay normal floats: triangle sizes and coordinates between about 1e-18 and 1e18.
/// Outside it products underflow or overflow and hits are lost, by the grid and the
/// brute-force reference alike (nothing crashes); scale such scenes.
struct Ray {
    Vec3f origin;
    Vec3f direction;
    float t_min = 0.0f;
    float t_max = std::numeric_limits<float>::infinity();
};

/// Triangle id meaning "no hit".
inline constexpr std::uint32_t invalid_triangle = 0xFFFFFFFFu;

/// Result of a closest-hit query. `triangle == invalid_triangle` means the ray hit nothing;
/// then t is the ray's t_max and u, v are 0. The hit point is
/// (1 - u - v) * v0 + u * v1 + v * v2 for the triangle's vertices v0, v1, v2.
struct Hit {
    float t = std::numeric_limits<float>::infinity();
    std::uint32_t triangle = invalid_triangle;
    float u = 0.0f;
    float v = 0.0f;

    [[nodiscard]] constexpr bool is_hit() const noexcept { return triangle != invalid_triangle; }
};

/// A ray is valid when its origin, direction and t_min are finite, t_max is not NaN,
/// t_min <= t_max and the direction is not zero. Every query returns "no hit" for an
/// invalid ray without touching the structure.
[[nodiscard]] bool is_valid(const Ray& ray) noexcept;

/// What makes a ray invalid (is_valid), in words, for the tools' messages about such rays.
inline constexpr const char* invalid_ray_description =
    "NaN or infinite origin or direction, zero direction, NaN or infinite t_min, NaN t_max "
    "or t_min > t_max";

}  // namespace sg
