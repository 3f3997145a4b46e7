// The comparison structures (uniform grid, kd-tree, BVH) on real scanned meshes
// (../shared/meshes) against brute force over all triangles, computed once per ray and shared by
// the three. Skips when the shared meshes are absent.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "splitgrid/baselines/bvh.hpp"
#include "splitgrid/baselines/kd_tree.hpp"
#include "splitgrid/baselines/uniform_grid.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "splitgrid/traverse.hpp"
#include "support/oracle.hpp"
#include "support/random_scene.hpp"

namespace sg {
namespace {

struct Expected {
    Hit closest;
    bool any = false;
};

// Counts the rays on which `s` disagrees with the brute-force answers; names the first.
template <class S>
std::size_t disagreements(const S& s, const MeshView& mesh, const std::vector<Ray>& rays,
                          const std::vector<Expected>& expected, std::string& first)
{
    std::size_t bad = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const bool ok = test::same_closest_hit(expected[i].closest, s.intersect(mesh, rays[i])) &&
                        s.occluded(mesh, rays[i]) == expected[i].any;
        if (!ok && bad++ == 0) first = "ray " + std::to_string(i);
    }
    return bad;
}

TEST(RealMeshBaselines, AllThreeAgreeWithBruteForce)
{
    const std::filesystem::path path =
        std::filesystem::path(SG_SHARED_MESHES_DIR) / "scanned/stanford_dragon_vrip_res4.ply";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent (no ../shared/meshes)";
    const ImportedMesh imported = import_mesh(path);
    const MeshView mesh = imported.mesh.view();
    Aabb box = bounds(mesh);
    // Origins in the box widened by half its size: rays from outside and inside.
    for (int k = 0; k < 3; ++k) {
        const float margin = 0.5f * box.extent(k);
        box.lower[k] -= margin;
        box.upper[k] += margin;
    }
    auto rays = test::rays_at_triangles(1, 2000, box, mesh);
    const auto random = test::random_rays(2, 1000, box);
    rays.insert(rays.end(), random.begin(), random.end());
    std::vector<Expected> expected(rays.size());
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        expected[i] = Expected{intersect_brute_force(mesh, rays[i]), occluded_brute_force(mesh, rays[i])};
        hits += expected[i].closest.is_hit() ? 1 : 0;
    }
    ASSERT_GT(hits, 1500u);

    std::string first;
    EXPECT_EQ(disagreements(UniformGrid::build(mesh), mesh, rays, expected, first), 0u) << first;
    EXPECT_EQ(disagreements(KdTree::build(mesh), mesh, rays, expected, first), 0u) << first;
    EXPECT_EQ(disagreements(Bvh::build(mesh), mesh, rays, expected, first), 0u) << first;
}

}  // namespace
}  // namespace sg
