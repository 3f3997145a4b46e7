#include "splitgrid/occupancy.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "splitgrid/baselines/bvh.hpp"
#include "splitgrid/baselines/kd_tree.hpp"
#include "splitgrid/baselines/uniform_grid.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/structure_queries.hpp"
#include "structure_box.hpp"

namespace sg {
namespace {

bool inside_closed_box(Vec3f p, const Aabb& box) noexcept
{
    for (int k = 0; k < 3; ++k)
        if (!(p[k] >= box.lower[k] && p[k] <= box.upper[k])) return false;
    return true;
}

/// Points per batch of count queries: the rays of a batch live on the stack.
constexpr std::size_t batch_points = 64;

}  // namespace

Ray occupancy_ray(Vec3f point, const Aabb& box, std::uint32_t sample,
                  std::uint32_t nsamples) noexcept
{
    Ray ray;
    ray.origin = point;
    if (sample == 0) {
        int axis = 0;
        float sign = 1.0f;
        float shortest = std::numeric_limits<float>::infinity();
        for (int k = 0; k < 3; ++k) {
            const float down = point[k] - box.lower[k], up = box.upper[k] - point[k];
            if (down < shortest) shortest = down, axis = k, sign = -1.0f;
            if (up < shortest) shortest = up, axis = k, sign = 1.0f;
        }
        // Tilted off the axis: a ray parallel to two axes is one that a BVH's box test cannot
        // narrow on those axes (it visits every box the axis' slab crosses).
        ray.direction[axis] = sign;
        ray.direction[(axis + 1) % 3] = 0x1p-5f;
        ray.direction[(axis + 2) % 3] = 0x1p-7f;
        return ray;
    }
    // Fibonacci lattice over the sphere: point k of n = nsamples - 1, z evenly spaced.
    const double n = static_cast<double>(nsamples - 1);
    const double k = static_cast<double>(sample - 1) + 0.5;
    const double z = 1.0 - 2.0 * k / n;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = k * std::numbers::pi * (3.0 - std::sqrt(5.0));
    ray.direction = Vec3f{static_cast<float>(r * std::cos(phi)),
                          static_cast<float>(r * std::sin(phi)), static_cast<float>(z)};
    return ray;
}

template <class Structure>
void compute_occupancy(const Structure& structure, const MeshView& mesh,
                       std::span<const Vec3f> points, std::span<float> out,
                       std::uint32_t nsamples, TriangleTest test)
{
    if (nsamples == 0 || nsamples % 2 == 0)
        throw ConfigError("occupancy: nsamples = " + std::to_string(nsamples) +
                          " must be odd (a majority of the rays' votes decides)");
    const Aabb& box = detail::root_box(structure);
    std::array<Ray, batch_points> rays;
    std::array<std::int32_t, batch_points> counts;
    std::array<std::size_t, batch_points> point_of;
    std::array<std::uint32_t, batch_points> votes;
    for (std::size_t first = 0; first < points.size(); first += batch_points) {
        const std::size_t last = std::min(points.size(), first + batch_points);
        for (std::size_t i = first; i < last; ++i) {
            const Vec3f p = points[i];
            out[i] = is_finite(p) ? 0.0f : std::numeric_limits<float>::quiet_NaN();
        }
        std::fill(votes.begin(), votes.end(), 0u);
        for (std::uint32_t sample = 0; sample < nsamples; ++sample) {
            std::size_t n = 0;
            for (std::size_t i = first; i < last; ++i) {
                const Vec3f p = points[i];
                if (!is_finite(p) || !inside_closed_box(p, box)) continue;
                rays[n] = occupancy_ray(p, box, sample, nsamples);
                point_of[n] = i;
                ++n;
            }
            if (n == 0) break;
            detail::count_hits(structure, mesh, std::span<const Ray>(rays.data(), n),
                               std::span<std::int32_t>(counts.data(), n), test);
            for (std::size_t j = 0; j < n; ++j)
                votes[point_of[j] - first] += static_cast<std::uint32_t>(counts[j] & 1);
        }
        for (std::size_t i = first; i < last; ++i) {
            const Vec3f p = points[i];
            if (is_finite(p) && inside_closed_box(p, box))
                out[i] = 2 * votes[i - first] > nsamples ? 1.0f : 0.0f;
        }
    }
}

template void compute_occupancy(const SplitGrid&, const MeshView&, std::span<const Vec3f>,
                                std::span<float>, std::uint32_t, TriangleTest);
template void compute_occupancy(const Bvh&, const MeshView&, std::span<const Vec3f>,
                                std::span<float>, std::uint32_t, TriangleTest);
template void compute_occupancy(const KdTree&, const MeshView&, std::span<const Vec3f>,
                                std::span<float>, std::uint32_t, TriangleTest);
template void compute_occupancy(const UniformGrid&, const MeshView&, std::span<const Vec3f>,
                                std::span<float>, std::uint32_t, TriangleTest);

}  // namespace sg
