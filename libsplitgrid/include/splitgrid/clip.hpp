#pragma once

#include "splitgrid/aabb.hpp"
#include "splitgrid/vec3.hpp"

namespace sg {

/// Double-precision box, closed on both sides; used by the builder and the checkers.
struct Aabbd {
    Vec3d lower;
    Vec3d upper;

    [[nodiscard]] static Aabbd from(const Aabb& b) noexcept
    {
        return {Vec3d(b.lower), Vec3d(b.upper)};
    }
    [[nodiscard]] Aabbd padded(double pad) const noexcept
    {
        return {{lower.x - pad, lower.y - pad, lower.z - pad},
                {upper.x + pad, upper.y + pad, upper.z + pad}};
    }
};

/// Bounding box of (triangle abc) intersected with `box`, computed by clipping the triangle
/// against the box's six planes (Sutherland-Hodgman, double precision; points on a plane
/// count as inside). Returns false when the intersection is empty. Degenerate triangles
/// (segments, points) are clipped like any other polygon.
/// Cost: a bounding-box test when the triangle lies inside the box; otherwise up to six
/// clips of a polygon of at most nine vertices.
[[nodiscard]] bool clip_triangle_bounds(Vec3d a, Vec3d b, Vec3d c, const Aabbd& box,
                                        Aabbd& out) noexcept;

/// Separating-axis triangle/box overlap test (Akenine-Moeller, "Fast 3D Triangle-Box Overlap
/// Testing", JGT 6(1), 2001) in double precision; touching counts as overlapping. Used by
/// check_coverage as an oracle independent of the clipping above.
[[nodiscard]] bool triangle_overlaps_box(Vec3d a, Vec3d b, Vec3d c, const Aabbd& box) noexcept;

}  // namespace sg
