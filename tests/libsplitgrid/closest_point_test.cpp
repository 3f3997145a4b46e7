// Closest points, distances and signed distances (closest_point.hpp) of every structure,
// against an independent double-precision oracle over all triangles (support/
// distance_oracle.hpp: Ericson's closest point by regions) and shapes whose inside is known.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "splitgrid/closed_shapes.hpp"
#include "splitgrid/closest_point.hpp"
#include "support/all_structures.hpp"
#include "support/distance_oracle.hpp"
#include "support/oracle.hpp"
#include "support/random_scene.hpp"

namespace sg::test {
namespace {

using PointQuery = std::function<void(std::span<const Vec3f>, std::span<ClosestPoint>, float)>;
using SignedQuery = std::function<void(std::span<const Vec3f>, std::span<float>)>;

struct PointStructure {
    std::string name;
    PointQuery closest;
    SignedQuery signed_distance;
};

/// Each structure's point queries on `built`, and brute force's.
std::vector<PointStructure> point_queries_of(const AllStructures& built)
{
    const MeshView m = built.mesh.view();
    std::vector<PointStructure> out;
    auto add = [&](const char* name, const auto& s) {
        out.push_back({name,
                       [&s, m](std::span<const Vec3f> p, std::span<ClosestPoint> o, float max) {
                           closest_points(s, m, p, o, max);
                       },
                       [&s, m](std::span<const Vec3f> p, std::span<float> o) {
                           signed_distances(s, m, p, o);
                       }});
    };
    add("split grid", built.grid);
    add("bvh", built.bvh);
    add("kd-tree", built.kd);
    add("uniform grid", built.uniform);
    out.push_back({"brute force",
                   [m](std::span<const Vec3f> p, std::span<ClosestPoint> o, float max) {
                       for (std::size_t k = 0; k < p.size(); ++k)
                           o[k] = closest_point_brute_force(m, p[k], max);
                   },
                   nullptr});
    return out;
}

/// The documented tolerance: 2^-40 (M + |p|), plus the rounding of the distance to float.
double tolerance(const Mesh& mesh, Vec3f p, double distance)
{
    const Aabb box = bounds(mesh.view());
    double m = 0.0;
    for (int k = 0; k < 3; ++k)
        m = std::max({m, std::abs(double(box.lower[k])), std::abs(double(box.upper[k])),
                      std::abs(double(p[k]))});
    return 0x1p-40 * 3.0 * m + 0x1p-24 * distance;
}

/// Every structure's closest points of `points` against the oracle: the distance within the
/// tolerance of the smallest, the triangle among those within the tolerance and the smallest
/// id of them, the point on that triangle and reproduced by its barycentrics.
void expect_closest_points(const Mesh& mesh, const std::vector<Vec3f>& points,
                           const std::string& what)
{
    const MeshView m = mesh.view();
    std::vector<DistanceOracle> expected;
    for (const Vec3f p : points) expected.push_back(distance_oracle(m, p, tolerance(mesh, p, 0.0)));
    const AllStructures built(mesh);
    for (const PointStructure& s : point_queries_of(built)) {
        std::vector<ClosestPoint> got(points.size());
        s.closest(points, got, std::numeric_limits<float>::infinity());
        std::size_t wrong = 0;
        std::string first;
        for (std::size_t k = 0; k < points.size(); ++k) {
            const ClosestPoint& c = got[k];
            const DistanceOracle& e = expected[k];
            const double tol = tolerance(mesh, points[k], e.distance);
            std::string why;
            if (!c.is_hit()) why = "no hit";
            else if (std::abs(double(c.distance) - e.distance) > tol) why = "distance off";
            else if (c.triangle != e.nearest.front()) why = "not the smallest id of the nearest";
            else {
                const Vec3f on = m.vertex(c.triangle, 0) * (1.0f - c.u - c.v) +
                                 m.vertex(c.triangle, 1) * c.u + m.vertex(c.triangle, 2) * c.v;
                // Float rounding of the point and of its barycentric reconstruction.
                const double scale = 1e-5 * (1.0 + e.distance + 0x1p40 * tolerance(mesh, points[k], 0.0));
                if (length(on - c.point) > scale || std::abs(double(length(c.point - points[k])) - e.distance) > scale)
                    why = "point or barycentrics off";
            }
            if (why.empty()) continue;
            if (wrong++ == 0)
                first = "point " + std::to_string(k) + ": " + why + " (got triangle " +
                        std::to_string(c.triangle) + " at " + std::to_string(c.distance) +
                        ", expected " + std::to_string(e.nearest.front()) + " at " +
                        std::to_string(e.distance) + ")";
        }
        EXPECT_EQ(wrong, 0u) << what << ", " << s.name << ": " << first;
    }
}

/// Points on every vertex, at every edge midpoint and face centre of `mesh`, and random points
/// near and far.
std::vector<Vec3f> probe_points(const Mesh& mesh, std::uint32_t seed, std::size_t random)
{
    std::vector<Vec3f> points;
    const MeshView m = mesh.view();
    for (std::uint32_t t = 0; t < m.triangle_count(); t += 1 + t % 3) {
        const Vec3f a = m.vertex(t, 0), b = m.vertex(t, 1), c = m.vertex(t, 2);
        points.push_back(a);
        points.push_back((a + b) * 0.5f);
        points.push_back((a + b + c) * (1.0f / 3.0f));
    }
    Aabb box = bounds(m);
    std::mt19937 rng(seed);
    for (int k = 0; k < 3; ++k) {
        const float e = box.extent(k);
        box.lower[k] -= e;
        box.upper[k] += e;
    }
    for (std::size_t k = 0; k < random; ++k) {
        Vec3f p;
        for (int a = 0; a < 3; ++a)
            p[a] = std::uniform_real_distribution<float>(box.lower[a], box.upper[a])(rng);
        points.push_back(p);
    }
    // Near the surface: random surface points moved a little off it.
    for (std::size_t k = 0; k < random; ++k) {
        const auto t = static_cast<std::uint32_t>(rng() % m.triangle_count());
        const float u = std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
        const float v = std::uniform_real_distribution<float>(0.0f, 1.0f - u)(rng);
        const Vec3f on = m.vertex(t, 0) * (1.0f - u - v) + m.vertex(t, 1) * u + m.vertex(t, 2) * v;
        const float off = 0.01f * box.extent(0) * std::uniform_real_distribution<float>(-1.0f, 1.0f)(rng);
        points.push_back(on + Vec3f{off, -off * 0.5f, off * 0.25f});
    }
    return points;
}

TEST(ClosestPoint, RandomTrianglesAgreeWithTheOracleNearAndFar)
{
    const Mesh mesh = random_triangles(61, 1500, Aabb{{0, 0, 0}, {10, 10, 10}}, 3.0f);
    expect_closest_points(mesh, probe_points(mesh, 62, 1500), "random triangles");
}

TEST(ClosestPoint, ClosedShapesAgreeWithTheOracleOnVerticesEdgesAndFaces)
{
    // Shared vertices and edges: points on them are equally close to several triangles, and
    // the smallest id must win in every structure.
    const Mesh cube = tessellated_cube(3);
    expect_closest_points(cube, probe_points(cube, 63, 500), "tessellated cube");
    const Mesh sphere = icosphere(2, 5.0f);
    expect_closest_points(sphere, probe_points(sphere, 64, 500), "icosphere");
}

TEST(ClosestPoint, MaxDistanceLeavesFarPointsWithoutAHit)
{
    const Mesh sphere = icosphere(2, 1.0f);
    const std::vector<Vec3f> points{{0, 0, 0}, {0.5f, 0, 0}, {3, 0, 0}, {0, -10, 0},
                                    {0.99f, 0.1f, 0}};
    const AllStructures built(sphere);
    for (const PointStructure& s : point_queries_of(built)) {
        std::vector<ClosestPoint> all(points.size()), within(points.size());
        s.closest(points, all, std::numeric_limits<float>::infinity());
        s.closest(points, within, 1.5f);
        for (std::size_t k = 0; k < points.size(); ++k) {
            const DistanceOracle e = distance_oracle(sphere.view(), points[k], 1e-12);
            if (e.distance <= 1.5) {
                EXPECT_EQ(within[k].triangle, all[k].triangle) << s.name << " point " << k;
                EXPECT_EQ(within[k].distance, all[k].distance) << s.name << " point " << k;
            } else {
                EXPECT_FALSE(within[k].is_hit()) << s.name << " point " << k;
                EXPECT_EQ(within[k].distance, std::numeric_limits<float>::infinity()) << s.name;
            }
        }
    }
}

TEST(ClosestPoint, NonFinitePointsGetNanAndNoHit)
{
    const Mesh cube = tessellated_cube(2);
    const AllStructures built(cube);
    const std::vector<Vec3f> points{{std::nanf(""), 0, 0}, {0, std::numeric_limits<float>::infinity(), 0}};
    for (const PointStructure& s : point_queries_of(built)) {
        std::vector<ClosestPoint> got(points.size());
        s.closest(points, got, std::numeric_limits<float>::infinity());
        for (const ClosestPoint& c : got) {
            EXPECT_FALSE(c.is_hit()) << s.name;
            EXPECT_TRUE(std::isnan(c.distance)) << s.name;
        }
    }
}

TEST(SignedDistance, IsNegativeExactlyInsideACubeAndASphere)
{
    for (const bool sphere_shape : {false, true}) {
        const Mesh mesh = sphere_shape ? icosphere(2, 2.0f) : tessellated_cube(4);
        const Aabb box = bounds(mesh.view());
        std::vector<Vec3f> points;
        for (int i = 0; i < 9; ++i)
            for (int j = 0; j < 9; ++j)
                for (int k = 0; k < 9; ++k) {
                    Vec3f p;
                    const int c[3] = {i, j, k};
                    for (int a = 0; a < 3; ++a)
                        p[a] = box.lower[a] - 0.3f + (box.extent(a) + 0.6f) * float(c[a]) / 8.0f;
                    points.push_back(p);
                }
        std::vector<float> inside;
        for (const Vec3f p : points) {
            if (sphere_shape) {
                // Inside the convex polyhedron: on the inner side of every face's plane.
                bool in = true;
                for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
                    const Vec3f a = mesh.view().vertex(t, 0);
                    const Vec3f n = cross(mesh.view().vertex(t, 1) - a, mesh.view().vertex(t, 2) - a);
                    in = in && dot(n, p - a) < 0.0f;
                }
                inside.push_back(in ? 1.0f : 0.0f);
            } else {
                auto in = [](float c) { return c > 0.0f && c < 4.0f; };
                inside.push_back(in(p.x) && in(p.y) && in(p.z) ? 1.0f : 0.0f);
            }
        }
        const AllStructures built(mesh);
        for (const PointStructure& s : point_queries_of(built)) {
            if (!s.signed_distance) continue;
            std::vector<float> got(points.size());
            s.signed_distance(points, got);
            std::size_t wrong = 0;
            for (std::size_t k = 0; k < points.size(); ++k) {
                const double d = distance_oracle(mesh.view(), points[k], 0.0).distance;
                const double expected = inside[k] == 1.0f ? -d : d;
                wrong += std::abs(got[k] - expected) <= 1e-5 * (1.0 + d) ? 0 : 1;
            }
            EXPECT_EQ(wrong, 0u) << (sphere_shape ? "icosphere, " : "cube, ") << s.name;
        }
    }
}

}  // namespace
}  // namespace sg::test
