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

/// Tests one triangle (corners a, b, c). On a hit with t in [t_min, t_max] it writes t and the
/// barycentrics u (weight of b) and v (weight of c) and returns true. No back-face culling.
/// Cost: about 30 flops; a double-precision fallback runs only when an edge function is
/// exactly zero (the ray passes through an edge or vertex).
[[nodiscard]] inline bool intersect_triangle(const WatertightRay& r, Vec3f a, Vec3f b, Vec3f c,
                                             float t_min, float t_max, float& t_out, float& u_out,
                                             float& v_out) noexcept
{
    const Vec3f A = a - r.origin;
    const Vec3f B = b - r.origin;
    const Vec3f C = c - r.origin;
    const float Ax = A[r.kx] - r.sx * A[r.kz];
    const float Ay = A[r.ky] - r.sy * A[r.kz];
    const float Bx = B[r.kx] - r.sx * B[r.kz];
    const float By = B[r.ky] - r.sy * B[r.kz];
    const float Cx = C[r.kx] - r.sx * C[r.kz];
    const float Cy = C[r.ky] - r.sy * C[r.kz];
    float U = Cx * By - Cy * Bx;
    float V = Ax * Cy - Ay * Cx;
    float W = Bx * Ay - By * Ax;
    if (U == 0.0f || V == 0.0f || W == 0.0f) {
        // An edge passes (in float) exactly through the ray: decide with exact-enough products.
        U = static_cast<float>(static_cast<double>(Cx) * By - static_cast<double>(Cy) * Bx);
        V = static_cast<float>(static_cast<double>(Ax) * Cy - static_cast<double>(Ay) * Cx);
        W = static_cast<float>(static_cast<double>(Bx) * Ay - static_cast<double>(By) * Ax);
    }
    if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;
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
