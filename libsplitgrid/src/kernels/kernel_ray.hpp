#pragma once

// Traversal kernels, part 1: the ray as every structure's traversal sees it. Compiled once per
// instruction set (kernels_isa.inc): everything here lives in sg::kernels::SG_KERNEL_ISA.

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

/// Absolute rounding allowance of plane crossings, in units of (magnitude + |origin|) / |d|.
///
/// Every plane p a traversal crosses lies inside the structure's root box, so |p| <= M, the
/// box's largest coordinate magnitude. A crossing computed as (p - o) * (1 / d), or as
/// t(p0) + k * t(w) for the k-th boundary of a grid whose width w was rounded, differs from
/// the exact (p - o) / d by a few roundings of quantities no larger than (M + |o|) / |d|:
/// below 23 * 2^-24 * (M + |o|) / |d| (docs/SPLIT_GRID.md derives the bound). Widening every
/// entry down and every exit up by 2^-18 * (M + |o|) / |d| (2.8 times that) makes the visited
/// cells and boxes a superset of those the exact ray crosses, whatever the ray's distance to
/// the plane, at the cost of one add per crossing (no multiply, no sign test).
inline constexpr float crossing_pad_unit = 0x1p-18f;

/// The ray of one query, prepared once: direction components below FLT_MIN flushed to zero
/// (ray.hpp), reciprocals, per-axis crossing allowances and the watertight test's shear.
struct KernelRay {
    float origin[3];
    float direction[3];
    /// 1 / direction[k]; 0 on a parallel axis, so that (p - o) * inv is 0 there, never NaN.
    float inv[3];
    /// Absolute widening of crossings on axis k (crossing_pad_unit), 0 with Padding::none;
    /// +infinity on a parallel axis, so that a slab test with inv = 0 leaves the interval
    /// unconstrained on that axis (conservative; structures that need the origin's cell on a
    /// parallel axis look it up by position).
    float pad[3];
    bool parallel[3];
    bool negative[3];  ///< direction[k] < 0
    /// True when a crossing of a plane in the root box may come near FLT_MAX (a direction
    /// component near FLT_MIN, or an origin near +-FLT_MAX): (M + |o|) / |d| >= 2^124 on some
    /// axis. Below that bound t(p) and t(p0) + k t(w) stay finite for every plane p of the box;
    /// traversals that extrapolate crossings take a conservative path for such rays.
    bool extreme = false;
    float t_min;
    float t_max;
    WatertightRay shear;  ///< per-ray data of the watertight triangle test
    Vec3f origin_vec;
    Vec3f direction_vec;  ///< flushed direction, for the Moeller-Trumbore test

    /// `magnitude`: the largest coordinate magnitude of the structure's root box.
    KernelRay(const Ray& ray, float magnitude, Padding padding) noexcept
        : t_min(ray.t_min), t_max(ray.t_max), origin_vec(ray.origin)
    {
        for (int k = 0; k < 3; ++k) {
            float d = ray.direction[k];
            if (std::abs(d) < std::numeric_limits<float>::min()) d = 0.0f;
            origin[k] = ray.origin[k];
            direction[k] = d;
            parallel[k] = d == 0.0f;
            negative[k] = d < 0.0f;
            inv[k] = parallel[k] ? 0.0f : 1.0f / d;
            if (!parallel[k] && (static_cast<double>(magnitude) + std::abs(static_cast<double>(origin[k]))) *
                                        std::abs(static_cast<double>(inv[k])) >= 0x1p124)
                extreme = true;
            pad[k] = parallel[k] ? std::numeric_limits<float>::infinity()
                     : padding == Padding::conservative
                         ? crossing_pad_unit * (magnitude + std::abs(origin[k])) * std::abs(inv[k])
                         : 0.0f;
        }
        direction_vec = Vec3f{direction[0], direction[1], direction[2]};
        shear = WatertightRay(Ray{ray.origin, direction_vec, ray.t_min, ray.t_max});
    }

    /// Ray parameter of the plane `coord` on a non-parallel `axis`.
    [[nodiscard]] float crossing(int axis, float coord) const noexcept
    {
        return (coord - origin[axis]) * inv[axis];
    }

    /// Narrows [t0, t1] to the ray inside the slab [lo, hi] on `axis`, widened by pad[axis];
    /// false when nothing is left. A parallel axis constrains nothing (pad is infinite).
    [[nodiscard]] bool clip_slab(int axis, float lo, float hi, float& t0, float& t1) const noexcept
    {
        const float a = crossing(axis, lo);
        const float b = crossing(axis, hi);
        t0 = std::max(t0, std::min(a, b) - pad[axis]);
        t1 = std::min(t1, std::max(a, b) + pad[axis]);
        return t0 <= t1;
    }

    /// Narrows [t0, t1] to the closed `box` (clip_slab on each axis), then, since the pad lets
    /// parallel axes through, checks the origin against the box on those axes exactly.
    [[nodiscard]] bool clip_box(const Aabb& box, float& t0, float& t1) const noexcept
    {
        for (int k = 0; k < 3; ++k) {
            if (parallel[k] && !(origin[k] >= box.lower[k] && origin[k] <= box.upper[k]))
                return false;
            (void)clip_slab(k, box.lower[k], box.upper[k], t0, t1);
        }
        return t0 <= t1;
    }
};

/// The M of crossing_pad_unit.
using detail::box_magnitude;

}  // namespace sg::kernels::SG_KERNEL_ISA
