#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/vec3.hpp"

namespace sg {

/// Where a hit is, for spawning secondary rays: the point from the barycentric coordinates
/// (more accurate than origin + t * direction, whose error grows with t) and the
/// unnormalised geometric normal (v1 - v0) x (v2 - v0).
struct SurfacePoint {
    Vec3f position;
    Vec3f normal;
};

[[nodiscard]] inline SurfacePoint surface_point(const MeshView& mesh, const Hit& hit) noexcept
{
    const Vec3f v0 = mesh.vertex(hit.triangle, 0);
    const Vec3f v1 = mesh.vertex(hit.triangle, 1);
    const Vec3f v2 = mesh.vertex(hit.triangle, 2);
    const float w = 1.0f - hit.u - hit.v;
    return {v0 * w + v1 * hit.u + v2 * hit.v, cross(v1 - v0, v2 - v0)};
}

/// The offset rule for secondary rays. A computed hit point lies within a few ulps of the
/// true surface, on either side, so a ray leaving from it may hit its own triangle again.
/// The origin is moved off the surface along the normal, towards the side the new ray
/// leaves on: by `offset_ulps` units in the last place of each coordinate (an error relative
/// to the coordinate's magnitude, as the hit point's rounding error is), and, for coordinates
/// below `origin_zone` in magnitude, where ulps become tiny, by `absolute_offset` times the
/// unit normal instead. The constants follow the analysis of Waechter and Binder, "A Fast and
/// Robust Method for Avoiding Self-Intersection" (Ray Tracing Gems, 2019).
/// Consequence: surfaces closer than about offset_ulps ulps of their coordinates to the
/// spawning surface are skipped by the secondary ray (tests/robustness measures the gap).
struct RayOffsetRule {
    float offset_ulps = 256.0f;
    float origin_zone = 1.0f / 32.0f;
    float absolute_offset = 1.0f / 65536.0f;
};

/// `point` moved off the surface with unit normal `unit_normal` to the side of `direction`.
[[nodiscard]] inline Vec3f offset_origin(Vec3f point, Vec3f unit_normal, Vec3f direction,
                                         const RayOffsetRule& rule = {}) noexcept
{
    const Vec3f n = dot(unit_normal, direction) < 0.0f ? unit_normal * -1.0f : unit_normal;
    Vec3f result = point;
    for (int axis = 0; axis < 3; ++axis) {
        const float p = point[axis];
        if (std::fabs(p) < rule.origin_zone) {
            result[axis] = p + rule.absolute_offset * n[axis];
            continue;
        }
        // Moving the bit pattern by k moves the float by k ulps, away from zero for positive
        // k and a positive p; the sign of p decides which way "up" the pattern runs.
        const auto ulps = static_cast<std::int32_t>(rule.offset_ulps * n[axis]);
        const std::int32_t step = p < 0.0f ? -ulps : ulps;
        const float moved = std::bit_cast<float>(std::bit_cast<std::int32_t>(p) + step);
        // Near +-FLT_MAX the pattern may step into infinity or NaN: keep the point finite.
        result[axis] = std::isfinite(moved) ? moved : p;
    }
    return result;
}

/// A secondary ray from a hit: origin offset by `rule`, t_min 0, t_max `t_max` (for a shadow
/// ray towards a point, pass the distance in units of `direction`).
[[nodiscard]] inline Ray spawn_ray(const SurfacePoint& at, Vec3f direction,
                                   float t_max = std::numeric_limits<float>::infinity(),
                                   const RayOffsetRule& rule = {}) noexcept
{
    return {offset_origin(at.position, normalize(at.normal), direction, rule), direction, 0.0f,
            t_max};
}

}  // namespace sg
