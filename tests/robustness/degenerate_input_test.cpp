// Row 8 of docs/ROBUSTNESS.md: degenerate and tiny inputs, through the library and the .sg
// format. 0 triangles (an error at import, a valid empty structure in the library), one
// triangle, 100,000 copies of one triangle (bounded depth and node count, no endless
// splitting, also with the settings that split hardest), a fully coplanar axis-aligned scene,
// slivers and needles: each builds, passes both grid checkers, is written and read back
// unchanged (with the coverage check on), has statistics that match its arrays, and traces
// like brute force. tests/apps/sg_degenerate_test.cpp runs the same scenes through sg-build,
// sg-stats, sg-export and sg-trace.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "robustness_support.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/stats.hpp"
#include "splitgrid/validate.hpp"
#include "support/random_scene.hpp"
#include "support/scratch_dir.hpp"

namespace sg::test {
namespace {

struct Scene {
    std::string name;
    Mesh mesh;
};

Mesh single_triangle()
{
    Mesh m;
    m.vertices = {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
    m.triangles = {Triangle{{0, 1, 2}}};
    return m;
}

// Triangles of length 1 to 5 and height 1e-6 of that (slivers), or with two corners 1e-6
// apart (needles), in random orientations in a box of 10.
Mesh thin_triangles(std::uint32_t seed, std::size_t count, bool needles)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f);
    Mesh m;
    for (std::size_t t = 0; t < count; ++t) {
        const Vec3f a{10 * u(rng), 10 * u(rng), 10 * u(rng)};
        const Vec3f along = normalize(Vec3f{s(rng), s(rng), s(rng)});
        const Vec3f side = normalize(cross(along, Vec3f{s(rng), s(rng), s(rng)}));
        const float len = 1.0f + 4.0f * u(rng);
        const Vec3f b = a + along * len;
        const Vec3f c = needles ? b + side * (1e-6f * len)
                                : a + along * (len * u(rng)) + side * (1e-6f * len);
        const auto base = static_cast<std::uint32_t>(m.vertices.size());
        m.vertices.insert(m.vertices.end(), {a, b, c});
        m.triangles.push_back(Triangle{{base, base + 1, base + 2}});
    }
    return m;
}

std::vector<Scene> degenerate_scenes()
{
    std::vector<Scene> scenes;
    scenes.push_back({"empty", Mesh{}});
    scenes.push_back({"one triangle", single_triangle()});
    Mesh copies = single_triangle();
    copies.triangles.assign(100000, copies.triangles[0]);
    scenes.push_back({"100000 copies, shared corners", copies});
    Mesh separate;
    for (std::uint32_t t = 0; t < 100000; ++t) {
        separate.vertices.insert(separate.vertices.end(), {{0.5f, 0.0f, 0.25f}, {1.5f, 0.0f, 0.25f},
                                                           {0.5f, 2.0f, 0.25f}});
        separate.triangles.push_back(Triangle{{3 * t, 3 * t + 1, 3 * t + 2}});
    }
    scenes.push_back({"100000 copies, own corners", separate});
    // With the hardest settings the shared corners of a plane's triangles (each lattice
    // vertex is a fan that no split separates) are split until a cell has kept all of its
    // parent's triangles twice in a row: 9 to 10 nodes per triangle.
    scenes.push_back({"coplanar z = 3", axis_plane(2, 3.0f, 20)});
    scenes.push_back({"coplanar x = -2", axis_plane(0, -2.0f, 10)});
    scenes.push_back({"slivers", thin_triangles(91, 3000, false)});
    scenes.push_back({"needles", thin_triangles(92, 3000, true)});
    return scenes;
}

// About 2,500 rays, fewer for the 100,000 copies (brute force tests every copy).
std::vector<Ray> probe_rays(const Mesh& mesh, std::uint32_t seed)
{
    const std::size_t n = mesh.triangles.size() > 10000 ? 30 : 1000;
    Aabb box = mesh.triangles.empty() ? Aabb{{-1, -1, -1}, {1, 1, 1}} : bounds(mesh.view());
    for (int k = 0; k < 3; ++k) {
        const float margin = 0.25f * box.extent(k) + 1.0f;
        box.lower[k] -= margin;
        box.upper[k] += margin;
    }
    std::vector<Ray> rays = random_rays(seed, n, box);
    if (mesh.triangles.empty()) return rays;
    const auto aimed = rays_at_triangles(seed + 1, n, box, mesh.view());
    rays.insert(rays.end(), aimed.begin(), aimed.end());
    // Axis rays through corners, and rays in the plane of a flat scene.
    for (std::size_t k = 0; k < n / 3; ++k) {
        const Vec3f v = mesh.vertices[mesh.triangles[(k * 7919) % mesh.triangles.size()].v[k % 3]];
        const auto axis = static_cast<int>(k % 3);
        Ray r;
        r.origin = v;
        r.origin[axis] = box.lower[axis];
        r.direction[axis] = 1.0f;
        rays.push_back(r);
    }
    append_rays_in_plane(rays, 2, 3.0f, n / 6);
    return rays;
}

void check_scene(const Scene& scene, const BuildConfig& config, const char* config_name)
{
    SCOPED_TRACE(scene.name + ", " + config_name);
    const Mesh& mesh = scene.mesh;
    SplitGrid grid;
    const double seconds = seconds_of([&] { grid = build_checked(mesh, config); });

    // Statistics against the arrays they describe.
    const GridStats stats = compute_stats(grid);
    EXPECT_EQ(stats.triangle_count, mesh.triangles.size());
    EXPECT_EQ(stats.node_count, grid.nodes.size());
    EXPECT_EQ(stats.cell_count, grid.cell_count());
    EXPECT_EQ(stats.reference_count, counted_references(grid));
    EXPECT_EQ(stats.empty_cells + stats.leaf_cells + stats.inner_cells,
              grid.cell_count() + (grid.root.is_leaf() ? 1u : 0u));
    EXPECT_LE(stats.max_depth, config.max_depth);
    EXPECT_EQ(stats.structure_bytes, grid.memory_bytes());

    // Written and read back unchanged, with every check of the reader on.
    const ScratchDir dir;
    const SgContents contents{mesh, grid, scene.name};
    write_sg_file(dir / "scene.sg", contents);
    const SgContents back = read_sg_file(dir / "scene.sg", {.check_coverage = true});
    EXPECT_TRUE(back == contents);

    const std::vector<Ray> rays = probe_rays(mesh, 93);
    const OracleReport r = parallel_compare(back.grid, back.mesh.view(), rays);
    EXPECT_EQ(r.closest_disagreements, 0u) << r.first_failure;
    EXPECT_EQ(r.any_hit_disagreements, 0u) << r.first_failure;
    if (!mesh.triangles.empty()) {
        EXPECT_GT(r.hits, rays.size() / 10);
    }
    std::printf("[ tiny     ] %-30s %-8s %7zu triangles: %6zu nodes, depth %2u, %8zu references, "
                "build %.3f s; %zu rays, %zu hits, 0 disagreements\n",
                scene.name.c_str(), config_name, mesh.triangles.size(), grid.nodes.size(),
                stats.max_depth, stats.reference_count, seconds, r.rays, r.hits);
}

TEST(DegenerateInput, EveryTinyOrDegenerateSceneBuildsSavesLoadsTracesAndHasStats)
{
    for (const Scene& scene : degenerate_scenes()) {
        check_scene(scene, {}, "default");
        check_scene(scene, hardest_splitting(), "hardest");
    }
}

TEST(DegenerateInput, CopiesOfOneTriangleNeverSplit)
{
    // Every cell would receive every copy: no split makes progress, whatever the settings.
    for (const Scene& scene : degenerate_scenes()) {
        if (scene.name.find("copies") == std::string::npos) continue;
        for (const BuildConfig& config : {BuildConfig{}, hardest_splitting()}) {
            const SplitGrid grid = build_split_grid(scene.mesh.view(), config);
            EXPECT_TRUE(grid.root.is_leaf()) << scene.name;
            EXPECT_EQ(grid.nodes.size(), 0u) << scene.name;
            EXPECT_EQ(counted_references(grid), scene.mesh.triangles.size()) << scene.name;
        }
    }
}

TEST(DegenerateInput, EmptyMeshIsAValidEmptyStructureButAnErrorAtImport)
{
    const Mesh none;
    const SplitGrid grid = build_checked(none);
    EXPECT_TRUE(grid.root.is_empty());
    EXPECT_TRUE(grid.nodes.empty() && grid.cells.empty() && grid.leaf_words.empty());
    EXPECT_EQ(compute_stats(grid).node_count, 0u);

    // A file whose only face is degenerate, and one with vertices only: no triangle is left.
    const ScratchDir dir;
    write_text(dir / "degenerate.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    write_text(dir / "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for (const char* name : {"degenerate.obj", "points.obj"}) {
        try {
            (void)import_mesh(dir / name);
            ADD_FAILURE() << name << " was imported";
        } catch (const InputError& e) {
            const std::string m = e.what();
            EXPECT_EQ(m.rfind((dir / name).string() + ": ", 0), 0u) << m;
            if (std::string(name) == "degenerate.obj") {
                EXPECT_NE(m.find("no triangles"), std::string::npos) << m;
            }
        }
    }
}

}  // namespace
}  // namespace sg::test
