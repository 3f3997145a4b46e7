// Inside or outside of real closed scans (../shared/meshes) near their vertices, where rays
// from the points run through vertices and edges, against the generalized winding number in
// double precision. Skips when the shared meshes are absent.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "splitgrid/baselines/bvh.hpp"
#include "splitgrid/brute_force.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "splitgrid/mesh_edges.hpp"
#include "splitgrid/occupancy.hpp"
#include "support/crossings_oracle.hpp"
#include "support/oracle.hpp"
#include "support/shared_meshes.hpp"

namespace sg {
namespace {

class RealClosedMesh : public ::testing::TestWithParam<const char*> {};

TEST_P(RealClosedMesh, PointsNearVerticesAlongAxesAndDiagonalsAreDecidedExactly)
{
    const std::filesystem::path path = std::filesystem::path(SG_SHARED_MESHES_DIR) / GetParam();
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent (no ../shared/meshes)";
    const Mesh mesh = import_mesh(path).mesh;
    const EdgeReport edges = edge_report(mesh.view());
    ASSERT_TRUE(edges.is_closed()) << edges.open_edges << " open edges";
    const Aabb box = bounds(mesh.view());
    const double diagonal = std::sqrt(double(box.extent(0)) * box.extent(0) +
                                      double(box.extent(1)) * box.extent(1) +
                                      double(box.extent(2)) * box.extent(2));
    // Along the axes (the direction occupancy's first ray takes is an axis: these points' rays
    // run through the vertex) and the diagonals.
    std::vector<Vec3f> directions;
    for (int k = 0; k < 3; ++k)
        for (const float s : {1.0f, -1.0f}) {
            Vec3f d{};
            d[k] = s;
            directions.push_back(d);
        }
    for (const float x : {1.0f, -1.0f})
        for (const float y : {1.0f, -1.0f})
            for (const float z : {1.0f, -1.0f}) directions.push_back(normalize(Vec3f{x, y, z}));
    std::vector<Vec3f> points;
    const std::size_t step = std::max<std::size_t>(1, mesh.vertices.size() / 120);
    for (std::size_t v = 0; v < mesh.vertices.size(); v += step)
        for (const Vec3f d : directions)
            for (const double distance : {1e-2, 1e-3, 1e-4})
                points.push_back(mesh.vertices[v] + d * static_cast<float>(distance * diagonal));
    std::vector<float> expected;
    std::size_t inside = 0;
    for (const Vec3f p : points) {
        const double w = winding_number(mesh.view(), Vec3d(p));
        ASSERT_LT(std::min(std::abs(w), std::abs(w - 1.0)), 1e-6) << "winding number " << w;
        expected.push_back(w > 0.5 ? 1.0f : 0.0f);
        inside += w > 0.5 ? 1 : 0;
    }
    EXPECT_GT(inside, points.size() / 5);
    EXPECT_LT(inside, points.size() * 4 / 5);

    const SplitGrid grid = test::build_checked(mesh);
    const Bvh bvh = Bvh::build(mesh.view());
    std::vector<float> from_grid(points.size()), from_bvh(points.size());
    compute_occupancy(grid, mesh.view(), points, std::span<float>(from_grid));
    compute_occupancy(bvh, mesh.view(), points, std::span<float>(from_bvh));
    std::size_t wrong_grid = 0, wrong_bvh = 0;
    for (std::size_t k = 0; k < points.size(); ++k) {
        wrong_grid += from_grid[k] == expected[k] ? 0 : 1;
        wrong_bvh += from_bvh[k] == expected[k] ? 0 : 1;
    }
    EXPECT_EQ(wrong_grid, 0u) << "of " << points.size();
    EXPECT_EQ(wrong_bvh, 0u) << "of " << points.size();
}

INSTANTIATE_TEST_SUITE_P(SharedMeshes, RealClosedMesh,
                         ::testing::Values("scanned/bunny_npm.obj",
                                           "scanned/stanford_dragon_vrip_res4.ply"),
                         test::mesh_test_name);

}  // namespace
}  // namespace sg
