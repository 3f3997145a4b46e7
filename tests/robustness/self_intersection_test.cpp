// Row 9 of docs/ROBUSTNESS.md: self-intersection. Secondary rays spawned from hits with the
// offset rule of ray_offset.hpp (the hit point from its barycentrics, moved off the surface
// by 256 ulps of each coordinate along the normal, towards the side the new ray leaves on;
// 1/65536 of the unit normal for coordinates below 1/32) must never hit their source
// triangle again: directions all over the sphere, both sides of the surface, grazing ones
// included, on a closed sphere near the origin and far from it, a random soup and a real mesh.
// Then the price of the rule: the smallest gap between two parallel surfaces that a ray
// spawned from one still sees the other across, measured at several coordinate magnitudes
// and printed (a surface closer than that is skipped).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

#include "robustness_support.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "splitgrid/ray_offset.hpp"
#include "support/random_scene.hpp"

namespace sg::test {
namespace {

Vec3f random_unit(std::mt19937& rng)
{
    std::uniform_real_distribution<float> s(-1.0f, 1.0f);
    for (;;) {
        const Vec3f v{s(rng), s(rng), s(rng)};
        if (const float l = length(v); l > 0.05f && l <= 1.0f) return v * (1.0f / l);
    }
}

struct SelfHits {
    std::size_t secondary = 0;
    std::size_t self_hits = 0;
    std::size_t hits = 0;
    std::string first;
};

// Primary rays aimed at triangles; from each hit, `per_hit` secondary rays: random
// directions, and directions within 1e-3 and 1e-6 of the tangent plane on either side.
SelfHits spawn_from_hits(const Mesh& mesh, const Aabb& box, std::uint32_t seed,
                         std::size_t secondary_count)
{
    const SplitGrid grid = build_checked(mesh);
    const MeshView view = mesh.view();
    constexpr std::size_t per_hit = 8;
    const std::vector<Ray> primary = rays_at_triangles(seed, secondary_count / per_hit, box, view);
    std::vector<Ray> rays;
    std::vector<std::uint32_t> source;
    std::mt19937 rng(seed + 1);
    for (const Ray& p : primary) {
        const Hit hit = intersect(grid, view, p);
        if (!hit.is_hit()) continue;
        const SurfacePoint at = surface_point(view, hit);
        const Vec3f n = normalize(at.normal);
        for (std::size_t k = 0; k < per_hit; ++k) {
            Vec3f d = random_unit(rng);
            if (k >= 4) {  // grazing: in the tangent plane, tilted by 1e-3 or 1e-6
                const Vec3f tangent = normalize(d - n * dot(d, n));
                const float tilt = (k % 2 == 0 ? 1e-3f : 1e-6f) * (k >= 6 ? -1.0f : 1.0f);
                d = tangent + n * tilt;
            }
            rays.push_back(spawn_ray(at, d));
            source.push_back(hit.triangle);
        }
    }
    SelfHits out;
    out.secondary = rays.size();
    out.self_hits = parallel_count(rays.size(), [&](std::size_t i) {
        return intersect(grid, view, rays[i]).triangle == source[i];
    });
    out.hits = parallel_count(rays.size(), [&](std::size_t i) {
        return intersect(grid, view, rays[i]).is_hit();
    });
    for (std::size_t i = 0; i < rays.size() && out.self_hits > 0; ++i)
        if (intersect(grid, view, rays[i]).triangle == source[i]) {
            out.first = "secondary ray " + std::to_string(i) + " hit its source triangle " +
                        std::to_string(source[i]);
            break;
        }
    return out;
}

void expect_no_self_hits(const char* name, const Mesh& mesh, const Aabb& box, std::uint32_t seed)
{
    const SelfHits s = spawn_from_hits(mesh, box, seed, pick_size(200000, 1000000) / 4);
    std::printf("[ self     ] %-12s %zu secondary rays: %zu hit their source, %zu hit something\n",
                name, s.secondary, s.self_hits, s.hits);
    EXPECT_GT(s.secondary, pick_size(200000, 1000000) / 8) << "too few primary hits";
    EXPECT_EQ(s.self_hits, 0u) << s.first;
}

TEST(SelfIntersection, SecondaryRaysNeverHitTheirSourceTriangle)
{
    // A quarter of the rays on each scene: 2 * 10^5 in CI, 10^6 in full.
    const Mesh sphere = uv_sphere({1.5f, 2.25f, -3.125f}, 5.0f, 64, 128);
    expect_no_self_hits("sphere", sphere, Aabb{{-2, -1, -6}, {5, 5, 0}}, 101);
    const Vec3f far_centre{148376.0f, 1234.0f, -223423.0f};
    const Mesh far = uv_sphere(far_centre, 400.0f, 64, 128);
    expect_no_self_hits("far sphere", far,
                        Aabb{far_centre - Vec3f{200, 200, 200}, far_centre + Vec3f{200, 200, 200}},
                        102);
    const Aabb box{{0, 0, 0}, {10, 10, 10}};
    expect_no_self_hits("soup", random_triangles(103, 20000, box, 0.5f), box, 104);
    const std::filesystem::path bunny =
        std::filesystem::path(SG_SHARED_MESHES_DIR) / "scanned/bunny_npm.obj";
    if (!std::filesystem::exists(bunny)) {
        std::printf("[ self     ] %s absent: real mesh skipped\n", bunny.string().c_str());
        return;
    }
    const Mesh real = import_mesh(bunny).mesh;
    expect_no_self_hits("bunny", real, bounds(real.view()), 105);
}

// Two parallel squares: the lower one at height `at` (its plane tilted by `tilt`), the upper
// one `gap` above. Rays spawned upwards from random points of the lower square must hit the
// upper one; returns how many of `count` do not.
std::size_t skipped_across(double at, double gap, float tilt, std::size_t count, std::uint32_t seed)
{
    Mesh mesh;
    const double half = std::max(1.0, std::fabs(at) * 1e-2);  // 2^16 ulps and more wide
    for (const double z : {at, at + gap})
        for (const Vec3f c : {Vec3f{-1, -1, 0}, Vec3f{1, -1, 0}, Vec3f{1, 1, 0}, Vec3f{-1, 1, 0}}) {
            const double x = at + half * c.x, y = at + half * c.y;
            mesh.vertices.push_back({static_cast<float>(x), static_cast<float>(y),
                                     static_cast<float>(z + tilt * half * c.x)});
        }
    for (const std::uint32_t base : {0u, 4u}) {
        mesh.triangles.push_back(Triangle{{base, base + 1, base + 2}});
        mesh.triangles.push_back(Triangle{{base, base + 2, base + 3}});
    }
    const SplitGrid grid = build_checked(mesh);
    const MeshView view = mesh.view();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.05f, 0.95f);
    std::size_t skipped = 0;
    for (std::size_t k = 0; k < count; ++k) {
        // A point of the lower square from its barycentrics, as a hit would give it.
        Hit h;
        h.triangle = static_cast<std::uint32_t>(k % 2);
        h.u = u(rng) * 0.5f;
        h.v = u(rng) * 0.5f;
        const SurfacePoint at_point = surface_point(view, h);
        // Towards the upper square, within about 42 degrees of the normal, so that the ray
        // meets it long before the square's edge.
        const Vec3f up = normalize(Vec3f{-tilt, 0.0f, 1.0f});
        const Vec3f d = random_unit(rng) + up * 1.5f;
        const Hit hit = intersect(grid, view, spawn_ray(at_point, d));
        skipped += (hit.is_hit() && hit.triangle >= 2) ? 0 : 1;
    }
    return skipped;
}

TEST(SelfIntersection, SmallestGapTheOffsetRuleStillResolvesIsMeasured)
{
    std::printf("\nSmallest gap between two parallel surfaces that a spawned ray still crosses "
                "(500 rays each, none may skip the far surface)\n\n"
                "| coordinates | tilt | smallest resolved gap | in ulps of the coordinates |\n"
                "|---:|---:|---:|---:|\n");
    for (const double at : {0.0, 0.5, 1.0, 1e3, 1e5, 1e7}) {
        for (const float tilt : {0.0f, 0.3f}) {
            const double ulp = at == 0.0 ? 0.0 : std::ldexp(1.0, std::ilogb(at) - 23);
            // Bisect on a doubling scale, then linearly: the gap is a property of the rule.
            double lo = 0.0, hi = at == 0.0 ? 1e-6 : ulp;
            while (skipped_across(at, hi, tilt, 500, 7) > 0) {
                lo = hi;
                hi *= 2.0;
                ASSERT_LT(hi, 1e-2 * std::max(1.0, at)) << "no gap is resolved at " << at;
            }
            for (int step = 0; step < 12; ++step) {
                const double mid = 0.5 * (lo + hi);
                (skipped_across(at, mid, tilt, 500, 7) > 0 ? lo : hi) = mid;
            }
            std::printf("| %g | %.1f | %.3g | %s |\n", at, double(tilt), hi,
                        at == 0.0 ? "(absolute 1/65536 offset)"
                                  : std::to_string(static_cast<long>(hi / ulp)).c_str());
            // The rule offsets by 256 ulps (or 1/65536 near zero) along the normal: a gap of
            // a few times that must always be resolved.
            const double offset = std::fabs(at) < 1.0 / 32 ? 1.0 / 65536 : 256.0 * ulp;
            EXPECT_LE(hi, 4.0 * offset) << "at " << at << ", tilt " << tilt;
        }
    }
}

}  // namespace
}  // namespace sg::test
