// The watertight test's decision against exact integer arithmetic (docs/SPLIT_GRID.md, "Exact
// edge functions"): for rays that pass within a few ulps of a triangle's edges and corners,
// the test hits exactly when the three edge functions of the sheared corners, evaluated in
// exact integer arithmetic with a zero decided by the perturbation (e, e^2), share one sign. The
// float filter, the double-precision path and the batched lanes of every structure are all
// held to it.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "exact_float.hpp"
#include "splitgrid/baselines/bvh.hpp"
#include "splitgrid/intersections.hpp"
#include "splitgrid/ray_triangle.hpp"
#include "splitgrid/traverse.hpp"
#include "support/oracle.hpp"

namespace sg::test {
namespace {

using boost::multiprecision::cpp_int;

/// The sign of qx py - qy px in integer arithmetic; a zero by the sign of qy - py, then of
/// px - qx (the ray moved by (e, e^2)).
int exact_perturbed_sign(float px, float py, float qx, float qy)
{
    const cpp_int e = scaled(qx) * scaled(py) - scaled(qy) * scaled(px);
    if (e != 0) return e > 0 ? 1 : -1;
    if (qy != py) return qy > py ? 1 : -1;
    if (px != qx) return px > qx ? 1 : -1;
    return 0;
}

/// Whether the ray passes through the triangle in the sheared frame, decided exactly.
bool exact_decision(const Ray& ray, Vec3f a, Vec3f b, Vec3f c)
{
    const detail::ShearedTriangle s(WatertightRay(ray), a, b, c);
    const int u = exact_perturbed_sign(s.Bx, s.By, s.Cx, s.Cy);
    const int v = exact_perturbed_sign(s.Cx, s.Cy, s.Ax, s.Ay);
    const int w = exact_perturbed_sign(s.Ax, s.Ay, s.Bx, s.By);
    return u != 0 && u == v && u == w;
}

/// Rays through points on the edges and corners of random triangles, nudged by 0 to 4 ulps
/// in each coordinate, and from random origins at all distances.
struct NearEdgeScene {
    Mesh mesh;
    std::vector<Ray> rays;
};

NearEdgeScene near_edge_scene(std::uint32_t seed, std::size_t triangles, std::size_t rays)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> coord(-8.0f, 8.0f);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::uniform_int_distribution<int> nudge(-4, 4);
    NearEdgeScene scene;
    // Fans around shared corners, so that shared edges are tested from both triangles.
    for (std::size_t k = 0; k < triangles; k += 6) {
        const auto centre = static_cast<std::uint32_t>(scene.mesh.vertices.size());
        scene.mesh.vertices.push_back({coord(rng), coord(rng), coord(rng)});
        for (int j = 0; j < 6; ++j) {
            const Vec3f p = scene.mesh.vertices[centre];
            scene.mesh.vertices.push_back(
                {p.x + coord(rng) * 0.3f, p.y + coord(rng) * 0.3f, p.z + coord(rng) * 0.3f});
        }
        for (std::uint32_t j = 0; j < 6; ++j)
            scene.mesh.triangles.push_back(Triangle{{centre, centre + 1 + j, centre + 1 + (j + 1) % 6}});
    }
    auto nudged = [&](float x) {
        int steps = nudge(rng);
        while (steps > 0) x = std::nextafter(x, 1e30f), --steps;
        while (steps < 0) x = std::nextafter(x, -1e30f), ++steps;
        return x;
    };
    const MeshView view = scene.mesh.view();
    for (std::size_t k = 0; k < rays; ++k) {
        const auto tri = static_cast<std::uint32_t>(k % view.triangle_count());
        const float w = (k % 3 == 0) ? 0.0f : unit(rng);  // a third at a corner
        const int e = static_cast<int>(k % 3);
        const Vec3f target = view.vertex(tri, e) * (1.0f - w) + view.vertex(tri, (e + 1) % 3) * w;
        const Vec3f origin{coord(rng) * 4.0f, coord(rng) * 4.0f, coord(rng) * 4.0f};
        Ray ray{origin, target - origin, -1e30f};
        if (k % 4 == 1) {
            // Along an axis exactly through a corner: two edge functions exactly zero.
            const int axis = static_cast<int>(k / 4 % 3);
            ray.origin = view.vertex(tri, e);
            ray.origin[axis] -= 10.0f;
            ray.direction = Vec3f{};
            ray.direction[axis] = k % 8 == 1 ? 1.0f : -1.0f;
            if (ray.direction[axis] < 0) ray.origin[axis] += 20.0f;
        } else if (k % 2 == 0) {
            ray.direction = Vec3f{nudged(ray.direction.x), nudged(ray.direction.y), nudged(ray.direction.z)};
        }
        scene.rays.push_back(ray);
    }
    return scene;
}

TEST(ExactEdgeSign, TheTriangleTestDecidesAsExactArithmeticWithThePerturbation)
{
    const NearEdgeScene scene = near_edge_scene(71, 600, 6000);
    const MeshView view = scene.mesh.view();
    std::size_t hits = 0, wrong = 0, exact_zero = 0;
    for (const Ray& ray : scene.rays) {
        const WatertightRay wr(ray);
        for (std::uint32_t tri = 0; tri < view.triangle_count(); tri += 1 + tri % 3) {
            const Vec3f a = view.vertex(tri, 0), b = view.vertex(tri, 1), c = view.vertex(tri, 2);
            float t, u, v;
            const bool hit = intersect_triangle(wr, a, b, c, ray.t_min, ray.t_max, t, u, v);
            const bool expected = exact_decision(ray, a, b, c);
            hits += expected ? 1 : 0;
            wrong += hit == expected ? 0 : 1;
            const detail::ShearedTriangle s(wr, a, b, c);
            exact_zero += double(s.Cx) * s.By == double(s.Cy) * s.Bx ||
                                  double(s.Ax) * s.Cy == double(s.Ay) * s.Cx ||
                                  double(s.Bx) * s.Ay == double(s.By) * s.Ax
                              ? 1
                              : 0;
        }
    }
    EXPECT_EQ(wrong, 0u);
    EXPECT_GT(hits, 3000u);
    EXPECT_GT(exact_zero, 100u) << "too few rays exactly through an edge to test the perturbation";
}

TEST(ExactEdgeSign, EveryStructuresBatchedLanesDecideAsExactArithmetic)
{
    // Every hit along each ray (all triangles, any t) from the BVH's and the Split Grid's
    // batched tests, against the exact decision for every triangle.
    const NearEdgeScene scene = near_edge_scene(72, 300, 1500);
    const MeshView view = scene.mesh.view();
    const SplitGrid grid = build_checked(scene.mesh);
    const Bvh bvh = Bvh::build(view);
    IntersectionList from_grid, from_bvh;
    list_intersections(grid, view, scene.rays, from_grid);
    bvh.list_intersections(view, scene.rays, from_bvh);
    std::size_t wrong_grid = 0, wrong_bvh = 0, hits = 0;
    for (std::size_t k = 0; k < scene.rays.size(); ++k) {
        std::vector<char> expected(view.triangle_count(), 0);
        for (std::uint32_t tri = 0; tri < view.triangle_count(); ++tri) {
            expected[tri] = exact_decision(scene.rays[k], view.vertex(tri, 0), view.vertex(tri, 1),
                                           view.vertex(tri, 2));
            hits += expected[tri];
        }
        auto wrong_in = [&](const IntersectionList& list) {
            std::vector<char> got(view.triangle_count(), 0);
            for (std::uint64_t i = list.ray_splits[k]; i < list.ray_splits[k + 1]; ++i)
                got[list.hits[i].triangle] = 1;
            return static_cast<std::size_t>(got != expected ? 1 : 0);
        };
        wrong_grid += wrong_in(from_grid);
        wrong_bvh += wrong_in(from_bvh);
    }
    EXPECT_GT(hits, 1000u);
    EXPECT_EQ(wrong_grid, 0u) << isa_name(kernel_isa());
    EXPECT_EQ(wrong_bvh, 0u) << isa_name(kernel_isa());
}

}  // namespace
}  // namespace sg::test
