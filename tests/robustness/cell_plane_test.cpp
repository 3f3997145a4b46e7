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

#include "robustness_support.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "support/random_scene.hpp"

namespace sg::test {
namespace {

struct PlaneRays {
    std::vector<Ray> rays;
    std::size_t planes = 0;
    std::size_t nodes = 0;
    std::uint32_t deepest = 0;
};

// Rays on the planes of `node_count` nodes drawn at random from every node of the grid.
PlaneRays rays_on_planes(const SplitGrid& grid, std::uint32_t seed, std::size_t node_count)
{
    const std::vector<NodeBox> boxes = node_boxes(grid);
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> pick(0, boxes.size() - 1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::uniform_real_distribution<float> dir(-1.0f, 1.0f);
    PlaneRays out;
    for (std::size_t n = 0; n < node_count; ++n) {
        const NodeBox& nb = boxes[pick(rng)];
        const GridNode& node = grid.nodes[nb.node];
        const int axis = node.axis();
        const CellMath cm(node.lo, node.hi, node.resolution());
        ++out.nodes;
        out.deepest = std::max(out.deepest, nb.depth);
        // Both bounding planes and up to two interior boundaries.
        std::vector<float> planes{node.lo, node.hi};
        if (node.resolution() > 1) {
            std::uniform_int_distribution<std::uint32_t> inner(1, node.resolution() - 1);
            planes.push_back(cm.boundary(inner(rng)));
            planes.push_back(cm.boundary(inner(rng)));
        }
        for (const float plane : planes) {
            ++out.planes;
            for (int rep = 0; rep < 6; ++rep) {
                Ray r;
                for (int k = 0; k < 3; ++k)
                    r.origin[k] = nb.box.lower[k] + u(rng) * nb.box.extent(k);
                r.origin[axis] = plane;
                r.direction = {dir(rng), dir(rng), dir(rng)};
                if (rep == 0) r.direction[axis] = 0.0f;   // in the plane
                if (rep == 1) r.direction[axis] = -0.0f;  // in the plane, negative zero
                if (rep == 2) {                            // in the plane, along an axis
                    r.direction = {};
                    const int other = (rng() & 1) != 0 ? 1 : 2;
                    r.direction[(axis + other) % 3] = (rng() & 1) != 0 ? 1.0f : -1.0f;
                }
                // rep 3..5: starting on the plane and crossing it, either way.
                if (r.direction == Vec3f{}) r.direction[(axis + 1) % 3] = 1.0f;
                out.rays.push_back(r);
            }
        }
    }
    return out;
}

// Axis-aligned rays exactly through random vertices: +-x, +-y, +-z in turn, half of them
// starting outside the scene box and half on the vertex itself.
std::vector<Ray> axis_rays_through_vertices(const Mesh& mesh, const Aabb& box, std::uint32_t seed,
                                            std::size_t count)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> pick(0, mesh.triangles.size() - 1);
    std::vector<Ray> rays;
    for (std::size_t k = 0; k < count; ++k) {
        const Triangle& t = mesh.triangles[pick(rng)];
        const Vec3f v = mesh.vertices[t.v[k % 3]];
        const auto axis = static_cast<int>((k / 2) % 3);
        const bool forward = k % 2 == 0;
        Ray r;
        r.origin = v;
        r.direction = {};
        r.direction[axis] = forward ? 1.0f : -1.0f;
        if ((k / 6) % 2 == 0) {
            const float margin = box.extent(axis) + 1.0f;
            r.origin[axis] = forward ? box.lower[axis] - margin : box.upper[axis] + margin;
        }
        rays.push_back(r);
    }
    return rays;
}

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
