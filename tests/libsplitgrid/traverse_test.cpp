// Traversal against the brute-force oracle (every triangle tested, lowest t wins), on seeded
// scenes chosen to hit the known failure modes of grids: zero direction components, rays
// starting on or lying in cell planes, flat scenes, geometry exactly on cell planes.

#include "splitgrid/traverse.hpp"

#include <gtest/gtest.h>

#include <random>

#include "splitgrid/builder.hpp"
#include "splitgrid/cell_math.hpp"
#include "splitgrid/validate.hpp"
#include "support/oracle.hpp"
#include "support/random_scene.hpp"

namespace sg {
namespace {

using test::build_checked;

void expect_agreement(const SplitGrid& grid, const Mesh& mesh, const std::vector<Ray>& rays,
                      std::size_t min_hits = 1)
{
    const test::OracleReport r = test::compare_with_brute_force(grid, mesh.view(), rays);
    EXPECT_EQ(r.closest_disagreements, 0u) << r.first_failure;
    EXPECT_EQ(r.any_hit_disagreements, 0u) << r.first_failure;
    EXPECT_GE(r.hits, min_hits) << "the rays should hit something, or the test proves little";
}

const Aabb unit_box{{0, 0, 0}, {10, 10, 10}};

TEST(Traverse, RandomSoupsAgreeWithBruteForce)
{
    for (std::uint32_t seed : {1u, 2u, 3u}) {
        const Mesh mesh = test::random_triangles(seed, 2000, unit_box, 1.0f);
        const SplitGrid grid = build_checked(mesh);
        ASSERT_GT(grid.nodes.size(), 1u);
        auto rays = test::random_rays(seed + 100, 10000, unit_box);
        const auto aimed = test::rays_at_triangles(seed + 200, 10000, unit_box, mesh.view());
        rays.insert(rays.end(), aimed.begin(), aimed.end());
        expect_agreement(grid, mesh, rays, 10000);
    }
}

TEST(Traverse, RayWindowsAgreeWithBruteForce)
{
    const Mesh mesh = test::random_triangles(7, 2000, unit_box, 1.5f);
    const SplitGrid grid = build_checked(mesh);
    auto rays = test::rays_at_triangles(8, 20000, unit_box, mesh.view());
    test::set_random_windows(rays, 9, 0.0f, 1.5f);
    rays[0].t_min = rays[0].t_max = 0.5f;  // an empty-width window
    expect_agreement(grid, mesh, rays, 1000);
}

TEST(Traverse, ZeroDirectionComponentsAgreeWithBruteForce)
{
    const Mesh mesh = test::random_triangles(11, 2000, unit_box, 1.0f);
    const SplitGrid grid = build_checked(mesh);
    const std::vector<Ray> rays = test::zero_direction_rays(12, 20000, unit_box, mesh);
    expect_agreement(grid, mesh, rays, 2000);
}

// Every boundary plane of a sample of nodes: origins exactly on the plane, crossing it or
// lying in it (direction component +0.0 and -0.0).
TEST(Traverse, RaysOnCellBoundariesAndBoundingPlanes)
{
    const Mesh mesh = test::random_triangles(21, 3000, unit_box, 1.0f);
    const SplitGrid grid = build_checked(mesh);
    std::mt19937 rng(22);
    std::uniform_real_distribution<float> u(0.0f, 10.0f);
    std::vector<Ray> rays;
    const auto dirs = test::random_rays(23, 40000, unit_box);
    std::size_t k = 0;
    // Cycle through the nodes until enough rays are made; the random origin differs each time.
    for (std::size_t n = 0; rays.size() < 40000; n = (n + 1) % grid.nodes.size()) {
        const GridNode& node = grid.nodes[n];
        const CellMath cm(node.lo, node.hi, node.resolution());
        for (std::uint32_t i = 0; i <= node.resolution() && rays.size() < 40000; ++i) {
            for (int rep = 0; rep < 4; ++rep, ++k) {
                Ray r;
                r.origin = {u(rng), u(rng), u(rng)};
                r.origin[node.axis()] = cm.boundary(i);
                r.direction = dirs[k % dirs.size()].direction;
                if (rep == 2) r.direction[node.axis()] = 0.0f;
                if (rep == 3) r.direction[node.axis()] = -0.0f;
                rays.push_back(r);
            }
        }
    }
    ASSERT_GE(rays.size(), 20000u);
    expect_agreement(grid, mesh, rays, 1000);
}

TEST(Traverse, PlanarSceneAndRaysInItsPlane)
{
    for (int axis = 0; axis < 3; ++axis) {
        const Mesh mesh = test::axis_plane(axis, 3.0f, 40);  // 3200 triangles in one plane
        const SplitGrid grid = build_checked(mesh);
        auto rays = test::random_rays(31, 5000, Aabb{{-1, -1, -1}, {41, 41, 41}});
        const auto aimed = test::rays_at_triangles(32, 5000, Aabb{{-1, -1, -1}, {41, 41, 41}},
                                                   mesh.view());
        rays.insert(rays.end(), aimed.begin(), aimed.end());
        test::append_rays_in_plane(rays, axis, 3.0f, 2000);  // rays lying in the triangles' plane
        expect_agreement(grid, mesh, rays, 3000);
    }
}

// Triangles lying exactly on cell planes: unit-spaced planes on all three axes, with the
// resolution forced so that cell boundaries fall on them.
TEST(Traverse, TrianglesOnCellPlanes)
{
    Mesh mesh;
    for (int axis = 0; axis < 3; ++axis)
        for (int offset = 0; offset <= 8; offset += 2) test::append(mesh, test::axis_plane(axis, float(offset), 8));
    BuildConfig config;
    config.resolution_min = 8;
    config.resolution_max = 8;
    const SplitGrid grid = build_checked(mesh, config);
    const Aabb box{{-0.5f, -0.5f, -0.5f}, {8.5f, 8.5f, 8.5f}};
    auto rays = test::random_rays(41, 10000, box);
    const auto aimed = test::rays_at_triangles(42, 10000, box, mesh.view());
    rays.insert(rays.end(), aimed.begin(), aimed.end());
    // Axis-aligned rays through lattice points (edges and corners of the triangles).
    const auto axis_rays = test::axis_rays_through_lattice(43, 6000, 8, false);
    rays.insert(rays.end(), axis_rays.begin(), axis_rays.end());
    expect_agreement(grid, mesh, rays, 5000);
}

// A closed sphere: every ray from inside must hit it, whatever the structure does.
TEST(Traverse, ClosedSphereHasNoLeaks)
{
    const Mesh mesh = test::uv_sphere({1.0f, 2.0f, 3.0f}, 5.0f, 64, 128);
    const SplitGrid grid = build_checked(mesh);
    const auto rays = test::random_rays(51, 50000, Aabb{{-1.5f, -0.5f, 0.5f}, {3.5f, 4.5f, 5.5f}});
    std::size_t misses = 0;
    for (const Ray& r : rays) misses += intersect(grid, mesh.view(), r).is_hit() ? 0 : 1;
    EXPECT_EQ(misses, 0u);
}

TEST(Traverse, InvalidRaysMissWithoutTouchingTheStructure)
{
    const Mesh mesh = test::random_triangles(61, 100, unit_box, 1.0f);
    const SplitGrid grid = build_checked(mesh);
    const std::vector<Ray> bad = test::invalid_rays();
    for (const Ray& r : bad) {
        EXPECT_FALSE(is_valid(r));
        TraversalCounters counters;
        EXPECT_FALSE(intersect(grid, mesh.view(), r, &counters).is_hit());
        EXPECT_FALSE(occluded(grid, mesh.view(), r, &counters));
        EXPECT_EQ(counters.cells_visited + counters.nodes_visited, 0u);
    }
}

TEST(Traverse, CountersSeeTheWork)
{
    const Mesh mesh = test::random_triangles(71, 2000, unit_box, 1.0f);
    const SplitGrid grid = build_checked(mesh);
    const auto rays = test::rays_at_triangles(72, 1000, unit_box, mesh.view());
    std::size_t tests = 0;
    for (const Ray& r : rays) {
        TraversalCounters c;
        (void)intersect(grid, mesh.view(), r, &c);
        EXPECT_GE(c.nodes_visited, 1u);
        tests += c.triangles_tested;
    }
    // The structure must test far fewer triangles than brute force would.
    EXPECT_LT(tests, rays.size() * mesh.triangles.size() / 20);
}

}  // namespace
}  // namespace sg
