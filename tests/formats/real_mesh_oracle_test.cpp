// Traversal on real scanned and modelled meshes (../shared/meshes) against brute force over
// all triangles. Skips when the shared meshes are absent.

#include <gtest/gtest.h>

#include <filesystem>

#include "splitgrid/formats/mesh_import.hpp"
#include "support/oracle.hpp"
#include "support/shared_meshes.hpp"
#include "support/random_scene.hpp"

namespace sg {
namespace {

class RealMesh : public ::testing::TestWithParam<const char*> {};

TEST_P(RealMesh, ClosestAndAnyHitAgreeWithBruteForce)
{
    const std::filesystem::path path = std::filesystem::path(SG_SHARED_MESHES_DIR) / GetParam();
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent (no ../shared/meshes)";
    const ImportedMesh imported = import_mesh(path);
    const Mesh& mesh = imported.mesh;
    const SplitGrid grid = test::build_checked(mesh);
    Aabb box = bounds(mesh.view());
    // Origins in the box widened by half its size: rays from outside and inside.
    for (int k = 0; k < 3; ++k) {
        const float margin = 0.5f * box.extent(k);
        box.lower[k] -= margin;
        box.upper[k] += margin;
    }
    auto rays = test::rays_at_triangles(1, 3000, box, mesh.view());
    const auto random = test::random_rays(2, 2000, box);
    rays.insert(rays.end(), random.begin(), random.end());
    const test::OracleReport r = test::compare_with_brute_force(grid, mesh.view(), rays);
    EXPECT_EQ(r.closest_disagreements, 0u) << r.first_failure;
    EXPECT_EQ(r.any_hit_disagreements, 0u) << r.first_failure;
    EXPECT_GT(r.hits, 2000u);
}

INSTANTIATE_TEST_SUITE_P(SharedMeshes, RealMesh,
                         ::testing::Values("scanned/stanford_dragon_vrip_res4.ply",
                                           "scanned/bunny_npm.obj", "models/teapot.obj",
                                           "gltf/smallpine/scene.gltf",
                                           "scenes/crytek_sponza_columns_shrubbery_part.obj",
                                           "scenes/mountain.obj"),
                         test::mesh_test_name);

}  // namespace
}  // namespace sg
