#pragma once

#include <algorithm>
#include <array>
#include <cstddef>

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

/// Bounding box of triangle abc.
[[nodiscard]] inline Aabbd triangle_box(const Vec3d& a, const Vec3d& b, const Vec3d& c) noexcept
{
    return {{std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::min({a.z, b.z, c.z})},
            {std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}), std::max({a.z, b.z, c.z})}};
}

/// A triangle clipped to a box (Sutherland-Hodgman, double precision; points on a plane count
/// as inside), kept as its polygon so that the bounds of its parts in several slabs can be
/// read without clipping the triangle again: the builder clips a triangle that straddles
/// cells once per node and reads each cell's piece from the polygon.
class ClippedTriangle {
public:
    /// Clips triangle abc to `box`; false where they do not touch (the polygon is then
    /// empty). Degenerate triangles (segments, points) are clipped like any other polygon.
    bool clip(Vec3d a, Vec3d b, Vec3d c, const Aabbd& box) noexcept;

    /// Bounding box of the polygon, clamped to `box` (interpolated points can stray from it
    /// by a rounding error; the piece lies in it by definition). Precondition: clip() was
    /// true for a box inside `box`.
    [[nodiscard]] Aabbd bounds(const Aabbd& box) const noexcept;

    /// Bounding box of the part of the polygon in the slab box.lower[axis] <= p[axis] <=
    /// box.upper[axis], clamped to `box`; false where the part is empty. The part of a
    /// convex polygon in a slab is spanned by its vertices inside the slab and the points
    /// where its edges cross the slab's two planes, so no clipping is needed: the result
    /// equals clipping the triangle to `box` up to rounding. Precondition: on the other two
    /// axes `box` contains the polygon (the clamp there only absorbs rounding; a box that
    /// cut the polygon would give a clamped box, not the clipped one).
    bool slab_bounds(int axis, const Aabbd& box, Aabbd& out) const noexcept;

    /// slab_bounds for two overlapping slabs at once, `below` and `above` on `axis` (two
    /// neighbouring padded cells: below.lower <= above.lower <= below.upper <= above.upper):
    /// when every vertex of the polygon lies in [below.lower, above.upper] on the axis, sets
    /// found[i] and out[i] to what slab_bounds returns and writes for the i-th slab, bit for
    /// bit, in one pass that crosses each edge with the two inner planes only (the outer ones
    /// cannot cut it), and returns true; otherwise returns false and writes nothing.
    bool adjacent_slab_bounds(int axis, const Aabbd& below, const Aabbd& above,
                              std::array<Aabbd, 2>& out, std::array<bool, 2>& found) const noexcept;

    /// A triangle clipped by six planes has at most 3 + 6 vertices. Rounding can make a
    /// polygon slightly non-convex and a clip then add more; the count is capped at this
    /// after each edge, and the two spare places take the at most two points one edge adds.
    /// Past the last vertex a copy of the first closes the polygon, so that the edge loops
    /// read each edge's end without a wrap-around test.
    static constexpr int max_vertices = 9;
    struct Polygon {
        std::array<Vec3d, max_vertices + 2> v;
        int count = 0;
    };

private:
    // The polygon is clipped from one buffer into the other, plane by plane; buffers_[result_]
    // holds the result. Both live as long as the object, so an object reused for many
    // triangles sets up no polygon per clip.
    std::array<Polygon, 2> buffers_;
    std::size_t result_ = 0;
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
