// Row 6 of docs/ROBUSTNESS.md: invalid rays. NaN and infinite origins, directions and
// t-ranges, zero and denormal-only directions, t_min > t_max, alone and combined: every query
// must return the documented result (ray.hpp: no hit, t = the ray's t_max, u = v = 0;
// occluded false), the same as brute force, and touch nothing (0 nodes, 0 cells, 0
// triangles), so an invalid ray costs only the validity check. The time of a batch of invalid
// rays against a batch of valid ones is printed, not asserted (speed belongs to benchmarks).
// Valid rays at the edges of the float range must agree with brute force.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "robustness_support.hpp"
#include "support/random_scene.hpp"

namespace sg::test {
namespace {

constexpr float nan = std::numeric_limits<float>::quiet_NaN();
constexpr float inf = std::numeric_limits<float>::infinity();
constexpr float big = std::numeric_limits<float>::max();
constexpr float tiny = std::numeric_limits<float>::min();

// Every single defect, then random combinations of two or three of them.
std::vector<Ray> invalid_ray_set(std::uint32_t seed, std::size_t combined)
{
    const Ray good{{1, 2, 3}, {0.3f, -0.5f, 0.8f}, 0.0f, inf};
    std::vector<Ray> rays;
    for (int k = 0; k < 3; ++k)
        for (const float bad : {nan, inf, -inf}) {
            Ray r = good;
            r.origin[k] = bad;
            rays.push_back(r);
            r = good;
            r.direction[k] = bad;
            rays.push_back(r);
        }
    for (const Vec3f d : {Vec3f{0, 0, 0}, Vec3f{-0.0f, 0.0f, -0.0f}, Vec3f{1e-40f, 0, 0},
                          Vec3f{-1e-45f, 1e-39f, -1e-38f}}) {
        Ray r = good;
        r.direction = d;
        rays.push_back(r);
    }
    for (const float t : {nan, inf, -inf}) {
        Ray r = good;
        r.t_min = t;
        rays.push_back(r);
    }
    for (const float t : {nan, -inf, -1.0f}) {  // -1 < t_min = 0
        Ray r = good;
        r.t_max = t;
        rays.push_back(r);
    }
    for (const auto& [lo, hi] : {std::pair{2.0f, 1.0f}, std::pair{big, -big},
                                 std::pair{0.0f, -tiny}, std::pair{inf, inf}}) {
        Ray r = good;
        r.t_min = lo;
        r.t_max = hi;
        rays.push_back(r);
    }
    const std::size_t singles = rays.size();
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> pick(0, singles - 1);
    while (rays.size() < singles + combined) {
        // Take the defective fields of two or three single-defect rays at once.
        Ray r = rays[pick(rng)];
        for (int extra = 0; extra < 1 + static_cast<int>(rng() % 2); ++extra) {
            const Ray& other = rays[pick(rng)];
            for (int k = 0; k < 3; ++k) {
                if (other.origin[k] != good.origin[k]) r.origin[k] = other.origin[k];
                if (other.direction[k] != good.direction[k] ||
                    std::signbit(other.direction[k]) != std::signbit(good.direction[k]))
                    r.direction[k] = other.direction[k];
            }
            if (!(other.t_min == good.t_min)) r.t_min = other.t_min;
            if (!(other.t_max == good.t_max)) r.t_max = other.t_max;
        }
        rays.push_back(r);
    }
    return rays;
}

bool same_bits(float a, float b)
{
    return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}

// The documented miss: no triangle, t = t_max (bit for bit, NaN included), u = v = 0.
bool is_documented_miss(const Hit& hit, const Ray& ray)
{
    return !hit.is_hit() && same_bits(hit.t, ray.t_max) && hit.u == 0.0f && hit.v == 0.0f;
}

void check_invalid_rays(const SplitGrid& grid, const Mesh& mesh, const std::vector<Ray>& rays)
{
    const MeshView view = mesh.view();
    for (const Ray& r : rays) {
        ASSERT_FALSE(is_valid(r));
        TraversalCounters closest, any;
        const Hit hit = intersect(grid, view, r, &closest);
        EXPECT_TRUE(is_documented_miss(hit, r));
        EXPECT_FALSE(occluded(grid, view, r, &any));
        EXPECT_TRUE(is_documented_miss(intersect_brute_force(view, r), r));
        EXPECT_FALSE(occluded_brute_force(view, r));
        for (const TraversalCounters& c : {closest, any}) {
            EXPECT_EQ(c.nodes_visited, 0u);
            EXPECT_EQ(c.cells_visited, 0u);
            EXPECT_EQ(c.triangles_tested, 0u);
        }
    }
}

TEST(InvalidRays, EveryKindGivesTheDocumentedMissAndTouchesNothing)
{
    const Mesh soup = random_triangles(61, 3000, Aabb{{0, 0, 0}, {10, 10, 10}}, 1.0f);
    const std::vector<Ray> rays = invalid_ray_set(62, 2000);
    std::printf("[ invalid  ] %zu invalid rays (%zu kinds alone, the rest combined)\n",
                rays.size(), rays.size() - 2000);
    check_invalid_rays(build_checked(soup), soup, rays);

    // A grid whose root is a leaf, and an empty grid.
    Mesh one;
    one.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    one.triangles = {Triangle{{0, 1, 2}}};
    check_invalid_rays(build_checked(one), one, rays);
    const Mesh none;
    check_invalid_rays(build_checked(none), none, rays);
}

TEST(InvalidRays, ValidRaysAtTheEdgesOfTheFloatRangeAgreeWithBruteForce)
{
    const Aabb box{{0, 0, 0}, {10, 10, 10}};
    const Mesh mesh = random_triangles(63, 2000, box, 1.0f);
    const SplitGrid grid = build_checked(mesh);
    const std::vector<Ray> rays = float_range_edge_rays(64, 2000, box, mesh.view());
    for (const Ray& r : rays) ASSERT_TRUE(is_valid(r));
    const OracleReport report = parallel_compare(grid, mesh.view(), rays);
    EXPECT_EQ(report.closest_disagreements, 0u) << report.first_failure;
    EXPECT_EQ(report.any_hit_disagreements, 0u) << report.first_failure;
    EXPECT_GT(report.hits, 2000u);
}

TEST(InvalidRays, BatchCostIsThatOfTheValidityCheck)
{
    const Aabb box{{0, 0, 0}, {10, 10, 10}};
    const Mesh mesh = random_triangles(65, 20000, box, 0.5f);
    const SplitGrid grid = build_checked(mesh);
    const std::size_t n = pick_size(200000, 1000000);
    const std::vector<Ray> valid = random_rays(66, n, box);
    const std::vector<Ray> kinds = invalid_ray_set(67, 1000);
    std::vector<Ray> invalid(n);
    for (std::size_t i = 0; i < n; ++i) invalid[i] = kinds[i % kinds.size()];

    const MeshView view = mesh.view();
    TraversalCounters work_valid, work_invalid;
    auto run = [&](const std::vector<Ray>& rays, TraversalCounters& work) {
        std::size_t hits = 0;
        for (const Ray& r : rays) {
            TraversalCounters c;
            hits += intersect(grid, view, r, &c).is_hit() ? 1 : 0;
            hits += occluded(grid, view, r, &c) ? 1 : 0;
            work.nodes_visited += c.nodes_visited;
            work.cells_visited += c.cells_visited;
            work.triangles_tested += c.triangles_tested;
        }
        return hits;
    };
    std::size_t hits_valid = 0, hits_invalid = 0;
    const double t_valid = seconds_of([&] { hits_valid = run(valid, work_valid); });
    const double t_invalid = seconds_of([&] { hits_invalid = run(invalid, work_invalid); });
    std::printf("[ invalid  ] %zu rays, intersect + occluded: valid %.3f s (%u cells), invalid "
                "%.3f s (%u cells): ratio %.3f (the issue allows 2.5)\n",
                n, t_valid, work_valid.cells_visited, t_invalid, work_invalid.cells_visited,
                t_invalid / t_valid);
    EXPECT_GT(hits_valid, 0u);
    EXPECT_EQ(hits_invalid, 0u);
    EXPECT_GT(work_valid.cells_visited, n);
    EXPECT_EQ(work_invalid.nodes_visited, 0u);
    EXPECT_EQ(work_invalid.cells_visited, 0u);
    EXPECT_EQ(work_invalid.triangles_tested, 0u);
}

}  // namespace
}  // namespace sg::test
