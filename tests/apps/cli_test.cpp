// Command-line behaviour shared by every tool: --help, --version, usage errors and the
// BuildConfig flags of sg-build.

#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "splitgrid/build_config.hpp"
#include "splitgrid/version.hpp"

#include <gtest/gtest.h>

namespace sg::test {
namespace {

const std::vector<std::string> all_tools = {SG_BUILD_EXE, SG_STATS_EXE, SG_TRACE_EXE,
                                            SG_RAYS_EXE};

TEST(ToolsCli, HelpExitsZeroAndDocumentsExitCodes)
{
    ScratchDir scratch;
    for (const std::string& tool : all_tools) {
        SCOPED_TRACE(tool);
        const ToolRun run = run_tool(tool, {"--help"}, scratch);
        ASSERT_EQ(run.exit_code, 0) << describe(run);
        EXPECT_NE(run.out.find("Exit codes:"), std::string::npos) << run.out;
        for (const char* line : {"0  ok", "1  usage", "2  bad input", "3  internal"})
            EXPECT_NE(run.out.find(line), std::string::npos) << line << " missing in\n" << run.out;
        EXPECT_EQ(run.err, "");
    }
}

TEST(ToolsCli, VersionPrintsLibraryVersion)
{
    ScratchDir scratch;
    for (const std::string& tool : all_tools) {
        SCOPED_TRACE(tool);
        const ToolRun run = run_tool(tool, {"--version"}, scratch);
        ASSERT_EQ(run.exit_code, 0) << describe(run);
        EXPECT_NE(run.out.find(version_string), std::string::npos) << run.out;
    }
}

TEST(ToolsCli, UnknownFlagIsUsageError)
{
    ScratchDir scratch;
    // Each tool gets its required arguments, so that the unknown flag is the only problem.
    const std::vector<std::pair<std::string, std::vector<std::string>>> commands = {
        {SG_BUILD_EXE, {"mesh.obj", "-o", "x.sg"}},
        {SG_STATS_EXE, {"x.sg"}},
        {SG_TRACE_EXE, {"x.sg", "--rays", "r.bin", "--out", "h.bin"}},
        {SG_RAYS_EXE, {"text", "r.csv", "-o", "r.bin"}},
    };
    for (const auto& [tool, required] : commands) {
        SCOPED_TRACE(tool);
        std::vector<std::string> args = required;
        args.push_back("--no-such-flag");
        const ToolRun run = run_tool(tool, args, scratch);
        EXPECT_EQ(run.exit_code, 1) << describe(run);
        EXPECT_NE(run.err.find("no-such-flag"), std::string::npos) << run.err;
        EXPECT_EQ(run.out, "");
    }
}

TEST(ToolsCli, MissingRequiredArgumentIsUsageError)
{
    ScratchDir scratch;
    EXPECT_EQ(run_tool(SG_BUILD_EXE, {}, scratch).exit_code, 1);
    EXPECT_EQ(run_tool(SG_BUILD_EXE, {"mesh.obj"}, scratch).exit_code, 1);  // no -o
    EXPECT_EQ(run_tool(SG_STATS_EXE, {}, scratch).exit_code, 1);
    EXPECT_EQ(run_tool(SG_TRACE_EXE, {"a.sg", "--rays", "r.bin"}, scratch).exit_code, 1);
    EXPECT_EQ(run_tool(SG_TRACE_EXE, {"a.sg", "--out", "h.bin"}, scratch).exit_code, 1);
    EXPECT_EQ(run_tool(SG_BUILD_EXE, {"-v", "-q", "m.obj", "-o", "x.sg"}, scratch).exit_code, 1)
        << "-v and -q exclude each other";
}

TEST(ToolsCli, BuildHelpListsEveryBuildConfigFieldWithItsDefault)
{
    ScratchDir scratch;
    const ToolRun run = run_tool(SG_BUILD_EXE, {"--help"}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const BuildConfig defaults{};
    const std::vector<std::pair<std::string, std::string>> flags = {
        {"--resolution-min", "Default " + std::to_string(defaults.resolution_min) + "."},
        {"--resolution-max", "Default " + std::to_string(defaults.resolution_max) + "."},
        {"--resolution-sigma", "Default 48."},
        {"--leaf-size", "Default " + std::to_string(defaults.leaf_size) + "."},
        {"--max-depth", "Default " + std::to_string(defaults.max_depth) + "."},
        {"--no-progress-fraction", "Default 0.9."},
        {"--min-cell-width", "Default 1."},
        {"--stop-by-cost", "Default --stop-by-cost."},
        {"--threads", "Default " + std::to_string(defaults.threads) + "."},
    };
    // The two non-integer defaults are spelled out above; make sure they are still the
    // library's, so the test fails (rather than passes stale) if a default changes.
    ASSERT_EQ(defaults.resolution_sigma, 48.0);
    ASSERT_EQ(defaults.no_progress_fraction, 0.9);
    ASSERT_EQ(defaults.min_cell_width, 1.0);
    ASSERT_TRUE(defaults.stop_by_cost);
    for (const auto& [flag, default_text] : flags) {
        // The flag's own entry starts a line; other entries may mention it in their text.
        const std::size_t at = run.out.find("\n  " + flag);
        ASSERT_NE(at, std::string::npos) << flag << " missing in\n" << run.out;
        const std::size_t next_flag = run.out.find("\n  -", at + 1);
        // Descriptions are word-wrapped: compare with runs of white space collapsed.
        std::string entry;
        for (const char c : run.out.substr(at + 1, next_flag - at - 1))
            if (!std::isspace(static_cast<unsigned char>(c)) || (!entry.empty() && entry.back() != ' '))
                entry += std::isspace(static_cast<unsigned char>(c)) ? ' ' : c;
        EXPECT_NE(entry.find(default_text), std::string::npos)
            << flag << " should show '" << default_text << "' in:\n" << entry;
    }
    // The resolution formula is part of the help (the flags are its named parameters).
    EXPECT_NE(run.out.find("exp(-(n / sigma)^2 / 2)"), std::string::npos) << run.out;
}

TEST(ToolsCli, OutOfRangeBuildFlagsAreUsageErrorsAndCreateNothing)
{
    ScratchDir scratch;
    const std::filesystem::path mesh = assimp_model("OFF/Cube.off");
    ASSERT_TRUE(std::filesystem::exists(mesh)) << mesh << ": install assimp-testmodels";
    const std::filesystem::path out = scratch / "out.sg";
    const std::vector<std::vector<std::string>> bad_flags = {
        {"--leaf-size", "0"},
        {"--leaf-size", "-1"},
        {"--leaf-size", "four"},
        {"--max-depth", "65"},
        {"--resolution-min", "0"},
        {"--resolution-max", "2000000"},
        {"--resolution-sigma", "0"},
        {"--resolution-sigma", "nan"},
        {"--no-progress-fraction", "0"},
        {"--no-progress-fraction", "1.5"},
        {"--threads", "5000"},
        {"--min-cell-width", "-1"},
        {"--min-cell-width", "2e6"},
        {"--resolution-max", "1"},
        {"--stop-by-cost=maybe", "(not a boolean)"},
        // Each value is in range alone; together they are not (sg::validate decides).
        {"--resolution-min", "10", "--resolution-max", "5"},
    };
    for (const std::vector<std::string>& flags : bad_flags) {
        std::vector<std::string> args = {mesh.string(), "-o", out.string()};
        for (const std::string& flag : flags)
            if (flag.front() != '(') args.push_back(flag);  // "(...)" entries are comments
        const ToolRun run = run_tool(SG_BUILD_EXE, args, scratch);
        SCOPED_TRACE(flags[0] + " " + flags[1]);
        EXPECT_EQ(run.exit_code, 1) << describe(run);
        EXPECT_NE(run.err.find("error: "), std::string::npos) << run.err;
        EXPECT_FALSE(std::filesystem::exists(out));
    }
    // The boundary values themselves are accepted. (Not all at once: a no-progress fraction
    // of 1 with 64 cells per node and depth 64 would grow without bound on this cube.)
    const std::vector<std::vector<std::string>> boundary_flags = {
        {"--max-depth", "64", "--leaf-size", "1048576"},
        {"--no-progress-fraction", "1", "--max-depth", "0"},
        {"--resolution-min", "64", "--resolution-max", "64", "--max-depth", "1"},
        {"--resolution-min", "1", "--resolution-sigma", "1e9", "--threads", "1024"},
        {"--min-cell-width", "0", "--no-stop-by-cost", "--max-depth", "4"},
        {"--min-cell-width", "1e6", "--stop-by-cost"},
    };
    for (const std::vector<std::string>& flags : boundary_flags) {
        std::vector<std::string> args = {mesh.string(), "-o", out.string(), "-q"};
        args.insert(args.end(), flags.begin(), flags.end());
        const ToolRun run = run_tool(SG_BUILD_EXE, args, scratch);
        SCOPED_TRACE(flags[0] + " " + flags[1]);
        EXPECT_EQ(run.exit_code, 0) << describe(run);
        EXPECT_TRUE(std::filesystem::exists(out));
        std::filesystem::remove(out);
    }
}

TEST(ToolsCli, TraceThreadsOutOfRangeIsUsageError)
{
    ScratchDir scratch;
    const ToolRun run = run_tool(
        SG_TRACE_EXE, {"a.sg", "--rays", "r.bin", "--out", "h.bin", "--threads", "5000"}, scratch);
    EXPECT_EQ(run.exit_code, 1) << describe(run);
}

}  // namespace
}  // namespace sg::test
