// End-to-end tests of sg-export: a model built by sg-build, exported, read back with VTK's own
// readers and compared with what sg-stats reports; the selection flags; the limit; bad input
// and failed writes leave nothing behind.

// sg-export and these tests exist only in builds with VTK (SG_WITH_VTK).
#ifdef SG_EXPORT_EXE

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstddef>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "support/vtk_readback.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// Builds Assimp's duck with sg-build into `scratch`/duck.sg.
fs::path build_duck(const ScratchDir& scratch)
{
    const fs::path model = assimp_model("Collada/duck.dae");
    EXPECT_TRUE(fs::exists(model)) << model << ": install assimp-testmodels";
    const fs::path sg = scratch / "duck.sg";
    const ToolRun run = run_tool(SG_BUILD_EXE, {model.string(), "-o", sg.string()}, scratch);
    EXPECT_EQ(run.exit_code, 0) << describe(run);
    return sg;
}

json stats_of(const fs::path& sg, const ScratchDir& scratch)
{
    const ToolRun run = run_tool(SG_STATS_EXE, {sg.string(), "--json"}, scratch);
    EXPECT_EQ(run.exit_code, 0) << describe(run);
    return json::parse(run.out).at("grid");
}

double sum(const std::vector<double>& values)
{
    double total = 0.0;
    for (double v : values) total += v;
    return total;
}

/// A failure message is exactly one line, "error: ...".
void expect_one_line_error(const ToolRun& run, const std::string& must_contain)
{
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_EQ(run.err.rfind("error: ", 0), 0u) << run.err;
    EXPECT_NE(run.err.find(must_contain), std::string::npos) << run.err;
    EXPECT_EQ(run.out, "");
}

TEST(SgExport, ExportOfBuiltModelMatchesSgStats)
{
    ScratchDir scratch;
    const fs::path sg = build_duck(scratch);
    const fs::path out = scratch / "out";
    const ToolRun run = run_tool(SG_EXPORT_EXE, {sg.string(), "-o", out.string(), "--json"}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const json summary = json::parse(run.out);
    const json grid = stats_of(sg, scratch);

    EXPECT_EQ(summary.at("schema_version"), 1);
    EXPECT_EQ(summary.at("vtm"), (out / "duck.vtm").string());
    const auto blocks = read_export(out / "duck.vtm");
    ASSERT_EQ(block_names(blocks), (std::vector<std::string>{"cells", "planes", "leaves", "mesh"}));

    const std::size_t nonempty = grid.at("cell_count").get<std::size_t>() -
                                 grid.at("empty_cells").get<std::size_t>();
    EXPECT_EQ(static_cast<std::size_t>(find_block(blocks, "cells")->GetNumberOfCells()), nonempty);
    EXPECT_EQ(find_block(blocks, "leaves")->GetNumberOfCells(), grid.at("leaf_cells").get<vtkIdType>());
    EXPECT_EQ(find_block(blocks, "planes")->GetNumberOfCells(),
              2 * grid.at("node_count").get<vtkIdType>());
    EXPECT_EQ(find_block(blocks, "mesh")->GetNumberOfCells(), grid.at("triangle_count").get<vtkIdType>());
    const double references = grid.at("reference_count").get<double>();
    EXPECT_EQ(sum(cell_values(find_block(blocks, "leaves"), "triangle_count")), references);
    EXPECT_EQ(sum(cell_values(find_block(blocks, "mesh"), "reference_count")), references);
    const std::vector<double> depth = cell_values(find_block(blocks, "cells"), "depth");
    EXPECT_EQ(*std::max_element(depth.begin(), depth.end()), grid.at("max_depth").get<double>());
    EXPECT_NEAR(field_number(find_block(blocks, "mesh"), "grid_expected_cost"),
                grid.at("sah_cost").get<double>(), 1e-9 * grid.at("sah_cost").get<double>());
    EXPECT_EQ(field_string(find_block(blocks, "cells"), "source_name"), "duck.dae");
    EXPECT_EQ(field_string(find_block(blocks, "cells"), "structure_name"), "duck.sg");

    // The JSON summary against the files.
    const json& counts = summary.at("counts");
    EXPECT_EQ(counts.at("cells"), nonempty);
    EXPECT_EQ(counts.at("leaves"), grid.at("leaf_cells"));
    EXPECT_EQ(counts.at("planes"), 2 * grid.at("node_count").get<std::size_t>());
    EXPECT_EQ(counts.at("mesh_triangles"), grid.at("triangle_count"));
    std::size_t total = 0;
    for (const json& file : summary.at("files")) {
        EXPECT_EQ(file.at("bytes"), fs::file_size(file.at("path").get<std::string>()));
        total += file.at("bytes").get<std::size_t>();
    }
    EXPECT_EQ(summary.at("files").size(), 5u);
    EXPECT_EQ(summary.at("total_bytes"), total);
    for (const std::string& name : scratch.entries())
        EXPECT_NE(name.front(), '.') << name << ": a staging folder was left behind";
}

TEST(SgExport, DepthPartsAndEmptyCellFlagsReachTheFiles)
{
    ScratchDir scratch;
    const fs::path sg = build_duck(scratch);
    const json grid = stats_of(sg, scratch);
    ASSERT_GE(grid.at("max_depth").get<int>(), 2);
    const fs::path out = scratch / "out";
    const ToolRun run =
        run_tool(SG_EXPORT_EXE,
                 {sg.string(), "-o", out.string(), "--min-depth", "1", "--max-depth", "1",
                  "--parts", "cells,planes", "--empty-cells"},
                 scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const auto blocks = read_export(out / "duck.vtm");
    ASSERT_EQ(block_names(blocks), (std::vector<std::string>{"cells", "planes"}));

    // Cells of all nodes at depth 1, empty ones included: their resolutions' sum.
    const double nodes = grid.at("nodes_per_depth").at(1).get<double>();
    const double mean_resolution = grid.at("mean_resolution_per_depth").at(1).get<double>();
    EXPECT_EQ(static_cast<double>(find_block(blocks, "cells")->GetNumberOfCells()),
              std::round(nodes * mean_resolution));
    EXPECT_EQ(static_cast<double>(find_block(blocks, "planes")->GetNumberOfCells()), 2 * nodes);
    for (const char* name : {"cells", "planes"}) {
        const std::vector<double> depth = cell_values(find_block(blocks, name), "depth");
        EXPECT_EQ(std::set<double>(depth.begin(), depth.end()), std::set<double>{1.0}) << name;
    }
    const std::vector<double> kind = cell_values(find_block(blocks, "cells"), "kind");
    EXPECT_NE(std::find(kind.begin(), kind.end(), 0.0), kind.end()) << "empty cells are there";
}

TEST(SgExport, SubtreeFlagSelectsANodeAndRefusesMissingOnes)
{
    ScratchDir scratch;
    const fs::path sg = build_duck(scratch);
    const json grid = stats_of(sg, scratch);
    const std::string past_last = std::to_string(grid.at("node_count").get<std::size_t>());
    const ToolRun bad = run_tool(SG_EXPORT_EXE, {sg.string(), "-o", (scratch / "x").string(), "--subtree", past_last}, scratch);
    EXPECT_EQ(bad.exit_code, 2) << describe(bad);
    expect_one_line_error(bad, "subtree node " + past_last + " does not exist");
    EXPECT_FALSE(fs::exists(scratch / "x"));

    const ToolRun run = run_tool(SG_EXPORT_EXE, {sg.string(), "-o", (scratch / "y").string(), "--subtree", "1", "--parts", "planes"}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const auto blocks = read_export(scratch / "y" / "duck.vtm");
    ASSERT_EQ(block_names(blocks), (std::vector<std::string>{"planes"}));
    const std::vector<double> nodes = cell_values(blocks[0].data, "node_id");
    EXPECT_EQ(*std::min_element(nodes.begin(), nodes.end()), 1.0) << "node 1 is the first node of its subtree";
    EXPECT_EQ(field_number(blocks[0].data, "export_subtree"), 1.0);
}

TEST(SgExport, OverTheLimitIsAUsageErrorThatSuggestsFlagsAndWritesNothing)
{
    ScratchDir scratch;
    const fs::path sg = build_duck(scratch);
    const std::vector<std::string> before = scratch.entries();
    // The root node alone has at most 16 cells (resolution_max), its leaves and two planes:
    // 200 fits depth 0.
    const ToolRun run = run_tool(SG_EXPORT_EXE, {sg.string(), "-o", (scratch / "out").string(), "--limit", "200"}, scratch);
    EXPECT_EQ(run.exit_code, 1) << describe(run);
    expect_one_line_error(run, "more than the limit of 200");
    EXPECT_NE(run.err.find("export fewer levels with --max-depth "), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("raise the limit with --limit "), std::string::npos) << run.err;

    const ToolRun tiny = run_tool(SG_EXPORT_EXE, {sg.string(), "-o", (scratch / "out").string(), "--limit", "1"}, scratch);
    EXPECT_EQ(tiny.exit_code, 1) << describe(tiny);
    expect_one_line_error(tiny, "even the shallowest depth holds");
    EXPECT_EQ(scratch.entries().size(), before.size() + 4) << "only the runs' stdout and stderr files";
    EXPECT_FALSE(fs::exists(scratch / "out"));
}

TEST(SgExport, BadInputIsOneLineAndLeavesNothing)
{
    ScratchDir scratch;
    write_text(scratch / "garbage.sg", "this is not a .sg file at all, just some text");
    struct Case {
        std::vector<std::string> args;
        int exit_code;
        std::string message;
    };
    const std::vector<Case> cases = {
        {{(scratch / "missing.sg").string(), "-o", (scratch / "a").string()}, 2, "missing.sg"},
        {{(scratch / "garbage.sg").string(), "-o", (scratch / "b").string()}, 2, "garbage.sg"},
        {{(scratch / "garbage.sg").string(), "-o", (scratch / "c").string(), "--parts", "cells,walls"}, 1, "walls"},
        {{(scratch / "garbage.sg").string(), "-o", (scratch / "d").string(), "--min-depth", "3", "--max-depth", "2"}, 1, "--min-depth 3"},
        {{(scratch / "garbage.sg").string(), "-o", (scratch / "e").string(), "--max-depth", "65"}, 1, "65"},
        {{(scratch / "garbage.sg").string(), "-o", (scratch / "f").string(), "--limit", "-1"}, 1, "-1"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.args[0] + " " + c.args.back());
        const ToolRun run = run_tool(SG_EXPORT_EXE, c.args, scratch);
        EXPECT_EQ(run.exit_code, c.exit_code) << describe(run);
        EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
        EXPECT_NE(run.err.find(c.message), std::string::npos) << run.err;
    }
    for (const std::string& name : scratch.entries())
        EXPECT_TRUE(name == "garbage.sg" || name.rfind("run", 0) == 0) << name << " left behind";
}

TEST(SgExport, ExistingOutputIsReplacedOnlyWithForceAndOnlyIfItIsAnExport)
{
    ScratchDir scratch;
    const fs::path sg = build_duck(scratch);
    const fs::path out = scratch / "out";
    const std::vector<std::string> planes_only = {sg.string(), "-o", out.string(), "--parts", "planes"};
    ASSERT_EQ(run_tool(SG_EXPORT_EXE, planes_only, scratch).exit_code, 0);
    const std::string vtm_before = read_text(out / "duck.vtm");

    std::vector<std::string> mesh_only = {sg.string(), "-o", out.string(), "--parts", "mesh"};
    const ToolRun refused = run_tool(SG_EXPORT_EXE, mesh_only, scratch);
    EXPECT_EQ(refused.exit_code, 2) << describe(refused);
    expect_one_line_error(refused, "--force");
    EXPECT_EQ(read_text(out / "duck.vtm"), vtm_before);

    mesh_only.push_back("--force");
    ASSERT_EQ(run_tool(SG_EXPORT_EXE, mesh_only, scratch).exit_code, 0);
    EXPECT_EQ(block_names(read_export(out / "duck.vtm")), (std::vector<std::string>{"mesh"}));

    fs::create_directory(scratch / "notes");
    write_text(scratch / "notes" / "todo.txt", "mine");
    const ToolRun never = run_tool(SG_EXPORT_EXE, {sg.string(), "-o", (scratch / "notes").string(), "--force"}, scratch);
    EXPECT_EQ(never.exit_code, 2) << describe(never);
    expect_one_line_error(never, "not an earlier export");
    EXPECT_EQ(folder_entries(scratch / "notes"), (std::vector<std::string>{"todo.txt"}));
}

TEST(SgExport, FailedWriteLeavesNoOutputAndNoStagingFolder)
{
    // A file size limit makes VTK's writers fail part-way, as a full disk would. SIGXFSZ is
    // ignored here (and so in the child) so that the write fails instead of killing the tool.
    const fs::path prlimit = "/usr/bin/prlimit";
    ASSERT_TRUE(fs::exists(prlimit)) << "prlimit (util-linux) is part of every Debian system";
    ScratchDir scratch;
    const fs::path sg = build_duck(scratch);
    const std::vector<std::string> before = scratch.entries();
    auto* const old_handler = std::signal(SIGXFSZ, SIG_IGN);
    // In the sanitizer tree, VTK leaks the header of the array whose write fails; the
    // suppression in tests/sanitizer/lsan.supp needs the slow unwinder to see VTK's frames.
    if (const char* lsan = std::getenv("LSAN_OPTIONS"))
        ::setenv("LSAN_OPTIONS", (std::string(lsan) + ":fast_unwind_on_malloc=0").c_str(), 1);
    const ToolRun run = run_tool(prlimit.string(), {"--fsize=20000", "--", SG_EXPORT_EXE, sg.string(), "-o", (scratch / "out").string()}, scratch);
    std::signal(SIGXFSZ, old_handler);
    EXPECT_EQ(run.exit_code, 2) << describe(run);
    expect_one_line_error(run, "writing the export failed, nothing was written");
    EXPECT_FALSE(fs::exists(scratch / "out"));
    EXPECT_EQ(scratch.entries().size(), before.size() + 2) << "only this run's stdout and stderr";
}

TEST(SgExport, HelpExplainsEveryFlagAndTheFiles)
{
    ScratchDir scratch;
    const ToolRun run = run_tool(SG_EXPORT_EXE, {"--help"}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    for (const char* text : {"--output", "--parts", "--min-depth", "--max-depth", "--subtree",
                             "--empty-cells", "--limit", "--force", "--json", ".vtm", ".vtu",
                             ".vtp", "depth", "node_id", "cell_index", "axis", "kind",
                             "triangle_count", "cost_share", "side", "cut_fraction",
                             "reference_count", "Exit codes:"})
        EXPECT_NE(run.out.find(text), std::string::npos) << text << " missing in\n" << run.out;
}

}  // namespace
}  // namespace sg::test

#endif  // SG_EXPORT_EXE
