// End-to-end tests of sg-build: real Assimp test models in several formats, the summary and
// JSON output checked against the file read back and an independent import, and bad inputs.

#include <cctype>
#include <cstddef>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "splitgrid/build_config.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/stats.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "support/changed_config.hpp"
#include "support/leaf_triangles.hpp"
#include "support/one_cell_nodes.hpp"

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// Number of references stored in the leaves of `grid`, counted from the cells themselves.
std::size_t count_leaf_references(const SplitGrid& grid)
{
    std::size_t refs = grid.root.is_leaf() ? leaf_triangles(grid, grid.root).size() : 0;
    for (const GridNode& node : grid.nodes)
        for (std::uint32_t i = 0; i < node.resolution(); ++i)
            if (const CellRef cell = node_cell(grid, node, i); cell.is_leaf())
                refs += leaf_triangles(grid, cell).size();
    return refs;
}

class SgBuildModel : public ::testing::TestWithParam<std::string> {};

TEST_P(SgBuildModel, BuildsFileMatchingIndependentImport)
{
    const fs::path model = assimp_model(GetParam());
    ASSERT_TRUE(fs::exists(model)) << model << ": install assimp-testmodels";
    ScratchDir scratch;
    const fs::path out = scratch / "model.sg";

    const ToolRun run = run_tool(SG_BUILD_EXE, {model.string(), "-o", out.string(), "--json"},
                                 scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    ASSERT_TRUE(fs::exists(out));

    // Independent paths: the library's own import of the same file, and the file read back
    // with every check (including coverage: every triangle in every cell it overlaps).
    const ImportedMesh imported = import_mesh(model);
    SgReadOptions read_options;
    read_options.check_coverage = true;
    const SgContents contents = read_sg_file(out, read_options);
    EXPECT_EQ(contents.mesh.triangles.size(), imported.mesh.triangles.size());
    EXPECT_EQ(contents.mesh, imported.mesh) << "the file must hold the imported mesh as is";
    EXPECT_EQ(contents.grid.triangle_count, imported.mesh.triangles.size());
    EXPECT_EQ(contents.source_name, model.filename().string());
    EXPECT_EQ(contents.grid.config, BuildConfig{});

    const json j = json::parse(run.out);
    EXPECT_EQ(j.at("schema_version"), 1);
    EXPECT_EQ(j.at("output"), out.string());
    const json& imp = j.at("import");
    EXPECT_EQ(imp.at("triangles_kept"), imported.mesh.triangles.size());
    EXPECT_EQ(imp.at("vertices"), imported.mesh.vertices.size());
    EXPECT_EQ(imp.at("triangles_read"), imported.report.triangles_read);
    EXPECT_EQ(imp.at("points_skipped"), imported.report.points_skipped);
    EXPECT_EQ(imp.at("lines_skipped"), imported.report.lines_skipped);
    EXPECT_EQ(imp.at("nonfinite_dropped"), imported.report.nonfinite_dropped);
    EXPECT_EQ(imp.at("degenerate_dropped"), imported.report.degenerate_dropped);
    // Triangles read = kept + dropped: nothing vanishes without being counted.
    EXPECT_EQ(imported.report.triangles_read,
              imported.mesh.triangles.size() + imported.report.nonfinite_dropped +
                  imported.report.degenerate_dropped);

    const json& grid = j.at("grid");
    EXPECT_EQ(grid.at("triangle_count"), contents.mesh.triangles.size());
    EXPECT_EQ(grid.at("node_count"), contents.grid.nodes.size());
    EXPECT_EQ(grid.at("cell_count"), contents.grid.cell_count());
    EXPECT_EQ(grid.at("reference_count"), test::counted_references(contents.grid));
    EXPECT_EQ(grid.at("reference_count"), count_leaf_references(contents.grid));
    EXPECT_EQ(grid.at("structure_bytes"), contents.grid.memory_bytes());
    EXPECT_EQ(grid.at("max_depth"), compute_stats(contents.grid).max_depth);
    EXPECT_EQ(j.at("file").at("bytes"), fs::file_size(out));
    EXPECT_DOUBLE_EQ(j.at("file").at("bytes_per_triangle").get<double>(),
                     static_cast<double>(fs::file_size(out)) /
                         static_cast<double>(contents.mesh.triangles.size()));
    const json& config = j.at("build_config");
    EXPECT_EQ(config.at("leaf_size"), BuildConfig{}.leaf_size);
    EXPECT_EQ(config.at("resolution_max"), BuildConfig{}.resolution_max);
}

// One model per format family Assimp reads, including models with line and point
// primitives among the triangles (spider.obj, Spider_binary.stl), node transforms and
// instancing (2CylinderEngine.glb, teapots.DAE).
INSTANTIATE_TEST_SUITE_P(AssimpTestModels, SgBuildModel,
                         ::testing::Values("OBJ/spider.obj", "OBJ/WusonOBJ.obj", "PLY/Wuson.ply",
                                           "STL/Spider_binary.stl", "OFF/Wuson.off",
                                           "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
                                           "Collada/duck.dae", "Collada/teapots.DAE",
                                           "3DS/fels.3ds"),
                         [](const ::testing::TestParamInfo<std::string>& param_info) {
                             std::string name = fs::path(param_info.param).filename().string();
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

TEST(SgBuild, TextSummaryReportsCountsOfTheFile)
{
    const fs::path model = assimp_model("OFF/Wuson.off");
    ASSERT_TRUE(fs::exists(model));
    ScratchDir scratch;
    const fs::path out = scratch / "wuson.sg";
    const ToolRun run = run_tool(SG_BUILD_EXE, {model.string(), "-o", out.string()}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const SgContents contents = read_sg_file(out);
    const std::string kept = std::to_string(contents.mesh.triangles.size()) + " kept";
    const std::string nodes = std::to_string(contents.grid.nodes.size()) + " nodes";
    const std::string refs = std::to_string(test::counted_references(contents.grid)) + " references";
    for (const std::string& text : {kept, nodes, refs, std::string("bytes/triangle"),
                                    std::string("build"), out.string()})
        EXPECT_NE(run.out.find(text), std::string::npos) << text << " missing in\n" << run.out;
    // stdout is for results: nothing of the summary goes to stderr, and no error is logged.
    EXPECT_EQ(run.err.find("error"), std::string::npos) << run.err;
}

TEST(SgBuild, BuildFlagsReachTheFile)
{
    const fs::path model = assimp_model("Collada/duck.dae");
    ASSERT_TRUE(fs::exists(model));
    ScratchDir scratch;
    const fs::path out = scratch / "duck.sg";
    const BuildConfig wanted = test::every_field_changed(false);
    const auto text = [](auto value) {
        std::ostringstream s;
        s << value;
        return s.str();
    };
    const ToolRun run = run_tool(
        SG_BUILD_EXE,
        {model.string(), "-o", out.string(), "--resolution-min", text(wanted.resolution_min),
         "--resolution-max", text(wanted.resolution_max), "--resolution-sigma",
         text(wanted.resolution_sigma), "--leaf-size", text(wanted.leaf_size), "--max-depth",
         text(wanted.max_depth), "--no-progress-fraction", text(wanted.no_progress_fraction),
         "--min-cell-width", text(wanted.min_cell_width), "--no-stop-by-cost",
         "--no-bounding-planes", "--no-bounding-nodes", "--no-clip-triangles", "--threads",
         text(wanted.threads), "-q"},
        scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    EXPECT_EQ(run.err, "") << "nothing to warn about, and -q hides the rest";
    const SgContents contents = read_sg_file(out);
    BuildConfig expected = wanted;
    expected.threads = 0;  // not kept: the result does not depend on it
    EXPECT_EQ(contents.grid.config, expected);
    const GridStats stats = compute_stats(contents.grid);
    EXPECT_LE(stats.max_depth, wanted.max_depth);
    // The min-cell-width cap may lower a resolution below --resolution-min, never raise it
    // above --resolution-max.
    std::size_t above_max = 0;
    for (const GridNode& node : contents.grid.nodes)
        if (node.resolution() > wanted.resolution_max) ++above_max;
    EXPECT_EQ(above_max, 0u);

    // Without the cap, every resolution lies in [--resolution-min, --resolution-max], but for
    // the one-cell bounding nodes.
    const fs::path uncapped = scratch / "uncapped.sg";
    ASSERT_EQ(run_tool(SG_BUILD_EXE,
                       {model.string(), "-o", uncapped.string(), "--resolution-min", "3",
                        "--resolution-max", "16", "--min-cell-width", "0", "-q"},
                       scratch)
                  .exit_code,
              0);
    std::size_t outside = 0;
    for (const GridNode& node : read_sg_file(uncapped).grid.nodes)
        if (node.resolution() != 1u && (node.resolution() < 3u || node.resolution() > 16u)) ++outside;
    EXPECT_EQ(outside, 0u);
}

TEST(SgBuild, PosterPresetBuildsThePostersNodesAndFlagsOverrideIt)
{
    const fs::path model = assimp_model("Collada/duck.dae");
    ASSERT_TRUE(fs::exists(model));
    ScratchDir scratch;
    auto build = [&](const std::string& name, std::vector<std::string> flags) {
        const fs::path out = scratch / (name + ".sg");
        std::vector<std::string> args{model.string(), "-o", out.string(), "-q"};
        args.insert(args.end(), flags.begin(), flags.end());
        const ToolRun run = run_tool(SG_BUILD_EXE, args, scratch);
        EXPECT_EQ(run.exit_code, 0) << describe(run);
        return read_sg_file(out).grid;
    };
    const SplitGrid poster = build("poster", {"--preset", "poster"});
    BuildConfig expected;
    expected.bounding_nodes = false;
    expected.stop_by_cost = false;
    expected.threads = 0;
    EXPECT_EQ(poster.config, expected);
    // Only the split rule's nodes: no one-cell node anywhere (the default makes many here).
    EXPECT_EQ(one_cell_node_count(poster), 0u);
    EXPECT_GT(one_cell_node_count(build("default", {"--preset", "default"})), 0u);

    // A flag given with the preset wins, before or after it on the command line.
    for (const auto& flags : {std::vector<std::string>{"--preset", "poster", "--bounding-nodes"},
                              std::vector<std::string>{"--bounding-nodes", "--preset", "poster"}}) {
        const SplitGrid mixed = build("mixed", flags);
        EXPECT_TRUE(mixed.config.bounding_nodes);
        EXPECT_FALSE(mixed.config.stop_by_cost);
    }

    const fs::path bad = scratch / "bad.sg";
    const ToolRun run = run_tool(SG_BUILD_EXE,
                                 {model.string(), "-o", bad.string(), "--preset", "fastest"}, scratch);
    EXPECT_EQ(run.exit_code, 1) << describe(run);  // a usage error
    EXPECT_NE(run.err.find("--preset"), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(bad));
}

TEST(SgBuild, SameGridForOneAndFourThreads)
{
    const fs::path model = assimp_model("PLY/Wuson.ply");
    ASSERT_TRUE(fs::exists(model));
    ScratchDir scratch;
    const fs::path one = scratch / "one.sg";
    const fs::path four = scratch / "four.sg";
    ASSERT_EQ(run_tool(SG_BUILD_EXE, {model.string(), "-o", one.string(), "--threads", "1"},
                       scratch).exit_code, 0);
    ASSERT_EQ(run_tool(SG_BUILD_EXE, {model.string(), "-o", four.string(), "--threads", "4"},
                       scratch).exit_code, 0);
    // The thread count is not part of the result: the files must be byte-identical.
    auto bytes = [](const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        return std::vector<char>(std::istreambuf_iterator<char>(in), {});
    };
    const std::vector<char> a = bytes(one);
    EXPECT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == bytes(four)) << "the file must not depend on the thread count";
}

TEST(SgBuild, VerboseLogsDebugDetails)
{
    const fs::path model = assimp_model("OFF/Cube.off");
    ASSERT_TRUE(fs::exists(model));
    ScratchDir scratch;
    const ToolRun run = run_tool(
        SG_BUILD_EXE, {model.string(), "-o", (scratch / "c.sg").string(), "-v"}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    EXPECT_NE(run.err.find("debug: "), std::string::npos) << run.err;
}

TEST(SgBuild, ReportsSkippedPrimitivesAsWarnings)
{
    // testmixed.obj holds points and lines besides its triangles; the user must hear about
    // them, with the counts the importer gives.
    const fs::path model = assimp_model("OBJ/testmixed.obj");
    ASSERT_TRUE(fs::exists(model));
    const ImportReport report = import_mesh(model).report;
    ASSERT_GT(report.points_skipped, 0u) << "test premise: the model has points";
    ASSERT_GT(report.lines_skipped, 0u) << "test premise: the model has lines";
    ScratchDir scratch;
    const ToolRun run = run_tool(
        SG_BUILD_EXE, {model.string(), "-o", (scratch / "m.sg").string()}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const std::string expected = "warning: " + model.string() + ": skipped " +
                                 std::to_string(report.points_skipped) + " point and " +
                                 std::to_string(report.lines_skipped) + " line primitives";
    EXPECT_NE(run.err.find(expected), std::string::npos) << expected << "\nmissing in\n" << run.err;
}

TEST(SgBuild, ReportsDroppedTrianglesAsWarnings)
{
    // spider.obj has zero-area triangles (Assimp's own "assimp info" shows them as lines).
    const fs::path model = assimp_model("OBJ/spider.obj");
    ASSERT_TRUE(fs::exists(model));
    const ImportedMesh imported = import_mesh(model);
    ASSERT_GT(imported.report.degenerate_dropped, 0u) << "test premise: degenerate triangles";
    ScratchDir scratch;
    const ToolRun run = run_tool(
        SG_BUILD_EXE, {model.string(), "-o", (scratch / "s.sg").string()}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const std::string expected =
        "dropped " + std::to_string(imported.report.degenerate_dropped) + " zero-area";
    EXPECT_NE(run.err.find(expected), std::string::npos) << expected << "\nmissing in\n" << run.err;
    EXPECT_NE(run.out.find(std::to_string(imported.report.degenerate_dropped) + " dropped"),
              std::string::npos)
        << run.out;
    // -q hides the summary (the result is the file) but never a warning: the same warning,
    // and nothing else.
    const ToolRun quiet = run_tool(
        SG_BUILD_EXE, {model.string(), "-o", (scratch / "q.sg").string(), "-q"}, scratch);
    ASSERT_EQ(quiet.exit_code, 0) << describe(quiet);
    EXPECT_EQ(quiet.out, "");
    EXPECT_EQ(quiet.err, "warning: " + model.string() + ": " + expected + " triangles\n");
    EXPECT_TRUE(fs::exists(scratch / "q.sg"));
}

// --- bad inputs: exit code 2, a message naming the file, and no output file ---

struct BadInputCase {
    std::string name;
    std::string file_name;  ///< created in the scratch folder unless `missing`
    std::string content;
    bool missing = false;

    // Test names print as the case name (GoogleTest would otherwise dump raw bytes).
    friend void PrintTo(const BadInputCase& c, std::ostream* os) { *os << c.name; }
};

class SgBuildBadInput : public ::testing::TestWithParam<BadInputCase> {};

TEST_P(SgBuildBadInput, ExitsTwoNamesFileAndLeavesNoOutput)
{
    const BadInputCase& c = GetParam();
    ScratchDir scratch;
    const fs::path input = scratch / c.file_name;
    if (!c.missing) write_text(input, c.content);
    const fs::path out = scratch / "out.sg";

    const ToolRun run = run_tool(SG_BUILD_EXE, {input.string(), "-o", out.string()}, scratch);
    EXPECT_EQ(run.exit_code, 2) << describe(run);
    EXPECT_NE(run.err.find("error: "), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(c.file_name), std::string::npos) << "stderr must name the file:\n"
                                                            << run.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_EQ(run.out, "");
    // Nothing else is left in the folder either (no temporary file).
    for (const fs::directory_entry& entry : fs::directory_iterator(scratch.path()))
        EXPECT_TRUE(entry.path() == input || entry.path().extension() == ".stdout" ||
                    entry.path().extension() == ".stderr")
            << "left behind: " << entry.path();
}

INSTANTIATE_TEST_SUITE_P(
    Cases, SgBuildBadInput,
    ::testing::Values(BadInputCase{"EmptyFile", "empty.obj", ""},
                      BadInputCase{"TextRenamedObj", "notes.obj",
                                   "These are meeting notes, not a mesh.\nSecond line.\n"},
                      BadInputCase{"TextRenamedPly", "notes.ply", "hello world\n"},
                      BadInputCase{"BinaryGarbageStl", "garbage.stl",
                                   // 15 bytes, no NUL: the length 17 given before read
                                   // past the literal (AddressSanitizer, build-asan/).
                                   std::string("\x01\x02\x03\x04 not an stl")},
                      BadInputCase{"MissingFile", "does_not_exist.obj", "", true}),
    [](const ::testing::TestParamInfo<BadInputCase>& param_info) { return param_info.param.name; });

TEST(SgBuild, ModelsWithoutUsableTrianglesAreBadInput)
{
    // Real files that Assimp reads but that hold no usable triangle: only points, only lines,
    // only triangles with infinite corners.
    for (const std::string relative :
         {"OBJ/testpoints.obj", "OBJ/testline.obj",
          "glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb"}) {
        SCOPED_TRACE(relative);
        const fs::path model = assimp_model(relative);
        ASSERT_TRUE(fs::exists(model));
        ScratchDir scratch;
        const fs::path out = scratch / "model.sg";
        const ToolRun run = run_tool(SG_BUILD_EXE, {model.string(), "-o", out.string()}, scratch);
        EXPECT_EQ(run.exit_code, 2) << describe(run);
        EXPECT_NE(run.err.find(model.filename().string()), std::string::npos) << run.err;
        EXPECT_FALSE(fs::exists(out));
    }
}

TEST(SgBuild, FailedBuildKeepsAnExistingOutputUntouched)
{
    ScratchDir scratch;
    const fs::path input = scratch / "broken.obj";
    write_text(input, "not a mesh\n");
    const fs::path out = scratch / "existing.sg";
    write_text(out, "previous contents");
    const ToolRun run = run_tool(SG_BUILD_EXE, {input.string(), "-o", out.string()}, scratch);
    EXPECT_EQ(run.exit_code, 2) << describe(run);
    EXPECT_EQ(read_text(out), "previous contents");
}

TEST(SgBuild, OutputInMissingFolderIsRefusedBeforeWork)
{
    const fs::path model = assimp_model("OFF/Cube.off");
    ASSERT_TRUE(fs::exists(model));
    ScratchDir scratch;
    const fs::path out = scratch / "no_such_folder" / "cube.sg";
    const ToolRun run = run_tool(SG_BUILD_EXE, {model.string(), "-o", out.string()}, scratch);
    EXPECT_EQ(run.exit_code, 2) << describe(run);
    EXPECT_NE(run.err.find("no_such_folder"), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(out.parent_path()));
}

TEST(SgBuild, OutputThatIsAFolderIsRefused)
{
    const fs::path model = assimp_model("OFF/Cube.off");
    ASSERT_TRUE(fs::exists(model));
    ScratchDir scratch;
    const ToolRun run = run_tool(SG_BUILD_EXE, {model.string(), "-o", scratch.path().string()},
                                 scratch);
    EXPECT_EQ(run.exit_code, 2) << describe(run);
}

// --- shared benchmark scenes (development machines and CI only) ---

TEST(SgBuildShared, TristripPlyIsReportedAsSuspicious)
{
    // Assimp 5.2 reads a PLY "tristrips" element as a single triangle; the import report
    // flags the implausible face count and sg-build must pass the warning on.
    const fs::path model = shared_mesh("tricky/igea_tristrips.ply");
    SG_SKIP_WITHOUT_SHARED_MESH(model);
    ScratchDir scratch;
    const ToolRun run = run_tool(
        SG_BUILD_EXE, {model.string(), "-o", (scratch / "igea.sg").string()}, scratch);
    EXPECT_NE(run.err.find("warning: "), std::string::npos) << describe(run);
}

TEST(SgBuildShared, ScannedMeshWithDefaultsMatchesImport)
{
    const fs::path model = shared_mesh("scanned/stanford_dragon_vrip_res4.ply");
    SG_SKIP_WITHOUT_SHARED_MESH(model);
    ScratchDir scratch;
    const fs::path out = scratch / "dragon.sg";
    const ToolRun run =
        run_tool(SG_BUILD_EXE, {model.string(), "-o", out.string(), "--json"}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const SgContents contents = read_sg_file(out);
    EXPECT_EQ(contents.mesh, import_mesh(model).mesh);
    EXPECT_EQ(json::parse(run.out).at("grid").at("reference_count"),
              count_leaf_references(contents.grid));
}

}  // namespace
}  // namespace sg::test
