// End-to-end tests of sg-stats' edge counts: the text line and the JSON object `edges` against
// edges counted here with an ordered map over the mesh read back from the .sg file, on
// tessellated cubes (closed, and opened or made non-manifold here) and on the shared scanned
// meshes whose closedness is known (skipped when ../shared/meshes is absent).

#include <filesystem>
#include <ostream>
#include <string>

#include "app_test_support.hpp"
#include "splitgrid/closed_shapes.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "support/edge_oracle.hpp"
#include "support/shared_meshes.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// The text line sg-stats prints for `edges`.
std::string edges_line(const EdgeCounts& edges)
{
    return "edges           " + std::to_string(edges.edges) + " (" +
           std::to_string(edges.open_edges) + " open: shared by an odd number of triangles; " +
           std::to_string(edges.nonmanifold_edges) + " non-manifold: by more than two): " +
           (edges.open_edges == 0 ? "closed" : "not closed") + "\n";
}

/// Runs sg-stats on `sg_file` as text and as JSON and checks both against the edges counted
/// here on the mesh the file holds; returns whether sg-stats calls the mesh closed.
bool check_edges(const fs::path& sg_file, const ScratchDir& scratch)
{
    const EdgeCounts expected = count_edges(read_sg_file(sg_file).mesh);
    const ToolRun text = run_tool(SG_STATS_EXE, {sg_file.string()}, scratch);
    EXPECT_EQ(text.exit_code, 0) << describe(text);
    EXPECT_NE(text.out.find(edges_line(expected)), std::string::npos)
        << "expected " << edges_line(expected) << "in\n"
        << text.out;
    const ToolRun run = run_tool(SG_STATS_EXE, {sg_file.string(), "--json"}, scratch);
    EXPECT_EQ(run.exit_code, 0) << describe(run);
    const json edges = json::parse(run.out).at("edges");
    EXPECT_EQ(edges.at("edges"), expected.edges);
    EXPECT_EQ(edges.at("open_edges"), expected.open_edges);
    EXPECT_EQ(edges.at("nonmanifold_edges"), expected.nonmanifold_edges);
    EXPECT_EQ(edges.at("closed"), expected.open_edges == 0);
    return edges.at("closed").get<bool>();
}

class SgStatsEdges : public ::testing::Test {
protected:
    fs::path build(const Mesh& mesh, const std::string& name)
    {
        const fs::path obj = scratch_ / (name + ".obj");
        const fs::path sg_file = scratch_ / (name + ".sg");
        write_text(obj, obj_of(mesh));
        const ToolRun run = run_tool(SG_BUILD_EXE, {obj.string(), "-o", sg_file.string()},
                                     scratch_);
        EXPECT_EQ(run.exit_code, 0) << describe(run);
        return sg_file;
    }

    ScratchDir scratch_;
};

TEST_F(SgStatsEdges, TessellatedCubeIsClosedAndStopsBeingSoWhenCut)
{
    const Mesh cube = tessellated_cube(3);
    EXPECT_TRUE(check_edges(build(cube, "cube"), scratch_));
    EXPECT_EQ(count_edges(cube).edges, 18u * 3u * 3u) << "premise: 12 n^2 triangles, 3 edges "
                                                         "each, two triangles per edge";

    Mesh cut = cube;
    cut.triangles.erase(cut.triangles.begin() + 4);
    EXPECT_FALSE(check_edges(build(cut, "cut"), scratch_));

    // A face's triangle twice: three edges shared by three triangles.
    Mesh doubled = cube;
    doubled.triangles.push_back(doubled.triangles[0]);
    ASSERT_EQ(count_edges(doubled).nonmanifold_edges, 3u);
    EXPECT_FALSE(check_edges(build(doubled, "doubled"), scratch_));

    // A second copy of every triangle: every edge shared by four, closed and non-manifold.
    Mesh twice = cube;
    twice.triangles.insert(twice.triangles.end(), cube.triangles.begin(), cube.triangles.end());
    ASSERT_EQ(count_edges(twice).nonmanifold_edges, count_edges(twice).edges);
    EXPECT_TRUE(check_edges(build(twice, "twice"), scratch_));
}

struct SharedMeshCase {
    const char* path;
    bool closed;
};

/// How gtest and ctest show a case: its path, not its bytes.
void PrintTo(const SharedMeshCase& c, std::ostream* out)
{
    *out << c.path << (c.closed ? " (closed)" : " (open)");
}

std::string shared_case_name(const ::testing::TestParamInfo<SharedMeshCase>& param_info)
{
    return mesh_test_name({param_info.param.path, param_info.index});
}

class SgStatsEdgesShared : public ::testing::TestWithParam<SharedMeshCase> {};

TEST_P(SgStatsEdgesShared, ClosedMeshesAreSaidClosedAndOpenOnesOpen)
{
    const fs::path mesh = shared_mesh(GetParam().path);
    SG_SKIP_WITHOUT_SHARED_MESH(mesh);
    ScratchDir scratch;
    const fs::path sg_file = scratch / "mesh.sg";
    const ToolRun build = run_tool(SG_BUILD_EXE, {mesh.string(), "-o", sg_file.string(), "-q"},
                                   scratch);
    ASSERT_EQ(build.exit_code, 0) << describe(build);
    EXPECT_EQ(check_edges(sg_file, scratch), GetParam().closed);
}

INSTANTIATE_TEST_SUITE_P(
    SharedMeshes, SgStatsEdgesShared,
    ::testing::Values(SharedMeshCase{"scanned/stanford_dragon_vrip.ply", true},
                      SharedMeshCase{"scanned/stanford_dragon_vrip_res2.ply", true},
                      SharedMeshCase{"scanned/stanford_dragon_vrip_res4.ply", true},
                      SharedMeshCase{"scanned/igea_triangles.ply", true},
                      SharedMeshCase{"scanned/nefertiti.obj", true},
                      SharedMeshCase{"scanned/bunny_npm.obj", true},
                      SharedMeshCase{"scanned/stanford_bunny.obj", false},
                      SharedMeshCase{"scanned/lionstatue.obj", false},
                      SharedMeshCase{"models/teapot.obj", false}),
    shared_case_name);

}  // namespace
}  // namespace sg::test
