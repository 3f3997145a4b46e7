// Tests of weld_identical_vertices (formats/src/vertex_weld.cpp) and of the welding that
// import_mesh does. The oracles are independent of the code under test: the set of distinct
// bit patterns among the corners, the corner positions triangle by triangle, binary STL files
// written here byte by byte, and the hits of a grid built over the unwelded soup.

#include "splitgrid/formats/vertex_weld.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "file_helpers.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "splitgrid/traverse.hpp"
#include "support/oracle.hpp"
#include "support/random_scene.hpp"
#include "support/triangle_soup.hpp"

namespace sg {
namespace {

/// Same number of triangles, and every corner of triangle i at the same bits in both.
void expect_same_corners(const Mesh& expected, const Mesh& actual)
{
    ASSERT_EQ(actual.triangles.size(), expected.triangles.size());
    for (std::size_t t = 0; t < expected.triangles.size(); ++t)
        for (int c = 0; c < 3; ++c)
            ASSERT_EQ(
                test::position_bits(actual.view().vertex(static_cast<std::uint32_t>(t), c)),
                test::position_bits(expected.view().vertex(static_cast<std::uint32_t>(t), c)))
                << "triangle " << t << " corner " << c;
}

void expect_no_two_vertices_alike(const Mesh& mesh)
{
    std::set<test::PositionBits> seen;
    for (const Vec3f& p : mesh.vertices) EXPECT_TRUE(seen.insert(test::position_bits(p)).second);
}

/// Traces the same rays through grids built over both meshes: hits must be identical,
/// bit for bit (triangle id, t, u, v).
void expect_same_hits(const Mesh& expected, const Mesh& actual, std::uint32_t seed)
{
    const SplitGrid expected_grid = test::build_checked(expected);
    const SplitGrid actual_grid = test::build_checked(actual);
    const std::vector<Ray> rays = test::rays_at_triangles(seed, 3000, bounds(expected.view()),
                                                          expected.view());
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit a = intersect(expected_grid, expected.view(), rays[i]);
        const Hit b = intersect(actual_grid, actual.view(), rays[i]);
        ASSERT_EQ(a.triangle, b.triangle) << "ray " << i;
        ASSERT_EQ(std::bit_cast<std::uint32_t>(a.t), std::bit_cast<std::uint32_t>(b.t));
        ASSERT_EQ(std::bit_cast<std::uint32_t>(a.u), std::bit_cast<std::uint32_t>(b.u));
        ASSERT_EQ(std::bit_cast<std::uint32_t>(a.v), std::bit_cast<std::uint32_t>(b.v));
        hits += a.is_hit() ? 1 : 0;
    }
    EXPECT_GT(hits, rays.size() / 2) << "the rays must test something";
}

TEST(VertexWeld, MergesExactlyTheBitIdenticalPositionsInFirstOccurrenceOrder)
{
    const float one_ulp_above_1 = std::nextafter(1.0f, 2.0f);
    Mesh mesh;
    mesh.vertices = {
        {1, 2, 3},                // 0
        {4, 5, 6},                // 1
        {1, 2, 3},                // 2: same bits as 0
        {one_ulp_above_1, 2, 3},  // 3: one unit in the last place from 0: kept apart
        {-0.0f, 0, 0},            // 4: -0.0 is not +0.0 bit for bit: kept apart
        {0, 0, 0},                // 5
        {7, 8, 9},                // 6: no triangle uses it: removed
        {4, 5, 6},                // 7: same bits as 1
        {0, 1, 0},                // 8
    };
    mesh.triangles = {{{2, 1, 3}}, {{4, 5, 8}}, {{7, 0, 5}}};
    const Mesh before = mesh;

    const WeldReport report = weld_identical_vertices(mesh);
    EXPECT_EQ(report.vertices_before, 8u);
    EXPECT_EQ(report.vertices_after, 6u);
    const std::vector<Vec3f> expected_vertices = {{1, 2, 3},     {4, 5, 6},
                                                  {one_ulp_above_1, 2, 3}, {-0.0f, 0, 0},
                                                  {0, 0, 0},     {0, 1, 0}};
    ASSERT_EQ(mesh.vertices.size(), expected_vertices.size());
    for (std::size_t v = 0; v < expected_vertices.size(); ++v)
        EXPECT_EQ(test::position_bits(mesh.vertices[v]), test::position_bits(expected_vertices[v]))
            << "vertex " << v;
    EXPECT_EQ(mesh.triangles, (std::vector<Triangle>{{{0, 1, 2}}, {{3, 4, 5}}, {{1, 0, 4}}}));
    expect_same_corners(before, mesh);
}

TEST(VertexWeld, NanIsWeldedOnlyWithTheSameBits)
{
    // import_mesh drops non-finite triangles first; the function itself still follows the
    // bit-identical rule for NaN, whose == is always false.
    const float quiet_nan = std::numeric_limits<float>::quiet_NaN();
    const float other_nan = std::bit_cast<float>(std::bit_cast<std::uint32_t>(quiet_nan) | 1u);
    Mesh mesh;
    mesh.vertices = {{quiet_nan, 0, 0}, {quiet_nan, 0, 0}, {other_nan, 0, 0}};
    mesh.triangles = {{{0, 1, 2}}};
    const WeldReport report = weld_identical_vertices(mesh);
    EXPECT_EQ(report.vertices_after, 2u);
    EXPECT_EQ(mesh.triangles[0], (Triangle{{0, 0, 1}}));
}

TEST(VertexWeld, ASoupWeldsToItsDistinctPositionsAndTracesTheSame)
{
    Mesh mesh = test::uv_sphere({0.5f, -1.0f, 2.0f}, 3.0f, 24, 40);
    test::append(mesh, test::random_triangles(11, 200, {{-4, -5, -2}, {5, 3, 6}}, 0.8f));
    const Mesh soup = test::soup_of(mesh);
    Mesh welded = soup;
    const WeldReport report = weld_identical_vertices(welded);
    EXPECT_EQ(report.vertices_before, soup.vertices.size());
    EXPECT_EQ(report.vertices_after, test::distinct_corner_positions(soup));
    EXPECT_EQ(welded.vertices.size(), report.vertices_after);
    EXPECT_LT(welded.vertices.size(), soup.vertices.size() / 2) << "the sphere shares corners";
    expect_no_two_vertices_alike(welded);
    expect_same_corners(soup, welded);
    expect_same_hits(soup, welded, 5);
}

TEST(VertexWeld, RefusesAnIndexPastTheVertexArray)
{
    Mesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.triangles = {{{0, 1, 2}}, {{0, 1, 3}}};
    try {
        (void)weld_identical_vertices(mesh);
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("triangle 1 has vertex index 3"), std::string::npos)
            << e.what();
    }
}

TEST(MeshImportWelding, BinaryStlSoupIsWeldedWithoutMovingACorner)
{
    // A closed sphere, random triangles, and a strip whose corners lie one unit in the last
    // place apart, which Assimp's JoinIdenticalVertices (a tolerance of four units) would
    // have merged into one vertex.
    Mesh mesh = test::uv_sphere({10.0f, 0.0f, -3.0f}, 2.0f, 16, 24);
    test::append(mesh, test::random_triangles(3, 500, {{5, -4, -8}, {15, 4, 2}}, 1.0f));
    Mesh close;
    const float x1 = std::nextafter(12.0f, 13.0f);
    // And -0.0 next to +0.0, which are equal as numbers but not bit for bit.
    close.vertices = {{12, 3, 1}, {x1, 3, 1}, {12, 4, 1}, {x1, 4, 1.5f},
                      {-0.0f, 5, 5}, {0.0f, 5, 5}, {1, 5, 5}, {0, 6, 5}};
    close.triangles = {{{0, 1, 2}}, {{1, 3, 2}}, {{4, 6, 7}}, {{5, 7, 6}}};
    test::append(mesh, close);
    const Mesh soup = test::soup_of(mesh);

    test::ScratchDir scratch;
    const std::filesystem::path stl = scratch / "soup.stl";
    test::write_binary_stl(stl, soup);
    const ImportedMesh imported = import_mesh(stl);

    EXPECT_EQ(imported.report.triangles_read, soup.triangles.size());
    EXPECT_EQ(imported.report.vertices_before_welding, soup.vertices.size());
    EXPECT_EQ(imported.report.vertices, test::distinct_corner_positions(soup));
    EXPECT_EQ(imported.mesh.vertices.size(), imported.report.vertices);
    expect_no_two_vertices_alike(imported.mesh);
    expect_same_corners(soup, imported.mesh);
    expect_same_hits(soup, imported.mesh, 9);
}

TEST(MeshImportWelding, DroppedTrianglesAreTheSameAsWithoutWelding)
{
    // Zero-area triangles (two corners with the same bits) among good ones: the same ones are
    // dropped as without welding, the rest keep their order and corners.
    Mesh soup;
    soup.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},     // good
                     {0, 0, 0}, {1, 0, 0}, {1, 0, 0},     // zero area
                     {1, 0, 0}, {1, 1, 0}, {0, 1, 0},     // good, shares two positions
                     {2, 2, 2}, {3, 2, 2}, {2, 2, 2}};    // zero area
    for (std::uint32_t t = 0; t < 4; ++t) soup.triangles.push_back({{3 * t, 3 * t + 1, 3 * t + 2}});
    test::ScratchDir scratch;
    test::write_binary_stl(scratch / "some_degenerate.stl", soup);
    const ImportedMesh imported = import_mesh(scratch / "some_degenerate.stl");
    EXPECT_EQ(imported.report.degenerate_dropped, 2u);
    Mesh kept;
    kept.vertices = soup.vertices;
    kept.triangles = {soup.triangles[0], soup.triangles[2]};
    expect_same_corners(kept, imported.mesh);
    EXPECT_EQ(imported.report.vertices_before_welding, 6u);
    EXPECT_EQ(imported.report.vertices, 4u);
}

TEST(MeshImportWelding, ObjWithNormalsIsWeldedToItsPositions)
{
    // The Tachikoma's OBJ lists 21,803 positions ('v' lines, each used and distinct) and
    // 30,421 normals; the import used to keep 63,499 vertices, one per position and normal.
    const std::filesystem::path path =
        std::filesystem::path(SG_SHARED_MESHES_DIR) / "models/tachikoma.obj";
    if (!std::filesystem::exists(path))
        GTEST_SKIP() << path << " is absent: ../shared/meshes exists only on development "
                                "machines and in CI";
    const ImportedMesh imported = import_mesh(path);
    EXPECT_EQ(imported.mesh.triangles.size(), 43'606u);
    EXPECT_EQ(imported.report.vertices_before_welding, 3 * 43'606u);
    EXPECT_EQ(imported.report.vertices, 21'803u);
    EXPECT_EQ(test::distinct_corner_positions(imported.mesh), 21'803u);
    expect_no_two_vertices_alike(imported.mesh);
}

}  // namespace
}  // namespace sg
