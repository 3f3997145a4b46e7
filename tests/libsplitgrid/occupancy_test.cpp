// Inside or outside by the parity of exact crossings (occupancy.hpp), and the edge counts that
// say where parity is valid (mesh_edges.hpp), against shapes whose inside is known exactly.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "splitgrid/baselines/bvh.hpp"
#include "splitgrid/baselines/kd_tree.hpp"
#include "splitgrid/baselines/uniform_grid.hpp"
#include "splitgrid/brute_force.hpp"
#include "splitgrid/closed_shapes.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/mesh_edges.hpp"
#include "splitgrid/occupancy.hpp"
#include "support/crossings_oracle.hpp"
#include "support/oracle.hpp"
#include "support/random_scene.hpp"

namespace sg::test {
namespace {

/// Each structure's occupancy of `points`, compared with `inside` (1 or 0 per point).
void expect_occupancy(const Mesh& mesh, const std::vector<Vec3f>& points,
                      const std::vector<float>& inside, const std::string& what,
                      std::uint32_t nsamples = 1)
{
    const MeshView m = mesh.view();
    const SplitGrid grid = build_checked(mesh);
    const Bvh bvh = Bvh::build(m);
    const KdTree kd = KdTree::build(m);
    const UniformGrid uniform = UniformGrid::build(m);
    auto check = [&](const char* name, auto run) {
        std::vector<float> out(points.size(), -1.0f);
        run(out);
        std::size_t wrong = 0;
        std::string first;
        for (std::size_t k = 0; k < points.size(); ++k) {
            if (out[k] == inside[k]) continue;
            if (wrong++ == 0)
                first = "point " + std::to_string(k) + " (" + std::to_string(points[k].x) + " " +
                        std::to_string(points[k].y) + " " + std::to_string(points[k].z) +
                        "): " + std::to_string(out[k]);
        }
        EXPECT_EQ(wrong, 0u) << what << ", " << name << ", nsamples " << nsamples << ": " << first;
    };
    check("split grid", [&](std::vector<float>& out) {
        compute_occupancy(grid, m, points, std::span<float>(out), nsamples);
    });
    check("bvh", [&](std::vector<float>& out) { compute_occupancy(bvh, m, points, std::span<float>(out), nsamples); });
    check("kd-tree", [&](std::vector<float>& out) { compute_occupancy(kd, m, points, std::span<float>(out), nsamples); });
    check("uniform grid", [&](std::vector<float>& out) {
        compute_occupancy(uniform, m, points, std::span<float>(out), nsamples);
    });
}

TEST(Occupancy, PointsOnACubesGridLinesAndPlanesAreDecidedExactly)
{
    // Points on the planes, lines and vertices of the cube's tessellation (extended beyond the
    // cube), at 1/8 off a face: the rays from them run along grid lines and through vertices
    // of the surface. Inside iff strictly inside [0, n]^3 (no point lies on the surface).
    constexpr std::uint32_t n = 4;
    const Mesh cube = tessellated_cube(n);
    std::vector<Vec3f> points;
    std::vector<float> inside;
    const std::vector<float> coords{-1.0f, -0.125f, 0.125f, 1.0f, 2.0f, 2.5f, 3.0f, 3.875f, 4.125f, 5.0f};
    for (const float x : coords)
        for (const float y : coords)
            for (const float z : coords) {
                points.push_back({x, y, z});
                auto in = [](float c) { return c > 0.0f && c < float(n); };
                inside.push_back(in(x) && in(y) && in(z) ? 1.0f : 0.0f);
            }
    expect_occupancy(cube, points, inside, "tessellated cube");
    expect_occupancy(cube, points, inside, "tessellated cube", 3);
}

TEST(Occupancy, AGridAroundAnIcosphereIsDecidedExactly)
{
    // A 6 x 6 x 6 grid of points around an icosphere, and points just inside and outside each
    // vertex along the radius: inside iff on the inner side of every face's plane (the sphere
    // is convex; decided in double, exact enough: no point lies within 1e-5 of a plane).
    const Mesh sphere = icosphere(2, 1.0f);
    std::vector<Vec3f> points;
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            for (int k = 0; k < 6; ++k)
                points.push_back({-1.25f + 0.5f * float(i), -1.25f + 0.5f * float(j), -1.25f + 0.5f * float(k)});
    points.push_back({0, 0, 0});
    for (const Vec3f v : sphere.vertices) {
        points.push_back(v * 0.98f);
        points.push_back(v * 1.02f);
    }
    std::vector<float> inside;
    for (const Vec3f p : points) {
        const ConvexSide side = convex_side(sphere.view(), p);
        ASSERT_GT(side.nearest_plane, 1e-5) << "a test point lies too close to a face's plane";
        inside.push_back(side.inside ? 1.0f : 0.0f);
    }
    expect_occupancy(sphere, points, inside, "icosphere");
    expect_occupancy(sphere, points, inside, "icosphere", 5);
}

TEST(Occupancy, RefusesAnEvenNumberOfSamplesAndGivesNanForAnInvalidPoint)
{
    const Mesh cube = tessellated_cube(2);
    const SplitGrid grid = build_checked(cube);
    std::vector<Vec3f> points{{1, 1, 1}, {std::nanf(""), 1, 1},
                              {std::numeric_limits<float>::infinity(), 1, 1}, {9, 9, 9}};
    std::vector<float> out(points.size());
    EXPECT_THROW(compute_occupancy(grid, cube.view(), points, std::span<float>(out), 2), ConfigError);
    EXPECT_THROW(compute_occupancy(grid, cube.view(), points, std::span<float>(out), 0), ConfigError);
    compute_occupancy(grid, cube.view(), points, std::span<float>(out));
    EXPECT_EQ(out[0], 1.0f);
    EXPECT_TRUE(std::isnan(out[1]));
    EXPECT_TRUE(std::isnan(out[2]));
    EXPECT_EQ(out[3], 0.0f);
}

TEST(BruteForceOracles, WindingNumberAndHitCountKnowTheCubesInside)
{
    // The references sg-bench checks inside tests with: the winding number is 1 inside the
    // outward-wound cube, 0 outside and -1 inside the same cube wound inward; a ray from a
    // point inside crosses the surface once, from a point outside twice or never, also
    // through the tessellation's vertices and edges (every point here has integer or
    // half-integer coordinates, and the rays run along the axes).
    constexpr float n = 4.0f;
    const Mesh cube = tessellated_cube(4);
    Mesh inward = cube;
    for (Triangle& t : inward.triangles) std::swap(t.v[1], t.v[2]);
    const std::vector<float> coords{-1.0f, 0.5f, 1.0f, 2.0f, 2.5f, 3.5f, 5.0f};
    for (const float x : coords)
        for (const float y : coords)
            for (const float z : coords) {
                const auto in = [](float c) { return c > 0.0f && c < n; };
                const bool inside = in(x) && in(y) && in(z);
                const Vec3f p{x, y, z};
                EXPECT_NEAR(winding_number(cube.view(), sg::Vec3d(p)), inside ? 1.0 : 0.0, 1e-9)
                    << x << " " << y << " " << z;
                EXPECT_NEAR(winding_number(inward.view(), sg::Vec3d(p)), inside ? -1.0 : 0.0, 1e-9);
                for (int axis = 0; axis < 3; ++axis) {
                    Ray ray{p, {}};
                    ray.direction[axis] = 1.0f;
                    const std::int32_t count = count_intersections_brute_force(cube.view(), ray);
                    const bool crosses =
                        in(p[(axis + 1) % 3]) && in(p[(axis + 2) % 3]) && p[axis] < n;
                    const std::int32_t expected = inside ? 1 : (crosses ? 2 : 0);
                    EXPECT_EQ(count, expected) << x << " " << y << " " << z << " axis " << axis;
                }
            }
}

TEST(EdgeReport, CountsTheEdgesOfClosedOpenAndNonManifoldMeshes)
{
    // A closed genus-0 mesh has E = V + F - 2 edges (Euler), each shared by two triangles.
    for (const std::uint32_t n : {1u, 3u}) {
        const Mesh cube = tessellated_cube(n);
        const EdgeReport r = edge_report(cube.view());
        EXPECT_EQ(r.edges, cube.vertices.size() + cube.triangles.size() - 2);
        EXPECT_EQ(r.open_edges, 0u);
        EXPECT_EQ(r.nonmanifold_edges, 0u);
        EXPECT_TRUE(r.is_closed());
    }
    const Mesh sphere = icosphere(2, 3.0f);
    EXPECT_EQ(edge_report(sphere.view()).edges, sphere.vertices.size() + sphere.triangles.size() - 2);
    EXPECT_TRUE(edge_report(sphere.view()).is_closed());
    // A square of n x n quads has 4n boundary edges, each in one triangle.
    const Mesh plane = axis_plane(2, 0.0f, 5);
    EXPECT_EQ(edge_report(plane.view()).open_edges, 20u);
    EXPECT_FALSE(edge_report(plane.view()).is_closed());
    // The same cube with every triangle's corners copied (no shared vertex indices) is still
    // closed: vertices at one position are one vertex.
    Mesh unwelded;
    const Mesh cube = tessellated_cube(2);
    for (std::uint32_t t = 0; t < cube.triangles.size(); ++t) {
        const auto first = static_cast<std::uint32_t>(unwelded.vertices.size());
        for (int k = 0; k < 3; ++k) unwelded.vertices.push_back(cube.view().vertex(t, k));
        unwelded.triangles.push_back(Triangle{{first, first + 1, first + 2}});
    }
    EXPECT_EQ(edge_report(unwelded.view()), edge_report(cube.view()));
    // A fourth triangle on one edge of a tetrahedron's: one edge in three triangles (open and
    // non-manifold), two new edges open.
    Mesh tetra;
    tetra.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
    tetra.triangles = {Triangle{{0, 2, 1}}, Triangle{{0, 1, 3}}, Triangle{{1, 2, 3}},
                       Triangle{{0, 3, 2}}, Triangle{{0, 1, 4}}};
    const EdgeReport r = edge_report(tetra.view());
    EXPECT_EQ(r.edges, 8u);
    EXPECT_EQ(r.open_edges, 3u);
    EXPECT_EQ(r.nonmanifold_edges, 1u);
}

TEST(ClosedShapes, AreClosedOutwardWoundAndOfTheRightSize)
{
    // The divergence theorem: the signed volume of a closed outward-wound mesh is its volume.
    auto volume = [](const Mesh& m) {
        double v = 0.0;
        for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
            const Vec3f a = m.view().vertex(t, 0), b = m.view().vertex(t, 1), c = m.view().vertex(t, 2);
            v += (double(a.x) * (double(b.y) * c.z - double(b.z) * c.y) -
                  double(a.y) * (double(b.x) * c.z - double(b.z) * c.x) +
                  double(a.z) * (double(b.x) * c.y - double(b.y) * c.x)) / 6.0;
        }
        return v;
    };
    EXPECT_DOUBLE_EQ(volume(tessellated_cube(3)), 27.0);
    EXPECT_EQ(tessellated_cube(3).triangles.size(), 12u * 9u);
    const Mesh sphere = icosphere(4, 2.0f);
    EXPECT_EQ(sphere.triangles.size(), 20u * 256u);
    EXPECT_NEAR(volume(sphere), 4.0 / 3.0 * 3.14159265358979 * 8.0, 0.01 * 8 * 4.19);
    EXPECT_LT(volume(sphere), 4.0 / 3.0 * 3.14159265358979 * 8.0);
    EXPECT_THROW((void)tessellated_cube(0), ConfigError);
    EXPECT_THROW((void)icosphere(8, 1.0f), ConfigError);
    EXPECT_THROW((void)icosphere(1, -1.0f), ConfigError);
}

}  // namespace
}  // namespace sg::test
