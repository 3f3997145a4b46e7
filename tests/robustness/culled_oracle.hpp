#pragma once

// Brute force over all triangles, made affordable for 10^5 triangles and 10^6 rays: a ray is
// first tested against every triangle's bounding box (in double precision, the boxes padded
// by 2^-20 of their coordinates), and intersect_brute_force / occluded_brute_force then run on
// the triangles whose box it meets, in id order. A triangle whose box the ray misses cannot
// be hit, so the answers are exactly those of brute force over the whole mesh (the tie rule
// included: the candidates keep their id order). `CulledOracle::self_check` confirms that on
// a sample against the plain brute force. Nothing here uses the Split Grid.

#include <cmath>
#include <vector>

#include "robustness_support.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/traverse.hpp"
#include "support/oracle.hpp"

namespace sg::test {

class CulledOracle {
public:
    explicit CulledOracle(const MeshView& mesh) : mesh_(mesh)
    {
        const std::size_t n = mesh.triangle_count();
        for (auto* v : {&lo_x_, &lo_y_, &lo_z_, &hi_x_, &hi_y_, &hi_z_}) v->resize(n);
        for (std::uint32_t t = 0; t < n; ++t) {
            Aabb box;
            for (int c = 0; c < 3; ++c) box.extend(mesh.vertex(t, c));
            std::array<double, 3> lo{}, hi{};
            for (int k = 0; k < 3; ++k) {
                const double magnitude =
                    std::max(std::fabs(double(box.lower[k])), std::fabs(double(box.upper[k])));
                const double pad = magnitude * 0x1p-20 + 0x1p-100;
                lo[static_cast<std::size_t>(k)] = double(box.lower[k]) - pad;
                hi[static_cast<std::size_t>(k)] = double(box.upper[k]) + pad;
            }
            lo_x_[t] = lo[0], lo_y_[t] = lo[1], lo_z_[t] = lo[2];
            hi_x_[t] = hi[0], hi_y_[t] = hi[1], hi_z_[t] = hi[2];
        }
    }

    [[nodiscard]] Hit intersect(const Ray& ray) const
    {
        std::vector<std::uint32_t> ids;
        const std::vector<Triangle> tris = candidates(ray, ids);
        return closest_among(ray, tris, ids);
    }
    [[nodiscard]] bool occluded(const Ray& ray) const
    {
        std::vector<std::uint32_t> ids;
        const std::vector<Triangle> tris = candidates(ray, ids);
        return occluded_brute_force(MeshView{mesh_.vertices, tris}, ray);
    }

    /// Rays of `rays` on which this oracle and intersect_brute_force disagree.
    [[nodiscard]] std::size_t self_check(const std::vector<Ray>& rays) const
    {
        std::size_t wrong = 0;
        for (const Ray& r : rays) {
            const Hit a = intersect(r), b = intersect_brute_force(mesh_, r);
            if (a.triangle != b.triangle || !same_closest_hit(b, a) ||
                occluded(r) != occluded_brute_force(mesh_, r))
                ++wrong;
        }
        return wrong;
    }

    /// The grid's intersect() and occluded() against this oracle on every ray, in parallel;
    /// counted as compare_with_brute_force counts.
    [[nodiscard]] OracleReport compare(const SplitGrid& grid, const std::vector<Ray>& rays) const
    {
        return compare_in_blocks(rays, [&](const std::vector<Ray>& part) {
            // Both reference answers from one pass over the boxes: the closest-hit callback
            // computes the any-hit answer of the same ray too, which the next callback returns.
            const Ray* answered = nullptr;
            bool any_answer = false;
            return compare_with_oracle(
                part, [&](const Ray& r) { return sg::intersect(grid, mesh_, r); },
                [&](const Ray& r) { return sg::occluded(grid, mesh_, r); },
                [&](const Ray& r) {
                    std::vector<std::uint32_t> ids;
                    const std::vector<Triangle> tris = candidates(r, ids);
                    answered = &r;
                    any_answer = occluded_brute_force(MeshView{mesh_.vertices, tris}, r);
                    return closest_among(r, tris, ids);
                },
                [&](const Ray& r) { return &r == answered ? any_answer : occluded(r); });
        });
    }

private:
    [[nodiscard]] Hit closest_among(const Ray& ray, const std::vector<Triangle>& tris,
                                    const std::vector<std::uint32_t>& ids) const
    {
        Hit hit = intersect_brute_force(MeshView{mesh_.vertices, tris}, ray);
        if (hit.is_hit()) hit.triangle = ids[hit.triangle];
        return hit;
    }

    // The triangles whose padded box the ray's segment [t_min, t_max] meets, in id order.
    std::vector<Triangle> candidates(const Ray& ray, std::vector<std::uint32_t>& ids) const
    {
        std::vector<Triangle> out;
        if (!is_valid(ray)) return out;
        const double ox = ray.origin.x, oy = ray.origin.y, oz = ray.origin.z;
        // Zero (or denormal, which every query treats as zero) components: the segment stays
        // in the plane, so the box test on that axis is containment of the origin.
        auto inverse = [](float d) {
            return std::fabs(d) < std::numeric_limits<float>::min() ? 0.0 : 1.0 / double(d);
        };
        const double ix = inverse(ray.direction.x), iy = inverse(ray.direction.y),
                     iz = inverse(ray.direction.z);
        const double t_lo = ray.t_min, t_hi = ray.t_max;
        const std::size_t n = lo_x_.size();
        hits_.resize(n);
        double* const mask = hits_.data();  // not the thread_local: it stops vectorising
        const double* const lx = lo_x_.data();
        const double* const ly = lo_y_.data();
        const double* const lz = lo_z_.data();
        const double* const hx = hi_x_.data();
        const double* const hy = hi_y_.data();
        const double* const hz = hi_z_.data();
        if (ix != 0.0 && iy != 0.0 && iz != 0.0) {
            // The common case without branches, so that the compiler can vectorise it.
            for (std::size_t t = 0; t < n; ++t) {
                const double ax = (lx[t] - ox) * ix, bx = (hx[t] - ox) * ix;
                const double ay = (ly[t] - oy) * iy, by = (hy[t] - oy) * iy;
                const double az = (lz[t] - oz) * iz, bz = (hz[t] - oz) * iz;
                const double t0 = std::max(std::max(std::min(ax, bx), std::min(ay, by)),
                                           std::max(std::min(az, bz), t_lo));
                const double t1 = std::min(std::min(std::max(ax, bx), std::max(ay, by)),
                                           std::min(std::max(az, bz), t_hi));
                mask[t] = t0 <= t1 ? 1.0 : 0.0;
            }
        } else {
            for (std::size_t t = 0; t < n; ++t) {
                double t0 = t_lo, t1 = t_hi;
                const bool in = slab(ox, ix, lx[t], hx[t], t0, t1) &&
                                slab(oy, iy, ly[t], hy[t], t0, t1) &&
                                slab(oz, iz, lz[t], hz[t], t0, t1);
                mask[t] = in ? 1.0 : 0.0;
            }
        }
        for (std::size_t t = 0; t < n; ++t) {
            if (mask[t] == 0.0) continue;
            out.push_back(mesh_.triangles[t]);
            ids.push_back(static_cast<std::uint32_t>(t));
        }
        return out;
    }

    static bool slab(double o, double inv, double lo, double hi, double& t0, double& t1)
    {
        if (inv == 0.0) return o >= lo && o <= hi;
        double a = (lo - o) * inv, b = (hi - o) * inv;
        if (a > b) std::swap(a, b);
        // Double rounding here is 2^-29 of a float ulp: far inside the 2^-20 box pad.
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
        return t0 <= t1;
    }

    MeshView mesh_;
    static thread_local inline std::vector<double> hits_;  // 1 or 0 per box; double vectorises
    std::vector<double> lo_x_, lo_y_, lo_z_, hi_x_, hi_y_, hi_z_;
};

}  // namespace sg::test
