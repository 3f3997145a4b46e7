#include "splitgrid/clip.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <type_traits>
#include <utility>

namespace sg {
namespace {

constexpr int max_polygon_vertices = ClippedTriangle::max_vertices;
using Polygon = ClippedTriangle::Polygon;

// x and y of a point or bound as one pair of lanes (GCC's and Clang's vector extension).
using Pair = double __attribute__((vector_size(16)));
static_assert(sizeof(Vec3d) == 3 * sizeof(double) && offsetof(Vec3d, y) == sizeof(double) &&
                  std::is_standard_layout_v<Vec3d> && std::is_trivially_copyable_v<Vec3d>,
              "Vec3d's x and y are loaded as one Pair");

[[gnu::always_inline]] inline Pair xy_of(const Vec3d& p) noexcept
{
    Pair xy;
    std::memcpy(&xy, &p, sizeof xy);  // x and y, the first 16 bytes of the object
    return xy;
}

// The point of edge pq on the plane p[Axis] = plane, from the signed distances dp and dq of
// its ends (on different sides), placed on the plane exactly so that later clips see the
// coordinate the plane has, not a rounded neighbour. Negating both distances gives the same
// point, bit for bit.
template <int Axis>
Vec3d edge_point(const Vec3d& p, const Vec3d& q, double dp, double dq, double plane) noexcept
{
    const double s = dp / (dp - dq);
    Vec3d x{p.x + (q.x - p.x) * s, p.y + (q.y - p.y) * s, p.z + (q.z - p.z) * s};
    component<Axis>(x) = plane;
    return x;
}

// Keeps the part of `in` with sign * (p[Axis] - plane) >= 0.
template <int Axis>
void clip_polygon(const Polygon& in, double plane, double sign, Polygon& out) noexcept
{
    out.count = 0;
    for (int i = 0; i < in.count; ++i) {
        const Vec3d& p = in.v[static_cast<std::size_t>(i)];
        const Vec3d& q = in.v[static_cast<std::size_t>(i + 1)];
        const double dp = sign * (component<Axis>(p) - plane);
        const double dq = sign * (component<Axis>(q) - plane);
        if (dp >= 0.0) out.v[static_cast<std::size_t>(out.count++)] = p;
        if ((dp >= 0.0) != (dq >= 0.0))
            out.v[static_cast<std::size_t>(out.count++)] = edge_point<Axis>(p, q, dp, dq, plane);
        if (out.count > max_polygon_vertices) out.count = max_polygon_vertices;
    }
    out.v[static_cast<std::size_t>(out.count)] = out.v[0];
}

// Clips `current` to the box's two planes on Axis where the triangle's box `tri` crosses
// them, swapping `current` and `next` after each clip; false once nothing is left.
template <int Axis>
bool clip_to_slab(const Aabbd& tri, const Aabbd& box, Polygon*& current, Polygon*& next) noexcept
{
    if (component<Axis>(tri.lower) < component<Axis>(box.lower)) {
        clip_polygon<Axis>(*current, component<Axis>(box.lower), 1.0, *next);
        std::swap(current, next);
        if (current->count == 0) return false;
    }
    if (component<Axis>(tri.upper) > component<Axis>(box.upper)) {
        clip_polygon<Axis>(*current, component<Axis>(box.upper), -1.0, *next);
        std::swap(current, next);
        if (current->count == 0) return false;
    }
    return true;
}

}  // namespace

bool ClippedTriangle::clip(Vec3d a, Vec3d b, Vec3d c, const Aabbd& box) noexcept
{
    const Aabbd tri = triangle_box(a, b, c);
    result_ = 0;
    buffers_[0].count = 0;
    for (int k = 0; k < 3; ++k)
        if (tri.upper[k] < box.lower[k] || tri.lower[k] > box.upper[k]) return false;
    Polygon* current = &buffers_[0];
    Polygon* next = &buffers_[1];
    current->v[0] = a;
    current->v[1] = b;
    current->v[2] = c;
    current->v[3] = a;
    current->count = 3;
    (void)(clip_to_slab<0>(tri, box, current, next) && clip_to_slab<1>(tri, box, current, next) &&
           clip_to_slab<2>(tri, box, current, next));
    result_ = current == &buffers_[0] ? 0 : 1;
    return current->count > 0;
}

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

// The box of the points added so far (lower > upper while there are none), x and y as a pair:
// a point costs one min and one max on the pair and one of each on z instead of three each
// (docs/notebook/build.md, "A piece's box widened two coordinates at a time"). Lane by lane
// `a < b ? a : b` is what std::min(b, a) returns, also for zeros of either sign and NaNs (GCC
// compiles it to minpd), so the box is the one per-component std::min and std::max give.
struct Widening {
    Pair lower_xy = {infinity, infinity};
    Pair upper_xy = {-infinity, -infinity};
    double lower_z = infinity;
    double upper_z = -infinity;

    [[gnu::always_inline]] void add(const Vec3d& p) noexcept
    {
        const Pair xy = xy_of(p);
        lower_xy = xy < lower_xy ? xy : lower_xy;  // std::min(lower, p)
        upper_xy = upper_xy < xy ? xy : upper_xy;  // std::max(upper, p)
        lower_z = std::min(lower_z, p.z);
        upper_z = std::max(upper_z, p.z);
    }
    [[nodiscard]] Aabbd box() const noexcept
    {
        return {{lower_xy[0], lower_xy[1], lower_z}, {upper_xy[0], upper_xy[1], upper_z}};
    }
};

inline Vec3d clamped(const Vec3d& p, const Aabbd& box) noexcept
{
    return {std::clamp(p.x, box.lower.x, box.upper.x), std::clamp(p.y, box.lower.y, box.upper.y),
            std::clamp(p.z, box.lower.z, box.upper.z)};
}
inline Aabbd clamped(const Aabbd& b, const Aabbd& box) noexcept
{
    return {clamped(b.lower, box), clamped(b.upper, box)};
}

}  // namespace

Aabbd ClippedTriangle::bounds(const Aabbd& box) const noexcept
{
    Widening out;
    const Polygon& polygon = buffers_[result_];
    for (int i = 0; i < polygon.count; ++i) out.add(polygon.v[static_cast<std::size_t>(i)]);
    return clamped(out.box(), box);
}

namespace {

// Widens `piece` by the point of edge pq on the plane, where its ends lie on different
// sides (the point clip_polygon would make), and sets `any`. A vertex on the plane is in the
// slab and taken by the caller; an edge that ends on the plane adds that vertex again at most.
template <int Axis>
[[gnu::always_inline]] inline void add_crossing(const Vec3d& p, const Vec3d& q, double plane,
                                                Widening& piece, bool& any) noexcept
{
    const double dp = component<Axis>(p) - plane;
    const double dq = component<Axis>(q) - plane;
    if ((dp >= 0.0) == (dq >= 0.0)) return;
    piece.add(edge_point<Axis>(p, q, dp, dq, plane));
    any = true;
}

// ClippedTriangle::slab_bounds for a split axis known at compile time.
template <int Axis>
bool slab_bounds_on(const Polygon& polygon, const Aabbd& box, Aabbd& out) noexcept
{
    const double lower = component<Axis>(box.lower);
    const double upper = component<Axis>(box.upper);
    Widening piece;
    bool any = false;
    for (int i = 0; i < polygon.count; ++i) {
        const Vec3d& p = polygon.v[static_cast<std::size_t>(i)];
        const Vec3d& q = polygon.v[static_cast<std::size_t>(i + 1)];
        if (component<Axis>(p) >= lower && component<Axis>(p) <= upper) {
            piece.add(p);
            any = true;
        }
        add_crossing<Axis>(p, q, lower, piece, any);
        add_crossing<Axis>(p, q, upper, piece, any);
    }
    if (!any) return false;
    out = clamped(piece.box(), box);
    return true;
}

// ClippedTriangle::adjacent_slab_bounds for a split axis known at compile time. With every
// vertex in [below.lower, above.upper], slab_bounds_on's test of a vertex against a slab's
// outer plane always passes and its crossings of that plane find none, so what is left for
// each slab is the same sequence of points added, in the same order (which keeps the sign of a
// zero the same too).
template <int Axis>
bool adjacent_slab_bounds_on(const Polygon& polygon, const Aabbd& below, const Aabbd& above,
                             std::array<Aabbd, 2>& out, std::array<bool, 2>& found) noexcept
{
    const double lower = component<Axis>(below.lower);
    const double upper = component<Axis>(above.upper);
    const double below_top = component<Axis>(below.upper);
    const double above_bottom = component<Axis>(above.lower);
    for (int i = 0; i < polygon.count; ++i) {
        const double x = component<Axis>(polygon.v[static_cast<std::size_t>(i)]);
        if (!(x >= lower && x <= upper)) return false;
    }
    Widening pieces[2];
    bool any[2] = {false, false};
    for (int i = 0; i < polygon.count; ++i) {
        const Vec3d& p = polygon.v[static_cast<std::size_t>(i)];
        const Vec3d& q = polygon.v[static_cast<std::size_t>(i + 1)];
        if (component<Axis>(p) <= below_top) {
            pieces[0].add(p);
            any[0] = true;
        }
        add_crossing<Axis>(p, q, below_top, pieces[0], any[0]);
        if (component<Axis>(p) >= above_bottom) {
            pieces[1].add(p);
            any[1] = true;
        }
        add_crossing<Axis>(p, q, above_bottom, pieces[1], any[1]);
    }
    found = {any[0], any[1]};
    if (any[0]) out[0] = clamped(pieces[0].box(), below);
    if (any[1]) out[1] = clamped(pieces[1].box(), above);
    return true;
}

}  // namespace

bool ClippedTriangle::slab_bounds(int axis, const Aabbd& box, Aabbd& out) const noexcept
{
    switch (axis) {
    case 0: return slab_bounds_on<0>(buffers_[result_], box, out);
    case 1: return slab_bounds_on<1>(buffers_[result_], box, out);
    default: return slab_bounds_on<2>(buffers_[result_], box, out);
    }
}

bool ClippedTriangle::adjacent_slab_bounds(int axis, const Aabbd& below, const Aabbd& above,
                                           std::array<Aabbd, 2>& out,
                                           std::array<bool, 2>& found) const noexcept
{
    const Polygon& polygon = buffers_[result_];
    switch (axis) {
    case 0: return adjacent_slab_bounds_on<0>(polygon, below, above, out, found);
    case 1: return adjacent_slab_bounds_on<1>(polygon, below, above, out, found);
    default: return adjacent_slab_bounds_on<2>(polygon, below, above, out, found);
    }
}

bool clip_triangle_bounds(Vec3d a, Vec3d b, Vec3d c, const Aabbd& box, Aabbd& out) noexcept
{
    // A triangle inside the box is its own piece: no polygon is set up (most calls of the
    // grid and kd-tree builders).
    const Aabbd tri = triangle_box(a, b, c);
    bool inside = true;
    for (int k = 0; k < 3; ++k) {
        if (tri.upper[k] < box.lower[k] || tri.lower[k] > box.upper[k]) return false;
        inside = inside && tri.lower[k] >= box.lower[k] && tri.upper[k] <= box.upper[k];
    }
    if (inside) {
        out = tri;
        return true;
    }
    ClippedTriangle clipped;
    if (!clipped.clip(a, b, c, box)) return false;
    out = clipped.bounds(box);
    return true;
}

bool triangle_overlaps_box(Vec3d a, Vec3d b, Vec3d c, const Aabbd& box) noexcept
{
    const Vec3d center{(box.lower.x + box.upper.x) * 0.5, (box.lower.y + box.upper.y) * 0.5,
                       (box.lower.z + box.upper.z) * 0.5};
    const Vec3d half{(box.upper.x - box.lower.x) * 0.5, (box.upper.y - box.lower.y) * 0.5,
                     (box.upper.z - box.lower.z) * 0.5};
    const std::array<Vec3d, 3> v{Vec3d{a.x - center.x, a.y - center.y, a.z - center.z},
                                 Vec3d{b.x - center.x, b.y - center.y, b.z - center.z},
                                 Vec3d{c.x - center.x, c.y - center.y, c.z - center.z}};
    // Projections of the triangle and the box on `axis`: separated if the intervals are
    // disjoint. A zero axis (parallel edges, degenerate triangle) separates nothing.
    auto separated = [&](const Vec3d& axis) {
        double pmin = std::numeric_limits<double>::infinity();
        double pmax = -pmin;
        for (const Vec3d& p : v) {
            const double d = p.x * axis.x + p.y * axis.y + p.z * axis.z;
            pmin = std::min(pmin, d);
            pmax = std::max(pmax, d);
        }
        const double r =
            half.x * std::abs(axis.x) + half.y * std::abs(axis.y) + half.z * std::abs(axis.z);
        return pmin > r || pmax < -r;
    };
    // 1. The box's face normals (the bounding boxes must overlap).
    for (int k = 0; k < 3; ++k) {
        Vec3d axis{0, 0, 0};
        axis[k] = 1.0;
        if (separated(axis)) return false;
    }
    const std::array<Vec3d, 3> e{Vec3d{v[1].x - v[0].x, v[1].y - v[0].y, v[1].z - v[0].z},
                                 Vec3d{v[2].x - v[1].x, v[2].y - v[1].y, v[2].z - v[1].z},
                                 Vec3d{v[0].x - v[2].x, v[0].y - v[2].y, v[0].z - v[2].z}};
    // 2. The triangle's normal.
    const Vec3d n{e[0].y * e[1].z - e[0].z * e[1].y, e[0].z * e[1].x - e[0].x * e[1].z,
                  e[0].x * e[1].y - e[0].y * e[1].x};
    if (separated(n)) return false;
    // 3. The nine cross products of triangle edges and box axes.
    for (const Vec3d& edge : e) {
        if (separated(Vec3d{0.0, -edge.z, edge.y})) return false;  // x cross edge
        if (separated(Vec3d{edge.z, 0.0, -edge.x})) return false;  // y cross edge
        if (separated(Vec3d{-edge.y, edge.x, 0.0})) return false;  // z cross edge
    }
    return true;
}

}  // namespace sg
