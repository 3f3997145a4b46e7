#pragma once

// Point queries: the distance from a point to a triangle, and the state of one closest point
// search (closest_point.hpp), shared by every structure's point walk, in plain double
// precision. Included by kernel_deps.hpp, so compiled for the baseline instruction set: the
// batched lanes (point_lanes.hpp) measure triangles eight at a time with the same operations
// and hand their results here.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "splitgrid/aabb.hpp"
#include "splitgrid/closest_point.hpp"
#include "splitgrid/mesh.hpp"

namespace sg::kernels::points {

struct Vec3d {
    double x, y, z;
};
[[nodiscard]] inline Vec3d to_double(Vec3f v) noexcept { return {v.x, v.y, v.z}; }
[[nodiscard]] inline Vec3d operator-(Vec3d a, Vec3d b) noexcept
{
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
[[nodiscard]] inline Vec3d operator+(Vec3d a, Vec3d b) noexcept
{
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
[[nodiscard]] inline Vec3d operator*(Vec3d a, double s) noexcept { return {a.x * s, a.y * s, a.z * s}; }
[[nodiscard]] inline double dot(Vec3d a, Vec3d b) noexcept { return a.x * b.x + a.y * b.y + a.z * b.z; }
[[nodiscard]] inline Vec3d cross(Vec3d a, Vec3d b) noexcept
{
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// Whether float point a comes before b in (x, y, z) order.
[[nodiscard]] inline bool lexicographically_before(Vec3f a, Vec3f b) noexcept
{
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
}

/// The closest point of a triangle to a point: squared distance, barycentrics (u the weight of
/// corner 1, v of corner 2) and the point.
struct TrianglePoint {
    double distance2 = std::numeric_limits<double>::infinity();
    double u = 0.0, v = 0.0;
    Vec3d point{};
};

/// The closest point on the segment between corners `i` and `j` of triangle `c` (corners in
/// double `cd`, in float `cf`), measured from the lexicographically smaller end, so that both
/// triangles of an edge compute the same bits; an end is returned as itself.
[[nodiscard]] inline TrianglePoint closest_on_edge(Vec3d q, const Vec3f (&cf)[3],
                                                   const Vec3d (&cd)[3], int i, int j) noexcept
{
    if (lexicographically_before(cf[j], cf[i])) std::swap(i, j);
    const Vec3d p = cd[i], e = cd[j] - cd[i];
    const double len2 = dot(e, e);
    const double s = len2 > 0.0 ? std::clamp(dot(q - p, e) / len2, 0.0, 1.0) : 0.0;
    TrianglePoint out;
    out.point = s <= 0.0 ? cd[i] : s >= 1.0 ? cd[j] : p + e * s;
    const Vec3d d = q - out.point;
    out.distance2 = dot(d, d);
    // Barycentrics: weight s on corner j, 1 - s on corner i.
    double w[3] = {0.0, 0.0, 0.0};
    w[i] = 1.0 - s;
    w[j] = s;
    out.u = w[1];
    out.v = w[2];
    return out;
}

/// The closest point of triangle (a, b, c) to q: the foot of the perpendicular where it falls
/// strictly inside the triangle (the edge functions of the projection all positive), else the
/// closest point of its three edges.
[[nodiscard]] inline TrianglePoint closest_on_triangle(Vec3d q, const Vec3f (&cf)[3]) noexcept
{
    const Vec3d cd[3] = {to_double(cf[0]), to_double(cf[1]), to_double(cf[2])};
    const Vec3d n = cross(cd[1] - cd[0], cd[2] - cd[0]);
    const double n2 = dot(n, n);
    if (n2 > 0.0) {
        const double wa = dot(n, cross(cd[2] - cd[1], q - cd[1]));  // opposite corner 0
        const double wb = dot(n, cross(cd[0] - cd[2], q - cd[2]));  // opposite corner 1
        const double wc = dot(n, cross(cd[1] - cd[0], q - cd[0]));  // opposite corner 2
        if (wa > 0.0 && wb > 0.0 && wc > 0.0) {
            const double height = dot(n, q - cd[0]);
            TrianglePoint out;
            out.distance2 = height * height / n2;
            out.u = wb / n2;
            out.v = wc / n2;
            out.point = q - n * (height / n2);
            return out;
        }
    }
    TrianglePoint best = closest_on_edge(q, cf, cd, 0, 1);
    for (const auto& [i, j] : {std::pair{1, 2}, std::pair{2, 0}}) {
        const TrianglePoint e = closest_on_edge(q, cf, cd, i, j);
        if (e.distance2 < best.distance2) best = e;
    }
    return best;
}

/// Squared distance from q to the closed box, in double (0 inside).
[[nodiscard]] inline double box_distance2(Vec3d q, const Aabb& box) noexcept
{
    double d2 = 0.0;
    const double c[3] = {q.x, q.y, q.z};
    for (int k = 0; k < 3; ++k) {
        const double gap = std::max({double{box.lower[k]} - c[k], 0.0, c[k] - double{box.upper[k]}});
        d2 += gap * gap;
    }
    return d2;
}

/// The state of one closest point search: the best triangle so far and the bound that prunes
/// boxes. Two distances within `tolerance` of each other count as equal, and then the smaller
/// triangle id wins, so the answer does not depend on the order in which a walk meets
/// triangles; a box is skipped only when its distance exceeds the best by more than that.
class PointSearch {
public:
    /// `magnitude`: the largest coordinate magnitude of the structure's root box.
    PointSearch(Vec3f point, float magnitude, float max_distance) noexcept
        : q_(to_double(point)),
          tolerance_(0x1p-40 * (double{magnitude} + std::max({std::abs(double{point.x}),
                                                                std::abs(double{point.y}),
                                                                std::abs(double{point.z})}))),
          limit2_(double{max_distance} * max_distance)
    {
        bound2_ = limit2_;
    }

    [[nodiscard]] Vec3d point() const noexcept { return q_; }
    /// Boxes farther than this (squared) hold nothing the search can use.
    [[nodiscard]] double bound2() const noexcept { return bound2_; }
    [[nodiscard]] bool prunes(double box_distance2) const noexcept { return box_distance2 > bound2_; }

    /// Tests triangle `tri` of `mesh`: first against the box of its corners (a cheap lower
    /// bound), then exactly.
    void offer(const MeshView& mesh, std::uint32_t tri) noexcept
    {
        const Vec3f cf[3] = {mesh.vertex(tri, 0), mesh.vertex(tri, 1), mesh.vertex(tri, 2)};
        Aabb box;
        for (const Vec3f& c : cf) box.extend(c);
        if (prunes(box_distance2(q_, box))) return;
        const TrianglePoint p = closest_on_triangle(q_, cf);
        if (beats_best(p.distance2, tri)) keep(p, tri);
    }

    /// Offers triangle `tri` whose squared distance `distance2` was measured already, bit for
    /// bit as closest_on_triangle measures it (the batched lanes of point_lanes.hpp); the rest
    /// of its closest point is measured only if it becomes the best.
    void offer_distance(const MeshView& mesh, std::uint32_t tri, double distance2) noexcept
    {
        if (!beats_best(distance2, tri)) return;
        const Vec3f cf[3] = {mesh.vertex(tri, 0), mesh.vertex(tri, 1), mesh.vertex(tri, 2)};
        keep(closest_on_triangle(q_, cf), tri);
    }

    [[nodiscard]] ClosestPoint result() const noexcept
    {
        ClosestPoint out;
        if (!found_) return out;
        out.distance = static_cast<float>(std::sqrt(best_.distance2));
        out.triangle = triangle_;
        out.u = static_cast<float>(best_.u);
        out.v = static_cast<float>(best_.v);
        out.point = Vec3f{static_cast<float>(best_.point.x), static_cast<float>(best_.point.y),
                          static_cast<float>(best_.point.z)};
        return out;
    }

private:
    /// Within the bound, and closer by more than the tolerance, or as close with a smaller id.
    [[nodiscard]] bool beats_best(double distance2, std::uint32_t tri) const noexcept
    {
        if (!(distance2 <= bound2_)) return false;
        return !found_ || distance2 < closer2_ || tri < triangle_;
    }

    void keep(const TrianglePoint& p, std::uint32_t tri) noexcept
    {
        found_ = true;
        best_ = p;
        triangle_ = tri;
        const double best = std::sqrt(p.distance2);
        const double reach = best + tolerance_;
        bound2_ = std::min(limit2_, reach * reach);
        closer2_ = best > tolerance_ ? (best - tolerance_) * (best - tolerance_) : -1.0;
    }

    Vec3d q_;
    double tolerance_;
    double limit2_;
    double bound2_;
    double closer2_ = -1.0;  ///< a squared distance below this beats the best whatever its id
    bool found_ = false;
    TrianglePoint best_;
    std::uint32_t triangle_ = invalid_triangle;
};

}  // namespace sg::kernels::points
