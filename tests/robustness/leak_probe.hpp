#pragma once

// The leak probe of rows 1 and 2 (docs/ROBUSTNESS.md): a closed UV sphere, its grid, and rays
// from inside it, which must all hit it. Header-only (see robustness_support.hpp).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "robustness_support.hpp"
#include "splitgrid/traverse.hpp"
#include "support/oracle.hpp"
#include "support/random_scene.hpp"

namespace sg::test {

/// Rays that escaped a closed mesh.
struct LeakCount {
    std::size_t rays = 0;
    std::size_t closest_misses = 0;  ///< intersect() found nothing
    std::size_t any_hit_misses = 0;  ///< occluded() said false
    std::string first_leak;          ///< the first escaping ray, for the failure message

    [[nodiscard]] std::size_t leaks() const { return std::max(closest_misses, any_hit_misses); }
    [[nodiscard]] double rate() const
    {
        return rays == 0 ? 0.0 : static_cast<double>(leaks()) / static_cast<double>(rays);
    }
    LeakCount& operator+=(const LeakCount& o)
    {
        rays += o.rays;
        closest_misses += o.closest_misses;
        any_hit_misses += o.any_hit_misses;
        if (first_leak.empty()) first_leak = o.first_leak;
        return *this;
    }
};

/// Units in the last place of x: the spacing of the floats at |x|.
inline double ulp_of(float x)
{
    const float a = std::fabs(x);
    return double(std::nextafter(a, INFINITY)) - double(a);
}

/// The smallest extent, in ulps of its own coordinates, of any triangle of `mesh`: a
/// triangle's extent is the largest of its bounding box's three extents, measured in ulps of
/// the largest coordinate magnitude of its corners. 0 when a triangle has collapsed to a point.
inline double smallest_span_in_ulps(const MeshView& mesh)
{
    double smallest = INFINITY;
    for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
        Aabb box;
        float magnitude = 0.0f;
        for (int c = 0; c < 3; ++c) {
            const Vec3f v = mesh.vertex(t, c);
            box.extend(v);
            magnitude = std::max({magnitude, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
        }
        double extent = 0.0;
        for (int k = 0; k < 3; ++k)
            extent = std::max(extent, double(box.upper[k]) - double(box.lower[k]));
        smallest = std::min(smallest, extent / ulp_of(magnitude));
    }
    return smallest;
}

/// A closed UV sphere (test::uv_sphere: shared vertices, fans at the poles) and its grid.
class LeakScene {
public:
    LeakScene(Vec3f center, float radius, std::uint32_t rings, std::uint32_t segments,
              const BuildConfig& config = {})
        : center_(center), radius_(radius), mesh(uv_sphere(center, radius, rings, segments)),
          grid(build_checked(mesh, config))
    {
    }

    /// Random rays from random points inside the sphere, in random directions.
    [[nodiscard]] std::vector<Ray> random_rays(std::uint32_t seed, std::size_t count) const
    {
        std::mt19937 rng(seed);
        std::vector<Ray> rays(count);
        for (Ray& r : rays) {
            r.origin = interior_point(rng);
            r.direction = interior_point(rng) - center_;
            if (r.direction == Vec3f{}) r.direction = {1.0f, 0.0f, 0.0f};
        }
        return rays;
    }

    /// Rays from random interior points whose lines pass exactly through a random vertex.
    [[nodiscard]] std::vector<Ray> rays_at_vertices(std::uint32_t seed, std::size_t count) const
    {
        std::mt19937 rng(seed);
        std::uniform_int_distribution<std::size_t> pick(0, mesh.vertices.size() - 1);
        return aimed_rays(rng, count, [&] { return mesh.vertices[pick(rng)]; });
    }

    /// Rays from random interior points whose lines pass exactly through the float nearest to
    /// the midpoint of a random edge.
    [[nodiscard]] std::vector<Ray> rays_at_edge_midpoints(std::uint32_t seed,
                                                          std::size_t count) const
    {
        std::mt19937 rng(seed);
        std::uniform_int_distribution<std::size_t> pick(0, mesh.triangles.size() - 1);
        std::uniform_int_distribution<int> corner(0, 2);
        return aimed_rays(rng, count, [&] {
            const auto t = static_cast<std::uint32_t>(pick(rng));
            const int c = corner(rng);
            const Vec3f a = mesh.view().vertex(t, c);
            const Vec3f b = mesh.view().vertex(t, (c + 1) % 3);
            Vec3f m;
            for (int k = 0; k < 3; ++k)
                m[k] = static_cast<float>((double(a[k]) + double(b[k])) / 2.0);
            return m;
        });
    }

    /// Runs intersect() and occluded() on every ray (in parallel) and counts those that miss.
    [[nodiscard]] LeakCount count_leaks(const std::vector<Ray>& rays) const
    {
        LeakCount count;
        count.rays = rays.size();
        const MeshView view = mesh.view();
        count.closest_misses =
            parallel_count(rays.size(), [&](std::size_t i) {
                return !intersect(grid, view, rays[i]).is_hit();
            });
        count.any_hit_misses = parallel_count(
            rays.size(), [&](std::size_t i) { return !occluded(grid, view, rays[i]); });
        for (const Ray& r : rays) {
            if (intersect(grid, view, r).is_hit() && occluded(grid, view, r)) continue;
            char text[256];
            std::snprintf(text, sizeof text, "first escaping ray: o=(%.9g %.9g %.9g) "
                          "d=(%.9g %.9g %.9g)", double(r.origin.x), double(r.origin.y),
                          double(r.origin.z), double(r.direction.x), double(r.direction.y),
                          double(r.direction.z));
            count.first_leak = text;
            break;
        }
        return count;
    }

    Vec3f center_;
    float radius_;
    Mesh mesh;
    SplitGrid grid;

private:
    // Uniform in the ball of 0.9 times the radius: well inside the polyhedron, whose faces
    // come within radius * (1 - cos(pi / rings)) of the sphere.
    [[nodiscard]] Vec3f interior_point(std::mt19937& rng) const
    {
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (;;) {
            const double x = u(rng), y = u(rng), z = u(rng);
            if (x * x + y * y + z * z > 1.0) continue;
            const double s = 0.9 * radius_;
            return {static_cast<float>(center_.x + s * x), static_cast<float>(center_.y + s * y),
                    static_cast<float>(center_.z + s * z)};
        }
    }

    [[nodiscard]] bool is_inside(Vec3f p) const
    {
        const double dx = double(p.x) - center_.x, dy = double(p.y) - center_.y,
                     dz = double(p.z) - center_.z;
        return dx * dx + dy * dy + dz * dz <= 0.95 * 0.95 * double(radius_) * radius_;
    }

    template <class Target>
    std::vector<Ray> aimed_rays(std::mt19937& rng, std::size_t count, const Target& target) const
    {
        std::vector<Ray> rays;
        rays.reserve(count);
        // On a sphere collapsed by rounding (row 2's smallest scales) most attempts fail: give
        // up after a while and return fewer rays.
        for (std::size_t targets = 0; rays.size() < count && targets < 4 * count; ++targets) {
            const Vec3f goal = target();
            // ray_through may move the origin onto the target's plane on an axis: keep only
            // origins that are still inside.
            for (int attempt = 0; attempt < 16; ++attempt) {
                const std::optional<Ray> r = ray_through(interior_point(rng), goal);
                if (!r || !is_inside(r->origin)) continue;
                rays.push_back(*r);
                break;
            }
        }
        return rays;
    }
};

}  // namespace sg::test
