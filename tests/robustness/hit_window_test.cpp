// Rows 5 and 7 of docs/ROBUSTNESS.md, the triangle test under both: whether a triangle hit
// lies in [t_min, t_max] must be decided on the t the test returns, nothing else. Otherwise
// a hit is refused once the closest hit so far is a float or two further away, and the
// closest hit of a ray depends on the order in which triangles are tested (brute force, in
// id order, and the grid, in leaf order, then disagree by one ulp of t). Found by the
// garbage-geometry test: corners near 1e37 and a ray whose two hits lie one ulp apart.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <random>

#include "splitgrid/ray_triangle.hpp"
#include "support/random_scene.hpp"

namespace sg::test {
namespace {

// For each (ray, triangle) hit: with t_max = t it must still hit, with the same t; with
// t_max one float below t it must miss; and likewise for t_min.
std::size_t inconsistent_windows(const Mesh& mesh, const std::vector<Ray>& rays,
                                 std::size_t& hits)
{
    std::size_t wrong = 0;
    const MeshView view = mesh.view();
    for (const Ray& ray : rays) {
        if (!is_valid(ray)) continue;
        const WatertightRay wr(ray);
        for (std::uint32_t tri = 0; tri < view.triangle_count(); ++tri) {
            const Vec3f a = view.vertex(tri, 0), b = view.vertex(tri, 1), c = view.vertex(tri, 2);
            float t = 0, u = 0, v = 0;
            if (!intersect_triangle(wr, a, b, c, -INFINITY, INFINITY, t, u, v)) continue;
            ++hits;
            float t2 = 0, u2 = 0, v2 = 0;
            const float below = std::nextafter(t, -INFINITY), above = std::nextafter(t, INFINITY);
            const bool at_max = intersect_triangle(wr, a, b, c, -INFINITY, t, t2, u2, v2) &&
                                t2 == t;
            const bool at_min = intersect_triangle(wr, a, b, c, t, INFINITY, t2, u2, v2) &&
                                t2 == t;
            const bool under = intersect_triangle(wr, a, b, c, -INFINITY, below, t2, u2, v2);
            const bool over = intersect_triangle(wr, a, b, c, above, INFINITY, t2, u2, v2);
            if (!at_max || !at_min || under || over) {
                if (wrong == 0)
                    std::printf("first inconsistent window: triangle %u, t = %.9g: t_max = t %s, "
                                "t_min = t %s, t_max below %s, t_min above %s\n",
                                tri, double(t), at_max ? "hits" : "misses",
                                at_min ? "hits" : "misses", under ? "hits" : "misses",
                                over ? "hits" : "misses");
                ++wrong;
            }
        }
    }
    return wrong;
}

TEST(HitWindow, TheTriangleTestAcceptsExactlyTheTItReturns)
{
    std::size_t hits = 0, wrong = 0;
    // Ordinary triangles, and triangles whose corners have random float bit patterns with
    // large exponents, where the products t * det of the window check round differently
    // from T / det.
    const Aabb box{{0, 0, 0}, {10, 10, 10}};
    const Mesh soup = random_triangles(81, 300, box, 2.0f);
    wrong += inconsistent_windows(soup, rays_at_triangles(82, 300, box, soup.view()), hits);
    std::mt19937 rng(83);
    std::uniform_int_distribution<std::uint32_t> bits;
    for (int m = 0; m < 50; ++m) {
        Mesh mesh;
        for (int v = 0; v < 60; ++v) {
            Vec3f p;
            for (int k = 0; k < 3; ++k)
                p[k] = std::bit_cast<float>((bits(rng) & 0x807FFFFFu) |
                                            ((100u + bits(rng) % 60u) << 23));
            mesh.vertices.push_back(p);
        }
        for (std::uint32_t t = 0; t < 20; ++t)
            mesh.triangles.push_back(Triangle{{3 * t, 3 * t + 1, 3 * t + 2}});
        const Aabb b = bounds(mesh.view());
        wrong += inconsistent_windows(
            mesh, rays_at_triangles(static_cast<std::uint32_t>(m), 100, b, mesh.view()), hits);
    }
    std::printf("[ window   ] %zu hits, %zu whose window check disagrees with the returned t\n",
                hits, wrong);
    EXPECT_GT(hits, 1000u);
    EXPECT_EQ(wrong, 0u);
}

}  // namespace
}  // namespace sg::test
