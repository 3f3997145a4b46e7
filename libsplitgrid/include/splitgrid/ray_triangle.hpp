#pragma once

#include <cmath>
#include <cstdint>
#include <utility>

#include "splitgrid/ray.hpp"
#include "splitgrid/vec3.hpp"

namespace sg {

/// Per-ray data of the watertight ray/triangle test of Woop, Benthin and Wald,
/// "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013. The ray is sheared so that it
/// becomes the +z axis; a hit is decided by the signs of three 2D edge functions, which two
/// triangles sharing an edge compute from the same inputs, so no ray slips between them.
struct WatertightRay {
    Vec3f origin;
    int kx = 0, ky = 1, kz = 2;  ///< axis permutation: kz is the dominant direction axis
    float sx = 0.0f, sy = 0.0f, sz = 1.0f;  ///< shear constants

    WatertightRay() = default;
    /// Precondition: direction is not the zero vector.
    explicit WatertightRay(const Ray& ray) noexcept : origin(ray.origin)
    {
        const Vec3f d = ray.direction;
        const float ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
        kz = (ax > ay) ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
        kx = (kz + 1) % 3;
        ky = (kx + 1) % 3;
        if (d[kz] < 0.0f) std::swap(kx, ky);  // keep the winding (and so the signs) consistent
        sx = d[kx] / d[kz];
        sy = d[ky] / d[kz];
        sz = 1.0f / d[kz];
    }
};

namespace detail {

/// A triangle's corners moved to the ray's origin (A, B, C) and sheared along the ray (X and Y
/// of each corner in the frame where the ray runs along +z), and the float edge functions U, V
/// and W of the edges b -> c, c -> a and a -> b (qx * py - qy * px for an edge from P to Q).
/// Each corner's values come from that corner alone, so every triangle holding it computes
/// the same ones, and the two triangles of an edge the same edge function up to its sign.
struct ShearedTriangle {
    Vec3f A, B, C;
    float Ax, Ay, Bx, By, Cx, Cy;
    float U, V, W;
    ShearedTriangle(const WatertightRay& r, Vec3f a, Vec3f b, Vec3f c) noexcept
        : A(a - r.origin), B(b - r.origin), C(c - r.origin),
          Ax(A[r.kx] - r.sx * A[r.kz]), Ay(A[r.ky] - r.sy * A[r.kz]),
          Bx(B[r.kx] - r.sx * B[r.kz]), By(B[r.ky] - r.sy * B[r.kz]),
          Cx(C[r.kx] - r.sx * C[r.kz]), Cy(C[r.ky] - r.sy * C[r.kz]), U(Cx * By - Cy * Bx),
          V(Ax * Cy - Ay * Cx), W(Bx * Ay - By * Ax)
    {
    }
};

/// True when the float edge function `e` may not have the sign of the exact one: it is zero
/// (the two rounded products came out equal; the exact difference may be zero or of either
/// sign) or NaN (the products overflowed). A non-zero float edge function has the exact sign:
/// rounding is monotone, so qx * py > qy * px gives fl(qx * py) >= fl(qy * px), whose
/// difference rounds to a value >= 0 (docs/SPLIT_GRID.md, "Exact edge functions").
[[nodiscard]] inline bool edge_sign_is_uncertain(float e) noexcept
{
    return !(e < 0.0f || e > 0.0f);
}

/// The sign of the edge function qx * py - qy * px of the 2D edge from (px, py) to (qx, qy),
/// evaluated exactly (products of floats are exact in double, and the one rounding of their
/// difference keeps its sign), with a zero decided by symbolic perturbation: the sign it takes
/// when the ray moves by (e, e^2) for an infinitesimal e > 0, which is that of
/// e (qy - py) + e^2 (px - qx). It depends on the edge alone and flips with its direction, so
/// two triangles sharing an edge decide it alike whatever their winding. 0 only for an edge
/// whose ends coincide in the ray's frame (an edge along the ray), which bounds no area.
[[nodiscard]] inline int perturbed_edge_sign(float px, float py, float qx, float qy,
                                             double& exact) noexcept
{
    exact = static_cast<double>(qx) * py - static_cast<double>(qy) * px;
    if (exact != 0.0) return exact > 0.0 ? 1 : -1;
    if (qy != py) return qy > py ? 1 : -1;
    if (px != qx) return px > qx ? 1 : -1;
    return 0;
}

/// The part of the watertight test after the edge functions U, V and W (all of one sign, or
/// zero): the determinant, the distance in [t_min, t_max] and the barycentrics. `A`, `B` and
/// `C` are the corners moved to the ray's origin.
[[nodiscard]] inline bool hit_distance(const WatertightRay& r, Vec3f A, Vec3f B, Vec3f C,
                                       float U, float V, float W, float t_min, float t_max,
                                       float& t_out, float& u_out, float& v_out) noexcept
{
    const float det = U + V + W;
    if (det == 0.0f) return false;
    const float Az = r.sz * A[r.kz];
    const float Bz = r.sz * B[r.kz];
    const float Cz = r.sz * C[r.kz];
    const float T = U * Az + V * Bz + W * Cz;
    if (!(std::isfinite(T))) return false;
    // Early out before the division: t = T / det far outside [t_min, t_max]. The products
    // t_min * det and t_max * det round differently from the t computed below, so they get a
    // margin of 2^-20 (the rounding of both sides stays below 2^-21) and FLT_MIN (underflow):
    // the decision itself is taken on the returned t only, or a hit would be refused once the
    // closest hit so far lies a float or two further, and the closest hit would depend on
    // the order in which triangles are tested.
    auto widened = [](float x) { return std::abs(x) * 0x1p-20f + 0x1p-126f; };
    const float lo = t_min * det, hi = t_max * det;
    if (det > 0.0f) {
        if (T < lo - widened(lo) || T > hi + widened(hi)) return false;
    } else {
        if (T > lo + widened(lo) || T < hi - widened(hi)) return false;
    }
    const float inv_det = 1.0f / det;
    t_out = T * inv_det;
    if (!(t_out >= t_min && t_out <= t_max)) return false;
    u_out = V * inv_det;
    v_out = W * inv_det;
    return true;
}

}  // namespace detail

/// Tests one triangle (corners a, b, c). On a hit with t in [t_min, t_max] it writes t and the
/// barycentrics u (weight of b) and v (weight of c) and returns true. No back-face culling.
///
/// The signs of the three edge functions are exact, and a zero one (the ray through an edge
/// or a vertex) is decided by symbolic perturbation (detail::perturbed_edge_sign): the test
/// answers what it would for the ray moved by an infinitesimal amount, the same amount for
/// every triangle. So a ray through an edge shared by two triangles hits exactly one of them
/// where it crosses the surface (none or both where it grazes it, as the moved ray misses or
/// pierces the fold), a ray through a vertex hits one triangle of the fan around it, and a
/// triangle seen edge-on is never hit: the hits along a ray are those of a slightly moved ray
/// (docs/SPLIT_GRID.md, "Exact edge functions").
/// Cost: about 30 flops; a double-precision path runs only where an edge function is zero in
/// float (the ray passes through an edge or a vertex, or within rounding of one).
[[nodiscard]] inline bool intersect_triangle(const WatertightRay& r, Vec3f a, Vec3f b, Vec3f c,
                                             float t_min, float t_max, float& t_out, float& u_out,
                                             float& v_out) noexcept
{
    const detail::ShearedTriangle s(r, a, b, c);
    float U = s.U, V = s.V, W = s.W;
    if (!detail::edge_sign_is_uncertain(U) && !detail::edge_sign_is_uncertain(V) &&
        !detail::edge_sign_is_uncertain(W)) {
        if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f))
            return false;
    } else {
        double Ud, Vd, Wd;
        const int su = detail::perturbed_edge_sign(s.Bx, s.By, s.Cx, s.Cy, Ud);
        const int sv = detail::perturbed_edge_sign(s.Cx, s.Cy, s.Ax, s.Ay, Vd);
        const int sw = detail::perturbed_edge_sign(s.Ax, s.Ay, s.Bx, s.By, Wd);
        if (su == 0 || su != sv || su != sw) return false;
        U = static_cast<float>(Ud);
        V = static_cast<float>(Vd);
        W = static_cast<float>(Wd);
    }
    return detail::hit_distance(r, s.A, s.B, s.C, U, V, W, t_min, t_max, t_out, u_out, v_out);
}

/// intersect_triangle before symbolic perturbation (TriangleTest::watertight_no_tie_break):
/// the float edge functions, recomputed in double only where one is exactly zero in float, and
/// a zero accepted on either side. For sg-bench's comparison of inside tests only. Same
/// contract as intersect_triangle.
[[nodiscard]] inline bool intersect_triangle_no_tie_break(const WatertightRay& r, Vec3f a,
                                                          Vec3f b, Vec3f c, float t_min,
                                                          float t_max, float& t_out,
                                                          float& u_out, float& v_out) noexcept
{
    const detail::ShearedTriangle s(r, a, b, c);
    float U = s.U, V = s.V, W = s.W;
    if (U == 0.0f || V == 0.0f || W == 0.0f) {
        double exact;
        (void)detail::perturbed_edge_sign(s.Bx, s.By, s.Cx, s.Cy, exact);
        U = static_cast<float>(exact);
        (void)detail::perturbed_edge_sign(s.Cx, s.Cy, s.Ax, s.Ay, exact);
        V = static_cast<float>(exact);
        (void)detail::perturbed_edge_sign(s.Ax, s.Ay, s.Bx, s.By, exact);
        W = static_cast<float>(exact);
    }
    if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;
    return detail::hit_distance(r, s.A, s.B, s.C, U, V, W, t_min, t_max, t_out, u_out, v_out);
}

/// The test of Moeller and Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection"
/// (JGT 2(1), 1997), in single precision and without an epsilon: a few flops cheaper than the
/// watertight test and not watertight. Its barycentric tests are computed separately for each
/// triangle, so a ray through a shared edge can fail both triangles' tests, and rays nearly
/// parallel to a triangle lose precision in the determinant. For sg-bench's
/// speed-against-accuracy chart only (TriangleTest::moller_trumbore); never the default.
/// Same contract as intersect_triangle.
[[nodiscard]] inline bool intersect_triangle_moller_trumbore(Vec3f origin, Vec3f direction,
                                                             Vec3f a, Vec3f b, Vec3f c,
                                                             float t_min, float t_max,
                                                             float& t_out, float& u_out,
                                                             float& v_out) noexcept
{
    const Vec3f e1 = b - a;
    const Vec3f e2 = c - a;
    const Vec3f p = cross(direction, e2);
    const float det = dot(e1, p);
    if (det == 0.0f) return false;
    const float inv_det = 1.0f / det;
    const Vec3f s = origin - a;
    const float bu = dot(s, p) * inv_det;
    if (!(bu >= 0.0f && bu <= 1.0f)) return false;
    const Vec3f q = cross(s, e1);
    const float bv = dot(direction, q) * inv_det;
    if (!(bv >= 0.0f && bu + bv <= 1.0f)) return false;
    const float t = dot(e2, q) * inv_det;
    if (!(t >= t_min && t <= t_max)) return false;
    t_out = t;
    u_out = bu;
    v_out = bv;
    return true;
}

}  // namespace sg
