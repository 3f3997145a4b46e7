#pragma once

#include <cmath>

#include "splitgrid/ray.hpp"
#include "splitgrid/ray_triangle.hpp"
#include "splitgrid/vec3.hpp"

/// The two choices every traversal in splitgrid is templated on, the Split Grid's and the
/// comparison structures' alike: which ray/triangle test it runs, and whether it widens its
/// ray intervals against rounding. The defaults are the exact ones; the others exist so that
/// sg-bench can chart what exactness costs and what dropping it loses.

namespace sg {

/// Whether a traversal widens its ray intervals to absorb the rounding of plane crossings
/// (Conservative, the default and the only mode the tests hold to zero misses), or uses the
/// computed crossings as they are (None: a little faster, and it can lose hits where a ray
/// passes within rounding error of a cell edge; sg-bench charts the difference).
/// Build-time padding (boundary_pad) is not affected.
enum class Padding { Conservative, None };

/// The triangle test of every query unless the caller picks another one: the watertight test
/// of ray_triangle.hpp, the same one intersect_brute_force uses, so that a structure finds
/// exactly the hits brute force finds.
///
/// A triangle-test policy is any class with
///   explicit Policy(const Ray& ray) noexcept;   // per-ray set-up; direction denormals flushed
///   bool operator()(Vec3f a, Vec3f b, Vec3f c, float t_min, float t_max,
///                   float& t, float& u, float& v) const noexcept;
/// which reports a hit with t in [t_min, t_max], barycentrics u (of b) and v (of c).
class WatertightTest {
public:
    explicit WatertightTest(const Ray& ray) noexcept : ray_(ray) {}
    [[nodiscard]] bool operator()(Vec3f a, Vec3f b, Vec3f c, float t_min, float t_max, float& t,
                                  float& u, float& v) const noexcept
    {
        return intersect_triangle(ray_, a, b, c, t_min, t_max, t, u, v);
    }

private:
    WatertightRay ray_;
};

/// The test of Moeller and Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection"
/// (JGT 2(1), 1997), in single precision and without an epsilon: a few flops cheaper than the
/// watertight test and not watertight. Its barycentric tests are computed separately for
/// each triangle, so a ray through a shared edge can fail both triangles' tests, and rays
/// nearly parallel to a triangle lose precision in the determinant. For sg-bench's
/// speed-against-accuracy chart only; never the default.
class MollerTrumboreTest {
public:
    explicit MollerTrumboreTest(const Ray& ray) noexcept
        : origin_(ray.origin), direction_(ray.direction)
    {
    }
    [[nodiscard]] bool operator()(Vec3f a, Vec3f b, Vec3f c, float t_min, float t_max, float& t,
                                  float& u, float& v) const noexcept
    {
        const Vec3f e1 = b - a;
        const Vec3f e2 = c - a;
        const Vec3f p = cross(direction_, e2);
        const float det = dot(e1, p);
        if (det == 0.0f) return false;
        const float inv_det = 1.0f / det;
        const Vec3f s = origin_ - a;
        const float bu = dot(s, p) * inv_det;
        if (!(bu >= 0.0f && bu <= 1.0f)) return false;
        const Vec3f q = cross(s, e1);
        const float bv = dot(direction_, q) * inv_det;
        if (!(bv >= 0.0f && bu + bv <= 1.0f)) return false;
        const float th = dot(e2, q) * inv_det;
        if (!(th >= t_min && th <= t_max)) return false;
        t = th;
        u = bu;
        v = bv;
        return true;
    }

private:
    Vec3f origin_;
    Vec3f direction_;
};

}  // namespace sg
