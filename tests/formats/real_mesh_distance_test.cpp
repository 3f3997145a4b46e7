// Closest points and signed distances on real meshes (../shared/meshes) against the
// independent double-precision oracle over all triangles (support/distance_oracle.hpp), for
// random points in and around the scene's box and points near the surface. Skips when the
// shared meshes are absent.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <vector>

#include "splitgrid/baselines/bvh.hpp"
#include "splitgrid/closest_point.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "support/distance_oracle.hpp"
#include "support/oracle.hpp"
#include "support/shared_meshes.hpp"

namespace sg {
namespace {

class RealMeshDistance : public ::testing::TestWithParam<const char*> {};

TEST_P(RealMeshDistance, ClosestPointsAgreeWithTheOracle)
{
    const std::filesystem::path path = std::filesystem::path(SG_SHARED_MESHES_DIR) / GetParam();
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent (no ../shared/meshes)";
    const Mesh mesh = import_mesh(path).mesh;
    const MeshView m = mesh.view();
    Aabb box = bounds(m);
    double magnitude = 0.0;
    for (int k = 0; k < 3; ++k) {
        const float e = 0.25f * box.extent(k);
        box.lower[k] -= e;
        box.upper[k] += e;
        magnitude = std::max({magnitude, std::abs(double(box.lower[k])), std::abs(double(box.upper[k]))});
    }
    std::mt19937 rng(7);
    std::vector<Vec3f> points;
    for (int k = 0; k < 400; ++k) {
        Vec3f p;
        for (int a = 0; a < 3; ++a)
            p[a] = std::uniform_real_distribution<float>(box.lower[a], box.upper[a])(rng);
        points.push_back(p);
    }
    for (int k = 0; k < 400; ++k) {  // on and just off the surface, and on vertices
        const auto t = static_cast<std::uint32_t>(rng() % m.triangle_count());
        const float off = 1e-3f * box.extent(1) * std::uniform_real_distribution<float>(-1.0f, 1.0f)(rng);
        const Vec3f on = k % 4 == 0 ? m.vertex(t, 0) : (m.vertex(t, 0) + m.vertex(t, 1) + m.vertex(t, 2)) * (1.0f / 3.0f);
        points.push_back(on + Vec3f{off, off, -off});
    }
    const SplitGrid grid = test::build_checked(mesh);
    const Bvh bvh = Bvh::build(m);
    std::vector<ClosestPoint> from_grid(points.size()), from_bvh(points.size());
    closest_points(grid, m, points, std::span<ClosestPoint>(from_grid));
    closest_points(bvh, m, points, std::span<ClosestPoint>(from_bvh));
    std::size_t wrong = 0;
    double worst = 0.0;
    for (std::size_t k = 0; k < points.size(); ++k) {
        const double tol = 0x1p-40 * 3.0 * magnitude;
        const test::DistanceOracle e = test::distance_oracle(m, points[k], tol);
        for (const ClosestPoint& c : {from_grid[k], from_bvh[k]}) {
            // The error in units of the allowed one: the tolerance plus half a float ulp of the
            // distance (the rounding of the double result to float).
            const double allowed = tol + 0x1p-24 * e.distance;
            const double error = std::abs(double(c.distance) - e.distance) / allowed;
            worst = std::max(worst, error);
            wrong += error <= 1.0 && c.triangle == e.nearest.front() ? 0 : 1;
        }
    }
    EXPECT_EQ(wrong, 0u) << "of " << 2 * points.size() << "; worst error " << worst;
    std::printf("%s: %zu answers checked, worst distance error %.3g of the allowed "
                "(2^-40 (M + |p|) plus half a float ulp of the distance)\n",
                GetParam(), 2 * points.size(), worst);
}

INSTANTIATE_TEST_SUITE_P(SharedMeshes, RealMeshDistance,
                         ::testing::Values("scanned/stanford_dragon_vrip_res4.ply",
                                           "scanned/bunny_npm.obj", "models/teapot.obj",
                                           "gltf/smallpine/scene.gltf"),
                         test::mesh_test_name);

}  // namespace
}  // namespace sg
