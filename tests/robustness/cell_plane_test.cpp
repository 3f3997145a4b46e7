// Row 3 of docs/ROBUSTNESS.md: rays in or along cell planes. For a random sample of the built
// structure's nodes at every depth, on their bounding planes and on some of their cell
// boundaries: rays that start on the plane and lie in it (the crossing component +0.0 and
// -0.0) and rays that start on it and cross it; and rays along +-x, +-y, +-z exactly through
// vertices, starting outside the scene or on the vertex. Every answer must equal brute force
// and every ray's work must stay within the bound of row 10 (no hang).
// (tests/libsplitgrid/traverse_test.cpp has the smaller version on the first nodes only.)

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <random>

#include "adversarial_rays.hpp"
#include "robustness_support.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "support/random_scene.hpp"

namespace sg::test {
namespace {

void check_plane_rays(const Mesh& mesh, const BuildConfig& config, std::uint32_t seed)
{
    const SplitGrid grid = build_checked(mesh, config);
    ASSERT_GT(grid.nodes.size(), 10u);
    const PlaneRays planes = rays_on_planes(grid, seed, pick_size(400, 4000));
    std::vector<Ray> rays = planes.rays;
    const auto axis_rays =
        axis_rays_through_vertices(mesh, grid.root_box, seed + 1, pick_size(6000, 60000));
    rays.insert(rays.end(), axis_rays.begin(), axis_rays.end());

    const OracleReport r = parallel_compare(grid, mesh.view(), rays);
    EXPECT_EQ(r.closest_disagreements, 0u) << r.first_failure;
    EXPECT_EQ(r.any_hit_disagreements, 0u) << r.first_failure;
    EXPECT_GT(r.hits, rays.size() / 10) << "the rays should hit something";

    const WorkBound bound(grid);
    const MeshView view = mesh.view();
    const std::size_t over = parallel_count(rays.size(), [&](std::size_t i) {
        TraversalCounters closest, any;
        (void)intersect(grid, view, rays[i], &closest);
        (void)occluded(grid, view, rays[i], &any);
        return !bound.holds(closest) || !bound.holds(any);
    });
    EXPECT_EQ(over, 0u) << "rays whose work exceeds the bound of row 10";
    std::printf("[ planes   ] %zu nodes (deepest at depth %u), %zu planes, %zu plane rays, %zu "
                "axis rays through vertices: %zu disagreements, %zu hits\n",
                planes.nodes, planes.deepest, planes.planes, planes.rays.size(), axis_rays.size(),
                r.closest_disagreements + r.any_hit_disagreements, r.hits);
}

TEST(CellPlanes, RandomSoupAgreesWithBruteForceOnAndAlongPlanes)
{
    const Mesh mesh = random_triangles(31, 3000, Aabb{{0, 0, 0}, {10, 10, 10}}, 1.0f);
    check_plane_rays(mesh, {}, 32);
}

TEST(CellPlanes, AxisAlignedLatticeAgreesWithBruteForceOnAndAlongPlanes)
{
    // Triangles in axis planes at integer coordinates, where vertices, edges and cell planes
    // line up with the axis rays.
    Mesh mesh;
    for (int axis = 0; axis < 3; ++axis)
        for (int offset = 0; offset <= 12; offset += 3)
            append(mesh, axis_plane(axis, static_cast<float>(offset), 12));
    BuildConfig config;
    config.leaf_size = 4;
    check_plane_rays(mesh, config, 33);
}

TEST(CellPlanes, RealMeshAgreesWithBruteForceOnAndAlongPlanes)
{
    const std::filesystem::path path =
        std::filesystem::path(SG_SHARED_MESHES_DIR) / "scanned/bunny_npm.obj";
    if (!std::filesystem::exists(path))
        GTEST_SKIP() << path << " is absent: ../shared/meshes exists only on development "
                                "machines and in CI";
    const Mesh mesh = import_mesh(path).mesh;
    check_plane_rays(mesh, {}, 34);
}

}  // namespace
}  // namespace sg::test
