// Row 1 of docs/ROBUSTNESS.md: no ray leaks through the edges and vertices of a closed mesh.
// Every ray that starts inside a closed sphere mesh (shared vertices, fans of 320 triangles at
// the poles) must hit it, with intersect() and with occluded(): random rays from random
// interior points, rays whose line passes exactly through a vertex, and rays through the
// midpoint of an edge; near the origin and at Embree's watertightness position.

#include <gtest/gtest.h>

#include <cstdio>

#include "leak_probe.hpp"
#include "robustness_support.hpp"

namespace sg::test {
namespace {

struct Position {
    const char* name;
    Vec3f center;
};

// Names the parameter in test listings (ctest shows it) instead of dumping its bytes.
void PrintTo(const Position& p, std::ostream* out) { *out << p.name; }

class Leak : public ::testing::TestWithParam<Position> {};

TEST_P(Leak, NoRayFromInsideTheClosedSphereEscapes)
{
    // 2 * 320 * 159 = 101,760 triangles, 50,882 shared vertices.
    const LeakScene scene(GetParam().center, 400.0f, 160, 320);
    ASSERT_GE(scene.mesh.triangles.size(), 100000u);
    const std::size_t random = pick_size(200000, 1000000);
    const std::size_t aimed = pick_size(20000, 100000);
    const LeakCount vertices = scene.count_leaks(scene.rays_at_vertices(2, aimed));
    const LeakCount edges = scene.count_leaks(scene.rays_at_edge_midpoints(3, aimed));
    const LeakCount all = scene.count_leaks(scene.random_rays(1, random));
    std::printf("[ leaks    ] %s: random %zu of %zu, vertices %zu of %zu, edge midpoints %zu of "
                "%zu\n",
                GetParam().name, all.leaks(), all.rays, vertices.leaks(), vertices.rays,
                edges.leaks(), edges.rays);
    EXPECT_EQ(all.rays, random);
    EXPECT_EQ(vertices.rays, aimed);
    EXPECT_EQ(edges.rays, aimed);
    for (const LeakCount* c : {&all, &vertices, &edges}) {
        EXPECT_EQ(c->closest_misses, 0u) << c->first_leak;
        EXPECT_EQ(c->any_hit_misses, 0u) << c->first_leak;
    }
}

INSTANTIATE_TEST_SUITE_P(
    Positions, Leak,
    ::testing::Values(Position{"origin", {1.5f, 2.25f, -3.125f}},
                      // Embree's own watertight test position (verify/verify.cpp).
                      Position{"far", {148376.0f, 1234.0f, -223423.0f}}),
    [](const ::testing::TestParamInfo<Position>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace sg::test
