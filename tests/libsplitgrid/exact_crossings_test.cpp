// Rays through edges and vertices count what a slightly moved ray counts (docs/SPLIT_GRID.md,
// "Exact edge functions"), in every structure: checked against geometry whose answer is known
// (a convex sphere crossed once from inside, a cube's grid lines), against a double-precision
// count along the ray moved by a finite amount, and against brute force over all triangles.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "splitgrid/closed_shapes.hpp"
#include "splitgrid/intersections.hpp"
#include "splitgrid/traverse.hpp"
#include "support/all_structures.hpp"
#include "support/crossings_oracle.hpp"
#include "support/oracle.hpp"
#include "support/random_scene.hpp"

namespace sg::test {
namespace {

/// One structure's multi-hit and closest-hit queries, by name.
struct Structure {
    std::string name;
    std::function<std::vector<std::int32_t>(std::span<const Ray>)> count;
    std::function<IntersectionList(std::span<const Ray>)> list;
    std::function<Hit(const Ray&)> closest;
};

/// Each structure's queries on `built`, and brute force's.
std::vector<Structure> queries_of(const AllStructures& built)
{
    const MeshView m = built.mesh.view();
    std::vector<Structure> out;
    out.push_back({"split grid",
                   [&built, m](std::span<const Ray> r) {
                       std::vector<std::int32_t> c(r.size());
                       count_intersections(built.grid, m, r, c);
                       return c;
                   },
                   [&built, m](std::span<const Ray> r) {
                       IntersectionList l;
                       list_intersections(built.grid, m, r, l);
                       return l;
                   },
                   [&built, m](const Ray& r) { return intersect(built.grid, m, r); }});
    auto add = [&](const char* name, const auto& s) {
        out.push_back({name,
                       [&s, m](std::span<const Ray> r) {
                           std::vector<std::int32_t> c(r.size());
                           s.count_intersections(m, r, c);
                           return c;
                       },
                       [&s, m](std::span<const Ray> r) {
                           IntersectionList l;
                           s.list_intersections(m, r, l);
                           return l;
                       },
                       [&s, m](const Ray& r) { return s.intersect(m, r); }});
    };
    add("bvh", built.bvh);
    add("kd-tree", built.kd);
    add("uniform grid", built.uniform);
    out.push_back({"brute force",
                   [m](std::span<const Ray> r) {
                       std::vector<std::int32_t> c;
                       for (const Ray& ray : r)
                           c.push_back(static_cast<std::int32_t>(all_hits_brute_force(m, ray).size()));
                       return c;
                   },
                   nullptr, [m](const Ray& r) { return intersect_brute_force(m, r); }});
    return out;
}

/// Every structure's counts of `rays` must equal `expected` (one per ray).
void expect_counts(const Mesh& mesh, const std::vector<Ray>& rays,
                   const std::vector<std::int32_t>& expected, const std::string& what)
{
    const AllStructures built(mesh);
    for (const Structure& s : queries_of(built)) {
        const std::vector<std::int32_t> counts = s.count(rays);
        std::size_t wrong = 0;
        std::string first;
        for (std::size_t k = 0; k < rays.size(); ++k) {
            if (counts[k] == expected[k]) continue;
            if (wrong++ == 0)
                first = "ray " + std::to_string(k) + ": " + std::to_string(counts[k]) +
                        " hits, expected " + std::to_string(expected[k]);
        }
        EXPECT_EQ(wrong, 0u) << what << ", " << s.name << ": " << first;
    }
}

Vec3f midpoint(Vec3f a, Vec3f b) { return (a + b) * 0.5f; }

/// The targets of rays through every vertex and every edge midpoint of `mesh`.
std::vector<Vec3f> vertices_and_edge_midpoints(const Mesh& mesh)
{
    std::vector<Vec3f> targets = mesh.vertices;
    for (const Triangle& t : mesh.triangles)
        for (int k = 0; k < 3; ++k)
            targets.push_back(midpoint(mesh.vertices[t.v[static_cast<std::size_t>(k)]],
                                       mesh.vertices[t.v[static_cast<std::size_t>((k + 1) % 3)]]));
    return targets;
}

/// The same mesh with every third triangle's winding reversed.
Mesh with_mixed_winding(Mesh mesh)
{
    for (std::size_t k = 0; k < mesh.triangles.size(); k += 3)
        std::swap(mesh.triangles[k].v[1], mesh.triangles[k].v[2]);
    return mesh;
}

TEST(ExactEdges, AFlatFanIsCrossedOnceThroughItsCentreAndEveryInnerEdge)
{
    // Seven triangles around a centre in the plane z = 0: a ray that meets the plane inside
    // the fan crosses it once, wherever it meets it (the shared vertex, a shared edge).
    const Vec3f c{0.25f, 0.75f, 0.0f};
    Mesh fan;
    fan.vertices.push_back(c);
    for (int k = 0; k < 7; ++k) {
        const double phi = 2.0 * 3.14159265358979 * k / 7.0;
        fan.vertices.push_back({float(0.25 + std::cos(phi)), float(0.75 + std::sin(phi)), 0.0f});
    }
    for (std::uint32_t k = 0; k < 7; ++k) fan.triangles.push_back(Triangle{{0, 1 + k, 1 + (k + 1) % 7}});
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    std::vector<Ray> rays;
    for (int trial = 0; trial < 4000; ++trial) {
        const Vec3f origin{u(rng), u(rng), (trial % 4 < 2 ? 1.0f : -1.0f) * (1.0f + std::abs(u(rng)))};
        const int k = trial % 7;
        const Vec3f target = trial % 2 ? c : midpoint(fan.vertices[static_cast<std::size_t>(1 + k)], c);
        rays.push_back(Ray{origin, target - origin});
    }
    expect_counts(fan, rays, std::vector<std::int32_t>(rays.size(), 1), "fan");
    expect_counts(with_mixed_winding(fan), rays, std::vector<std::int32_t>(rays.size(), 1),
                  "fan, mixed winding");
}

TEST(ExactEdges, AnIcosphereIsCrossedOnceFromItsCentreThroughEveryVertexAndEdge)
{
    for (const float radius : {1.0f, 1000.0f}) {
        const Mesh sphere = icosphere(3, radius);
        const std::vector<Vec3f> targets = vertices_and_edge_midpoints(sphere);
        std::vector<Ray> from_centre, from_outside;
        for (const Vec3f t : targets) {
            from_centre.push_back(Ray{{0, 0, 0}, t});
            // From outside through the same point: in and out again.
            from_outside.push_back(Ray{t * 3.0f, t * -1.0f});
        }
        const std::string what = "icosphere r=" + std::to_string(radius);
        expect_counts(sphere, from_centre, std::vector<std::int32_t>(targets.size(), 1), what);
        expect_counts(sphere, from_outside, std::vector<std::int32_t>(targets.size(), 2), what);
        const Mesh mixed = with_mixed_winding(sphere);
        expect_counts(mixed, from_centre, std::vector<std::int32_t>(targets.size(), 1),
                      what + ", mixed winding");
    }
}

TEST(ExactEdges, ACubesGridLinesCountAsTheRayMovedOffThem)
{
    // Axis-aligned rays along every grid line of a tessellated cube (integer coordinates: every
    // value below is exact), from outside and from inside. A line through the interior enters
    // and leaves through grid vertices; one on a face or an edge of the cube grazes it. Each
    // counts what the ray moved by e = 2^-10 across it counts, in double precision.
    constexpr std::uint32_t n = 4;
    const Mesh cube = tessellated_cube(n);
    std::vector<Ray> rays;
    for (int axis = 0; axis < 3; ++axis) {
        for (const float sign : {1.0f, -1.0f}) {
            for (std::uint32_t i = 0; i <= n; ++i) {
                for (std::uint32_t j = 0; j <= n; ++j) {
                    for (const float start : {-1.0f, 0.5f, 2.0f}) {
                        Ray r;
                        r.origin[axis] = sign > 0 ? start : float(n) - start;
                        r.origin[(axis + 1) % 3] = float(i);
                        r.origin[(axis + 2) % 3] = float(j);
                        r.direction[axis] = sign;
                        rays.push_back(r);
                    }
                }
            }
        }
    }
    std::vector<std::int32_t> expected;
    std::size_t crossing = 0;
    for (const Ray& r : rays) {
        const Vec3d d{r.direction.x, r.direction.y, r.direction.z};
        expected.push_back(static_cast<std::int32_t>(
            count_crossings_double(cube.view(), moved_origin(r, 0x1p-10), d, 0.0)));
        crossing += expected.back() > 0 ? 1 : 0;
    }
    ASSERT_GT(crossing, rays.size() / 3);
    expect_counts(cube, rays, expected, "tessellated cube");
    expect_counts(with_mixed_winding(cube), rays, expected, "tessellated cube, mixed winding");
}

TEST(ExactEdges, ANonManifoldEdgeCountsAsTheRayMovedOffIt)
{
    // Two cubes that share one edge (x = 1, y = 1), welded: four triangles meet there. Rays
    // through points of that edge in many directions whose ratios are powers of two (so the
    // sheared frame is exact), against the double-precision count of the moved ray.
    Mesh two = tessellated_cube(2);
    for (Vec3f& v : two.vertices) v = v * 0.5f;
    Mesh other = two;
    for (Vec3f& v : other.vertices) v = v + Vec3f{1, 1, 0};
    const auto first_other = static_cast<std::uint32_t>(two.vertices.size());
    // Weld the second cube's vertices onto the first's where they coincide.
    std::vector<std::uint32_t> index(other.vertices.size());
    for (std::uint32_t k = 0; k < other.vertices.size(); ++k) {
        const auto same = std::find(two.vertices.begin(), two.vertices.begin() + first_other,
                                    other.vertices[k]);
        if (same != two.vertices.begin() + first_other) {
            index[k] = static_cast<std::uint32_t>(same - two.vertices.begin());
        } else {
            index[k] = static_cast<std::uint32_t>(two.vertices.size());
            two.vertices.push_back(other.vertices[k]);
        }
    }
    for (Triangle t : other.triangles) {
        for (auto& v : t.v) v = index[v];
        two.triangles.push_back(t);
    }
    std::vector<Ray> rays;
    const std::vector<float> parts{1.0f, -1.0f, 0.5f, -0.5f, 0.25f, 0.0f, 2.0f};
    for (const float z : {0.0f, 0.5f, 0.75f, 1.0f})
        for (const float dx : parts)
            for (const float dy : parts)
                for (const float dz : parts) {
                    if (dx == 0 && dy == 0 && dz == 0) continue;
                    const Vec3f d{dx, dy, dz};
                    rays.push_back(Ray{Vec3f{1, 1, z} - d * 5.0f, d});  // from outside both cubes
                }
    std::vector<std::int32_t> expected;
    for (const Ray& r : rays) {
        const Vec3d d{r.direction.x, r.direction.y, r.direction.z};
        expected.push_back(static_cast<std::int32_t>(
            count_crossings_double(two.view(), moved_origin(r, 0x1p-12), d, 0.0)));
    }
    expect_counts(two, rays, expected, "two cubes sharing an edge");
}

TEST(ExactEdges, EqualHitsGoToTheSmallestTriangleIdInEveryStructure)
{
    // Every triangle twice, under two ids far apart and in shuffled order: whichever copy a
    // walk meets first, the closest hit is the copy with the smaller id.
    Mesh mesh = random_triangles(41, 400, Aabb{{0, 0, 0}, {10, 10, 10}}, 2.0f);
    const std::size_t n = mesh.triangles.size();
    std::vector<std::uint32_t> order(n);
    for (std::uint32_t k = 0; k < n; ++k) order[k] = k;
    std::shuffle(order.begin(), order.end(), std::mt19937(5));
    for (std::uint32_t k = 0; k < n; ++k) mesh.triangles.push_back(mesh.triangles[order[k]]);
    const std::vector<Ray> rays = rays_at_triangles(42, 3000, Aabb{{0, 0, 0}, {10, 10, 10}}, mesh.view());
    const AllStructures built(mesh);
    for (const Structure& s : queries_of(built)) {
        std::size_t hits = 0, wrong = 0;
        for (const Ray& r : rays) {
            const Hit h = s.closest(r);
            if (!h.is_hit()) continue;
            ++hits;
            // The copy with the larger id is never the answer: the smaller one is hit at the
            // same t (the same corners in the same order).
            const std::uint32_t original = h.triangle < n ? h.triangle : order[h.triangle - n];
            wrong += h.triangle == original ? 0 : 1;
            const Hit expected = intersect_brute_force(mesh.view(), r);
            wrong += expected.triangle == h.triangle && expected.t == h.t ? 0 : 1;
        }
        EXPECT_GT(hits, rays.size() / 2) << s.name;
        EXPECT_EQ(wrong, 0u) << s.name;
    }
}

TEST(MultiHit, ListsAndCountsEqualBruteForceOverAllTriangles)
{
    // Random triangles, overlapping and crossing cells, and rays aimed at their vertices and
    // edges, with random windows: each structure's list equals brute force's, hit by hit (t,
    // id, barycentrics), each triangle once however many cells reference it.
    const Aabb box{{0, 0, 0}, {10, 10, 10}};
    const Mesh mesh = random_triangles(51, 2000, box, 4.0f);
    std::vector<Ray> rays = random_rays(52, 1500, box);
    const std::vector<Ray> aimed = rays_at_triangles(53, 1500, box, mesh.view());
    rays.insert(rays.end(), aimed.begin(), aimed.end());
    for (std::uint32_t k = 0; k < 1000; ++k) {
        Ray r = aimed[k];
        const std::uint32_t tri = k % static_cast<std::uint32_t>(mesh.triangles.size());
        const Vec3f target = k % 2 ? mesh.view().vertex(tri, k % 3)
                                   : midpoint(mesh.view().vertex(tri, 0), mesh.view().vertex(tri, 1));
        r.direction = target - r.origin;
        rays.push_back(r);
    }
    std::vector<Ray> windowed = rays;
    set_random_windows(windowed, 54, -5.0f, 30.0f);
    rays.insert(rays.end(), windowed.begin(), windowed.end());
    const std::vector<Ray> invalid = invalid_rays();
    rays.insert(rays.end(), invalid.begin(), invalid.end());

    IntersectionList expected;
    std::size_t several = 0;
    for (std::size_t k = 0; k < rays.size(); ++k) {
        const std::vector<Hit> hits = all_hits_brute_force(mesh.view(), rays[k]);
        several += hits.size() > 1 ? 1 : 0;
        expected.hits.insert(expected.hits.end(), hits.begin(), hits.end());
        expected.ray_ids.insert(expected.ray_ids.end(), hits.size(), static_cast<std::uint32_t>(k));
        expected.ray_splits.push_back(expected.hits.size());
    }
    ASSERT_GT(several, rays.size() / 10) << "too few rays with several hits to test anything";
    const AllStructures built(mesh);
    for (const Structure& s : queries_of(built)) {
        if (!s.list) continue;
        // In two batches joined by concatenate, as a parallel caller does.
        const std::size_t half = rays.size() / 2;
        const std::vector<IntersectionList> parts{
            s.list(std::span<const Ray>(rays).first(half)),
            s.list(std::span<const Ray>(rays).subspan(half))};
        const IntersectionList list = concatenate(parts);
        ASSERT_EQ(list.ray_splits, expected.ray_splits) << s.name;
        EXPECT_EQ(list.ray_ids, expected.ray_ids) << s.name;
        std::size_t differ = 0;
        for (std::size_t i = 0; i < list.hits.size(); ++i) {
            const Hit& a = list.hits[i];
            const Hit& b = expected.hits[i];
            differ += a.t == b.t && a.triangle == b.triangle && a.u == b.u && a.v == b.v ? 0 : 1;
        }
        EXPECT_EQ(differ, 0u) << s.name;
        const std::vector<std::int32_t> counts = s.count(rays);
        for (std::size_t k = 0; k < rays.size(); ++k)
            ASSERT_EQ(std::uint64_t(counts[k]), expected.ray_splits[k + 1] - expected.ray_splits[k])
                << s.name << ", ray " << k;
    }
}

}  // namespace
}  // namespace sg::test
