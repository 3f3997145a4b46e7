// End-to-end tests of what the tools do with their outputs before any work: an output that
// is one of the inputs (by name, through a link, or a file the mesh pulls in) is refused with
// exit code 2 and a message naming both, and the input is left byte for byte; "-o -" is a
// usage error everywhere; a folder that cannot be written is found before the input is even
// opened; every tool spells its output -o/--output (with --out as an alias).

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "splitgrid/formats/ray_file.hpp"

#include <gtest/gtest.h>

namespace sg::test {
namespace {

namespace fs = std::filesystem;

/// Every tool that writes a file or folder.
std::vector<std::string> writing_tools()
{
    std::vector<std::string> tools = {SG_BUILD_EXE, SG_TRACE_EXE, SG_RAYS_EXE, SG_POINTS_EXE,
                                      SG_BENCH_EXE};
#ifdef SG_RENDER_EXE
    tools.push_back(SG_RENDER_EXE);
    tools.push_back(SG_EXPORT_EXE);
#endif
    return tools;
}

std::size_t line_count(const std::string& text)
{
    return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

/// A refusal of an output over an input: exit code 2, one line naming both paths, nothing on
/// stdout, and the input exactly as before.
void expect_refused_over_input(const ToolRun& run, const fs::path& output, const fs::path& input,
                               const std::string& input_bytes)
{
    EXPECT_EQ(run.exit_code, 2) << describe(run);
    EXPECT_EQ(line_count(run.err), 1u) << run.err;
    EXPECT_EQ(run.err.rfind("error: " + output.string() + ": refusing to ", 0), 0u) << run.err;
    EXPECT_NE(run.err.find(input.string()), std::string::npos) << run.err;
    EXPECT_EQ(run.out, "");
    EXPECT_EQ(read_text(input), input_bytes) << input << " was changed";
}

/// The scratch folder holds nothing but `expected` and the runs' stdout and stderr files.
void expect_only(const ScratchDir& scratch, std::vector<std::string> expected)
{
    std::vector<std::string> left;
    for (const std::string& name : scratch.entries())
        if (name.rfind("run", 0) != 0) left.push_back(name);
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(left, expected);
}

class OutputSafety : public ::testing::Test {
protected:
    void SetUp() override
    {
        fs::copy_file(assimp_model("STL/Spider_binary.stl"), stl_);
        stl_bytes_ = read_text(stl_);
        const ToolRun built = run_tool(SG_BUILD_EXE, {stl_.string(), "-o", sg_.string()}, scratch_);
        ASSERT_EQ(built.exit_code, 0) << describe(built);
        sg_bytes_ = read_text(sg_);
        write_ray_file(rays_, std::vector<Ray>(10, Ray{{0, 0, 5}, {0, 0, -1}, 0.0f, 1e30f}));
        ray_bytes_ = read_text(rays_);
    }

    ScratchDir scratch_;
    fs::path stl_ = scratch_ / "part.stl";
    fs::path sg_ = scratch_ / "part.sg";
    fs::path rays_ = scratch_ / "rays.bin";
    std::string stl_bytes_;
    std::string sg_bytes_;
    std::string ray_bytes_;
};

TEST_F(OutputSafety, SgBuildRefusesToWriteOverItsMesh)
{
    const ToolRun run = run_tool(SG_BUILD_EXE, {stl_.string(), "-o", stl_.string()}, scratch_);
    expect_refused_over_input(run, stl_, stl_, stl_bytes_);
    // Another name of the same file: a hard link and a symbolic link.
    fs::create_hard_link(stl_, scratch_ / "hard.stl");
    fs::create_symlink(stl_, scratch_ / "soft.stl");
    for (const char* name : {"hard.stl", "soft.stl"}) {
        SCOPED_TRACE(name);
        const ToolRun linked =
            run_tool(SG_BUILD_EXE, {stl_.string(), "-o", (scratch_ / name).string()}, scratch_);
        expect_refused_over_input(linked, scratch_ / name, stl_, stl_bytes_);
    }
    expect_only(scratch_, {"part.stl", "part.sg", "rays.bin", "hard.stl", "soft.stl"});
}

TEST_F(OutputSafety, SgTraceRefusesToWriteOverItsRaysOrItsSgFile)
{
    const ToolRun over_rays = run_tool(
        SG_TRACE_EXE, {sg_.string(), "--rays", rays_.string(), "--out", rays_.string()}, scratch_);
    expect_refused_over_input(over_rays, rays_, rays_, ray_bytes_);
    const ToolRun over_sg = run_tool(
        SG_TRACE_EXE, {sg_.string(), "--rays", rays_.string(), "-o", sg_.string()}, scratch_);
    expect_refused_over_input(over_sg, sg_, sg_, sg_bytes_);
    expect_only(scratch_, {"part.stl", "part.sg", "rays.bin"});
}

TEST_F(OutputSafety, SgRaysRefusesToWriteOverItsInput)
{
    const ToolRun over_sg = run_tool(SG_RAYS_EXE, {"random", sg_.string(), "-o", sg_.string()},
                                     scratch_);
    expect_refused_over_input(over_sg, sg_, sg_, sg_bytes_);
    const fs::path text = scratch_ / "rays.csv";
    write_text(text, "0 0 5 0 0 -1\n");
    const std::string text_bytes = read_text(text);
    const ToolRun over_text = run_tool(SG_RAYS_EXE, {"text", text.string(), "--out", text.string()},
                                       scratch_);
    expect_refused_over_input(over_text, text, text, text_bytes);
    expect_only(scratch_, {"part.stl", "part.sg", "rays.bin", "rays.csv"});
}

TEST_F(OutputSafety, SgPointsRefusesToWriteOverItsPointsOrItsSgFile)
{
    const fs::path points = scratch_ / "points.csv";
    write_text(points, "0 0 0\n");
    const std::string point_bytes = read_text(points);
    const ToolRun over_points = run_tool(SG_POINTS_EXE,
                                         {sg_.string(), "--points", points.string(), "--out",
                                          points.string(), "--query", "occupancy"},
                                         scratch_);
    expect_refused_over_input(over_points, points, points, point_bytes);
    const ToolRun over_sg = run_tool(SG_POINTS_EXE,
                                     {sg_.string(), "--points", points.string(), "-o",
                                      sg_.string(), "--query", "occupancy"},
                                     scratch_);
    expect_refused_over_input(over_sg, sg_, sg_, sg_bytes_);
    expect_only(scratch_, {"part.stl", "part.sg", "rays.bin", "points.csv"});
}

#ifdef SG_RENDER_EXE
TEST_F(OutputSafety, SgRenderRefusesToWriteOverItsSgFile)
{
    // A .sg file is read whatever its name, so one called .png can be the output too.
    const fs::path sg_as_png = scratch_ / "part.png";
    fs::copy_file(sg_, sg_as_png);
    const ToolRun run = run_tool(SG_RENDER_EXE, {sg_as_png.string(), "-o", sg_as_png.string(),
                                                 "--width", "8", "--height", "8"},
                                 scratch_);
    expect_refused_over_input(run, sg_as_png, sg_as_png, sg_bytes_);
    expect_only(scratch_, {"part.stl", "part.sg", "part.png", "rays.bin"});
}

TEST_F(OutputSafety, SgExportRefusesAFolderThatIsOrHoldsItsInput)
{
    const ToolRun over_file = run_tool(SG_EXPORT_EXE, {sg_.string(), "-o", sg_.string()}, scratch_);
    expect_refused_over_input(over_file, sg_, sg_, sg_bytes_);

    // An earlier export that the .sg file was later moved into: --force would replace the
    // folder, and the input with it.
    const fs::path out = scratch_ / "out";
    ASSERT_EQ(run_tool(SG_EXPORT_EXE, {sg_.string(), "-o", out.string()}, scratch_).exit_code, 0);
    fs::rename(sg_, out / "part.sg");
    const std::vector<std::string> before = folder_entries(out);
    const ToolRun forced = run_tool(
        SG_EXPORT_EXE, {(out / "part.sg").string(), "-o", out.string(), "--force"}, scratch_);
    EXPECT_EQ(forced.exit_code, 2) << describe(forced);
    EXPECT_EQ(line_count(forced.err), 1u) << forced.err;
    EXPECT_EQ(forced.err.rfind("error: " + out.string() + ": refusing to replace the folder", 0),
              0u)
        << forced.err;
    EXPECT_NE(forced.err.find((out / "part.sg").string()), std::string::npos) << forced.err;
    EXPECT_EQ(folder_entries(out), before);
    EXPECT_EQ(read_text(out / "part.sg"), sg_bytes_);
    expect_only(scratch_, {"part.stl", "out", "rays.bin"});
}
#endif

TEST_F(OutputSafety, SgBenchRefusesAnOutputFolderThatIsItsMesh)
{
    const ToolRun run = run_tool(SG_BENCH_EXE, {"--quick", stl_.string(), "-o", stl_.string()},
                                 scratch_);
    expect_refused_over_input(run, stl_, stl_, stl_bytes_);
    expect_only(scratch_, {"part.stl", "part.sg", "rays.bin"});
}

TEST(OutputSafetyPulledIn, SgBuildRefusesTheFilesAMeshRefersTo)
{
    // A glTF's buffer (.bin) and an OBJ's material library (.mtl) are read through Assimp's
    // file system: not on the command line, and still inputs.
    ScratchDir scratch;
    const fs::path gltf_dir = assimp_model("glTF2/BoxTextured-glTF");
    for (const auto& entry : fs::directory_iterator(gltf_dir))
        fs::copy_file(entry.path(), scratch / entry.path().filename());
    fs::copy_file(assimp_model("OBJ/cube_usemtl.obj"), scratch / "cube.obj");
    fs::copy_file(assimp_model("OBJ/cube_usemtl.mtl"), scratch / "cube_usemtl.mtl");
    ASSERT_NE(read_text(scratch / "cube.obj").find("mtllib cube_usemtl.mtl"), std::string::npos)
        << "test premise: the OBJ names its .mtl";
    const std::vector<std::string> before = scratch.entries();

    struct Case {
        fs::path mesh;
        fs::path output;
    };
    for (const Case& c : {Case{scratch / "BoxTextured.gltf", scratch / "BoxTextured0.bin"},
                          Case{scratch / "cube.obj", scratch / "cube_usemtl.mtl"}}) {
        SCOPED_TRACE(c.output.string());
        const std::string bytes = read_text(c.output);
        const ToolRun run = run_tool(SG_BUILD_EXE, {c.mesh.string(), "-o", c.output.string()},
                                     scratch);
        expect_refused_over_input(run, c.output, c.output, bytes);
        EXPECT_NE(run.err.find("which the input " + c.mesh.string() + " reads"),
                  std::string::npos)
            << run.err;
    }
    std::vector<std::string> after;
    for (const std::string& name : scratch.entries())
        if (name.rfind("run", 0) != 0) after.push_back(name);
    EXPECT_EQ(after, before) << "no output and no temporary file left";
}

TEST(OutputSafetyPulledIn, SgBenchRefusesAResultsFileTheMeshRefersTo)
{
    // A glTF whose buffer is called results.json, in the output folder: only the import
    // finds that sg-bench would replace it.
    ScratchDir scratch;
    const fs::path out = scratch / "out";
    fs::create_directory(out);
    std::string gltf = read_text(assimp_model("glTF2/BoxTextured-glTF/BoxTextured.gltf"));
    const std::string uri = "\"BoxTextured0.bin\"";
    ASSERT_NE(gltf.find(uri), std::string::npos) << "test premise: the glTF names its buffer";
    gltf.replace(gltf.find(uri), uri.size(), "\"results.json\"");
    write_text(out / "box.gltf", gltf);
    fs::copy_file(assimp_model("glTF2/BoxTextured-glTF/BoxTextured0.bin"), out / "results.json");
    const std::string buffer = read_text(out / "results.json");

    const ToolRun run = run_tool(SG_BENCH_EXE, {"--quick", (out / "box.gltf").string(), "-o",
                                                out.string()},
                                 scratch);
    expect_refused_over_input(run, out / "results.json", out / "results.json", buffer);
    EXPECT_EQ(folder_entries(out), (std::vector<std::string>{"box.gltf", "results.json"}));
}

TEST(OutputSafetyDash, DashIsRefusedByEveryToolAndCreatesNothing)
{
    ScratchDir scratch;
    const fs::path mesh = assimp_model("OFF/Cube.off");
    for (const std::string& tool : writing_tools()) {
        SCOPED_TRACE(tool);
        std::vector<std::string> args = {mesh.string(), "-o", "-"};
        if (tool == SG_TRACE_EXE) args = {"a.sg", "--rays", "r.bin", "-o", "-"};
        if (tool == SG_RAYS_EXE) args = {"random", "a.sg", "-o", "-"};
        if (tool == SG_POINTS_EXE) args = {"a.sg", "--points", "p.bin", "-o", "-", "--query",
                                           "occupancy"};
        const ToolRun run = run_tool(tool, args, scratch, scratch.path());
        EXPECT_EQ(run.exit_code, 1) << describe(run);
        EXPECT_EQ(line_count(run.err), 1u) << run.err;
        EXPECT_NE(run.err.find("standard output) is not supported"), std::string::npos)
            << run.err;
        EXPECT_FALSE(fs::exists(scratch / "-"));
    }
}

TEST(OutputSafetyFlags, EveryToolSpellsItsOutputTheSameWay)
{
    ScratchDir scratch;
    for (const std::string& tool : writing_tools()) {
        SCOPED_TRACE(tool);
        const ToolRun run = run_tool(tool, {"--help"}, scratch);
        ASSERT_EQ(run.exit_code, 0) << describe(run);
        EXPECT_NE(run.out.find("\n  -o,--output,--out "), std::string::npos) << run.out;
    }
}

TEST(OutputSafetyEarly, AFolderThatCannotBeWrittenIsRefusedBeforeTheInputIsOpened)
{
    // The input does not exist: a tool that opened it before reserving its output would
    // complain about the input. Each must name the output instead.
    ScratchDir scratch;
    const fs::path no_write = unwritable_folder(scratch);
    const std::string missing = (scratch / "missing.stl").string();
    struct Case {
        std::string tool;
        std::vector<std::string> args;
        fs::path named;
    };
    std::vector<Case> cases = {
        {SG_BUILD_EXE, {missing, "-o", (no_write / "x.sg").string()}, no_write / "x.sg"},
        {SG_TRACE_EXE, {missing, "--rays", missing, "-o", (no_write / "h.bin").string()},
         no_write / "h.bin"},
        {SG_BENCH_EXE, {"--quick", missing, "-o", (no_write / "bench").string()},
         no_write / "bench"},
        {SG_RAYS_EXE, {"random", missing, "-o", (no_write / "r.bin").string()},
         no_write / "r.bin"},
        {SG_POINTS_EXE,
         {missing, "--points", missing, "-o", (no_write / "o.bin").string(), "--query",
          "occupancy"},
         no_write / "o.bin"},
    };
#ifdef SG_RENDER_EXE
    cases.push_back({SG_RENDER_EXE, {missing, "-o", (no_write / "x.png").string()},
                     no_write / "x.png"});
    cases.push_back({SG_EXPORT_EXE, {missing, "-o", (no_write / "dir").string()},
                     no_write / "dir"});
#endif
    for (const Case& c : cases) {
        SCOPED_TRACE(c.tool);
        const ToolRun run = run_tool(c.tool, c.args, scratch);
        EXPECT_EQ(run.exit_code, 2) << describe(run);
        EXPECT_EQ(line_count(run.err), 1u) << run.err;
        EXPECT_EQ(run.err.rfind("error: " + c.named.string() + ": ", 0), 0u) << run.err;
        EXPECT_EQ(run.err.find("missing.stl"), std::string::npos) << run.err;
        EXPECT_FALSE(fs::exists(c.named));
    }
}

}  // namespace
}  // namespace sg::test
