// Row 8 of docs/ROBUSTNESS.md through the tools: degenerate and tiny meshes as OBJ files go
// through sg-build, sg-stats, sg-export and sg-trace. A file without a usable triangle is
// refused by sg-build with one line naming it; one triangle, 100,000 copies of one triangle
// (also with the flags that split hardest), a coplanar axis-aligned plane, slivers and
// needles build, and their files report statistics, export and trace like brute force.
// (tests/robustness/degenerate_input_test.cpp checks the same through the library.)

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "support/leaf_triangles.hpp"
#include "splitgrid/formats/ray_file.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/traverse.hpp"
#include "support/random_scene.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Slivers (height 1e-4 of their length) or needles (two corners 1e-4 apart), lengths 1 to 5.
Mesh thin(std::uint32_t seed, bool needles)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Mesh m;
    for (std::uint32_t t = 0; t < 500; ++t) {
        const Vec3f a{10 * u(rng), 10 * u(rng), 10 * u(rng)};
        const float len = 1.0f + 4.0f * u(rng);
        const Vec3f b = a + Vec3f{len, 0.3f * len * u(rng), 0.2f * len};
        const Vec3f c = needles ? b + Vec3f{0.0f, 0.0f, 1e-4f * len}
                                : a + (b - a) * u(rng) + Vec3f{0.0f, 0.0f, 1e-4f * len};
        m.vertices.insert(m.vertices.end(), {a, b, c});
        m.triangles.push_back(Triangle{{3 * t, 3 * t + 1, 3 * t + 2}});
    }
    return m;
}

struct Case {
    std::string name;
    Mesh mesh;
    std::vector<std::string> flags;
};

std::vector<Case> buildable_cases()
{
    Mesh one;
    one.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    one.triangles = {Triangle{{0, 1, 2}}};
    Mesh copies = one;
    copies.triangles.assign(100000, one.triangles[0]);
    const std::vector<std::string> hardest{"--leaf-size",          "1", "--max-depth", "64",
                                           "--no-progress-fraction", "1", "--no-stop-by-cost",
                                           "--min-cell-width",     "0"};
    return {{"one", one, {}},
            {"copies", copies, {}},
            {"copies_hardest", copies, hardest},
            {"coplanar", axis_plane(1, 2.0f, 40), {}},
            {"slivers", thin(1, false), {}},
            {"needles", thin(2, true), {}}};
}

TEST(SgDegenerate, FilesWithoutAUsableTriangleAreRefusedInOneLine)
{
    for (const auto& [name, text] :
         std::vector<std::pair<std::string, std::string>>{
             {"points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"},
             {"collinear.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"},
             {"repeated.obj", "v 0 0 0\nv 1 0 0\nf 1 2 2\nf 2 2 2\n"}}) {
        SCOPED_TRACE(name);
        ScratchDir scratch;
        write_text(scratch / name, text);
        const ToolRun run =
            run_tool(SG_BUILD_EXE, {(scratch / name).string(), "-o", (scratch / "x.sg").string()},
                     scratch);
        EXPECT_EQ(run.exit_code, 2) << describe(run);
        EXPECT_EQ(run.err.rfind("error: ", 0), 0u) << run.err;
        EXPECT_NE(run.err.find(name), std::string::npos) << run.err;
        EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
        EXPECT_FALSE(fs::exists(scratch / "x.sg"));
    }
}

TEST(SgDegenerate, TinyAndDegenerateMeshesBuildReportExportAndTrace)
{
    for (const Case& c : buildable_cases()) {
        SCOPED_TRACE(c.name);
        ScratchDir scratch;
        const fs::path obj = scratch / (c.name + ".obj");
        const fs::path sg = scratch / (c.name + ".sg");
        write_text(obj, obj_of(c.mesh));
        std::vector<std::string> args{obj.string(), "-o", sg.string()};
        args.insert(args.end(), c.flags.begin(), c.flags.end());
        const ToolRun build = run_tool(SG_BUILD_EXE, args, scratch);
        ASSERT_EQ(build.exit_code, 0) << describe(build);
        const SgContents contents = read_sg_file(sg, {.check_coverage = true});
        EXPECT_EQ(contents.mesh.triangles.size(), c.mesh.triangles.size());

        const ToolRun stats =
            run_tool(SG_STATS_EXE, {sg.string(), "--json", "--coverage"}, scratch);
        ASSERT_EQ(stats.exit_code, 0) << describe(stats);
        const json grid = json::parse(stats.out).at("grid");
        EXPECT_EQ(grid.at("triangle_count"), c.mesh.triangles.size());
        EXPECT_EQ(grid.at("node_count"), contents.grid.nodes.size());
        EXPECT_EQ(grid.at("reference_count"), test::counted_references(contents.grid));
        if (c.name.rfind("copies", 0) == 0) {
            EXPECT_EQ(grid.at("node_count"), 0u) << "copies of one triangle must never split";
        }
#ifdef SG_EXPORT_EXE
        const ToolRun exported =
            run_tool(SG_EXPORT_EXE, {sg.string(), "-o", (scratch / "export").string()}, scratch);
        ASSERT_EQ(exported.exit_code, 0) << describe(exported);
        EXPECT_TRUE(fs::exists(scratch / "export" / (c.name + ".vtm")));
#endif
        const MeshView mesh = contents.mesh.view();
        Aabb box = bounds(mesh);
        for (int k = 0; k < 3; ++k) {
            box.lower[k] -= 1.0f;
            box.upper[k] += 1.0f;
        }
        std::vector<Ray> rays = rays_at_triangles(3, 300, box, mesh);
        const auto random = random_rays(4, 200, box);
        rays.insert(rays.end(), random.begin(), random.end());
        write_ray_file(scratch / "rays.bin", rays);
        const ToolRun trace = run_tool(SG_TRACE_EXE,
                                       {sg.string(), "--rays", (scratch / "rays.bin").string(),
                                        "--out", (scratch / "hits.bin").string()},
                                       scratch);
        ASSERT_EQ(trace.exit_code, 0) << describe(trace);
        const std::vector<Hit> hits = read_hit_file(scratch / "hits.bin");
        ASSERT_EQ(hits.size(), rays.size());
        std::size_t wrong = 0, hit_count = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const Hit expected = intersect_brute_force(mesh, rays[i]);
            hit_count += expected.is_hit() ? 1 : 0;
            wrong += (expected.is_hit() != hits[i].is_hit() ||
                      (expected.is_hit() && expected.t != hits[i].t))
                         ? 1
                         : 0;
        }
        EXPECT_EQ(wrong, 0u);
        EXPECT_GT(hit_count, 100u);
    }
}

}  // namespace
}  // namespace sg::test
