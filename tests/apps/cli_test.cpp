// Command-line behaviour shared by every tool: --help, --version, usage errors, the
// BuildConfig flags of sg-build, and the one convention of all tools (-q, --threads, help
// texts, messages that name flags).

#include <sched.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "splitgrid/build_config.hpp"
#include "splitgrid/formats/ray_file.hpp"
#include "splitgrid/version.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace sg::test {
namespace {

const std::vector<std::string> all_tools = {SG_BUILD_EXE, SG_STATS_EXE, SG_TRACE_EXE,
                                            SG_RAYS_EXE, SG_POINTS_EXE};

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
        {SG_POINTS_EXE, {"x.sg", "--points", "p.csv", "-o", "o.bin", "--query", "occupancy"}},
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

// --- The one command-line convention (every tool) ---

namespace sg::test {
namespace {

namespace fs = std::filesystem;

/// Every tool, with the libraries its --version must name besides the shared ones.
struct ToolLibraries {
    std::string exe;
    std::string name;
    std::vector<std::string> extra_libraries;
};

std::vector<ToolLibraries> every_tool()
{
    std::vector<ToolLibraries> tools = {
        {SG_BUILD_EXE, "sg-build", {}},
        {SG_STATS_EXE, "sg-stats", {}},
        {SG_TRACE_EXE, "sg-trace", {}},
        {SG_RAYS_EXE, "sg-rays", {}},
#ifdef SG_APPS_TESTS_READ_VTK
        {SG_POINTS_EXE, "sg-points", {"VTK"}},  // it writes --grid's fields through VTK
#else
        {SG_POINTS_EXE, "sg-points", {}},
#endif
#ifdef SG_BENCH_HAS_EMBREE
        {SG_BENCH_EXE, "sg-bench", {"Embree"}},
#else
        {SG_BENCH_EXE, "sg-bench", {}},
#endif
    };
#ifdef SG_RENDER_EXE
    tools.push_back({SG_RENDER_EXE, "sg-render", {"VTK"}});
    tools.push_back({SG_EXPORT_EXE, "sg-export", {"VTK"}});
#endif
    return tools;
}

/// The hardware threads the tools may use, counted independently of oneTBB: the CPUs of this
/// process's affinity mask (the tests inherit the mask they pass on to the tools).
unsigned affinity_threads()
{
    cpu_set_t set;
    CPU_ZERO(&set);
    if (::sched_getaffinity(0, sizeof set, &set) != 0) return 1;
    return static_cast<unsigned>(CPU_COUNT(&set));
}

/// The entries of the Options sections of --help: each option's lines, joined with runs of
/// white space collapsed.
std::vector<std::string> help_entries(const std::string& help)
{
    std::vector<std::string> entries;
    std::istringstream lines(help);
    bool in_entry = false;
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("  -", 0) == 0) {
            entries.emplace_back();
            in_entry = true;
        } else if (line.rfind("      ", 0) != 0 || !in_entry) {
            in_entry = false;
            continue;
        }
        for (const char c : line) {
            std::string& entry = entries.back();
            const bool space = std::isspace(static_cast<unsigned char>(c)) != 0;
            if (!space || (!entry.empty() && entry.back() != ' ')) entry += space ? ' ' : c;
        }
        if (!entries.back().empty() && entries.back().back() != ' ') entries.back() += ' ';
    }
    return entries;
}

TEST(ToolsConvention, VersionNamesTheToolAndTheLibrariesItLinks)
{
    ScratchDir scratch;
    for (const ToolLibraries& tool : every_tool()) {
        SCOPED_TRACE(tool.name);
        const ToolRun run = run_tool(tool.exe, {"--version"}, scratch);
        ASSERT_EQ(run.exit_code, 0) << describe(run);
        EXPECT_EQ(run.out.rfind(tool.name + " " + version_string + " (splitgrid " +
                                    version_string + ")\n",
                                0),
                  0u)
            << run.out;
        std::vector<std::string> libraries = {"oneTBB", "Assimp", "zlib", "CLI11", "spdlog",
                                              "nlohmann-json"};
        libraries.insert(libraries.end(), tool.extra_libraries.begin(),
                         tool.extra_libraries.end());
        for (const std::string& library : libraries) {
            // "  Assimp 5.2.4": the name, then a version that starts with a digit.
            const std::size_t at = run.out.find("\n  " + library + " ");
            ASSERT_NE(at, std::string::npos) << library << " missing in\n" << run.out;
            const char first = run.out[at + 4 + library.size()];
            EXPECT_TRUE(std::isdigit(static_cast<unsigned char>(first))) << run.out;
        }
        EXPECT_EQ(run.err, "");
    }
}

TEST(ToolsConvention, HelpShowsEveryDefaultAndRangeTheSameWay)
{
    ScratchDir scratch;
    for (const ToolLibraries& tool : every_tool()) {
        SCOPED_TRACE(tool.name);
        const ToolRun run = run_tool(tool.exe, {"--help"}, scratch);
        ASSERT_EQ(run.exit_code, 0) << describe(run);
        const std::vector<std::string> entries = help_entries(run.out);
        ASSERT_GT(entries.size(), 4u) << run.out;
        for (const std::string& entry : entries) {
            // CLI11's own ways of showing defaults and ranges ("=300", "[default: 16384]",
            // "FLOAT:FLOAT in [0.001 - 1e+06]") are not used.
            EXPECT_EQ(entry.find("[default"), std::string::npos) << entry;
            EXPECT_EQ(entry.find(" in ["), std::string::npos) << entry;
            EXPECT_EQ(entry.substr(0, entry.find(' ')).find('='), std::string::npos) << entry;
            // "--leaf-size UINT  A cell ...": an option that takes a value has a type name
            // after its names; "REQUIRED" ones have no default.
            const std::string head = entry.substr(0, entry.find(' '));
            const std::string after = entry.substr(head.size() + 1);
            const bool has_value = !after.empty() && std::isupper(static_cast<unsigned char>(after[0])) &&
                                   after.find(' ') != std::string::npos &&
                                   std::all_of(after.begin(), after.begin() + static_cast<std::ptrdiff_t>(after.find(' ')),
                                               [](char c) { return !std::islower(static_cast<unsigned char>(c)); });
            const bool is_switch_pair = head.find(",--no-") != std::string::npos;
            if ((has_value && entry.find(" REQUIRED ") == std::string::npos) || is_switch_pair) {
                EXPECT_NE(entry.find(" Default "), std::string::npos) << entry;
            }
            for (const char* numeric : {" UINT ", " INT ", " FLOAT "}) {
                if (entry.find(numeric) == head.size()) {
                    EXPECT_NE(entry.find(" Range "), std::string::npos) << entry;
                }
            }
            // The range, when there is one, comes right before the default.
            const std::size_t range = entry.find(" Range ");
            if (range != std::string::npos) {
                EXPECT_LT(range, entry.find(" Default ")) << entry;
            }
        }
    }
}

TEST(ToolsConvention, QuietHidesTheSummaryOfFileToolsButNotResultsOrWarnings)
{
    ScratchDir scratch;
    const fs::path mesh = assimp_model("OBJ/spider.obj");  // has zero-area triangles: a warning
    const fs::path sg = scratch / "s.sg";
    const ToolRun build = run_tool(SG_BUILD_EXE, {mesh.string(), "-o", sg.string(), "-q"}, scratch);
    ASSERT_EQ(build.exit_code, 0) << describe(build);
    EXPECT_EQ(build.out, "") << "the result is the file";
    EXPECT_NE(build.err.find("warning: "), std::string::npos) << build.err;
    EXPECT_EQ(build.err.find("info"), std::string::npos) << build.err;
    EXPECT_TRUE(fs::exists(sg));

    const ToolRun json = run_tool(SG_BUILD_EXE,
                                  {mesh.string(), "-o", (scratch / "j.sg").string(), "-q", "--json"},
                                  scratch);
    ASSERT_EQ(json.exit_code, 0) << describe(json);
    EXPECT_EQ(nlohmann::json::parse(json.out).at("output"), (scratch / "j.sg").string());

    const ToolRun stats = run_tool(SG_STATS_EXE, {sg.string(), "-q"}, scratch);
    ASSERT_EQ(stats.exit_code, 0) << describe(stats);
    EXPECT_NE(stats.out.find("duplication factor"), std::string::npos)
        << "sg-stats' statistics are its result: -q keeps them";
    EXPECT_EQ(stats.err, "");

    write_ray_file(scratch / "r.bin", std::vector<Ray>(5, Ray{{0, 0, 50}, {0, 0, -1}, 0.0f, 1e30f}));
    const ToolRun trace = run_tool(
        SG_TRACE_EXE, {sg.string(), "--rays", (scratch / "r.bin").string(), "-o",
                       (scratch / "h.bin").string(), "-q"},
        scratch);
    ASSERT_EQ(trace.exit_code, 0) << describe(trace);
    EXPECT_EQ(trace.out, "");
    EXPECT_EQ(trace.err, "");
    EXPECT_EQ(read_hit_file(scratch / "h.bin").size(), 5u);
}

TEST(ToolsConvention, TooManyThreadsGiveOneWarningOfOursAndTheSummaryTellsWhatRan)
{
    ScratchDir scratch;
    const unsigned hardware = affinity_threads();
    const std::string asked = std::to_string(hardware + 14);
    const std::string warning = "warning: --threads " + asked + " is more than the " +
                                std::to_string(hardware) + " hardware thread" +
                                (hardware == 1 ? "" : "s") + "; using " +
                                std::to_string(hardware) + "\n";
    const std::string ran = " on " + std::to_string(hardware) + " thread" +
                            (hardware == 1 ? "" : "s");
    const fs::path sg = scratch / "w.sg";
    const ToolRun build = run_tool(SG_BUILD_EXE, {assimp_model("PLY/Wuson.ply").string(), "-o",
                                                  sg.string(), "--threads", asked},
                                   scratch);
    ASSERT_EQ(build.exit_code, 0) << describe(build);
    EXPECT_EQ(build.err, warning);
    EXPECT_NE(build.out.find("build "), std::string::npos);
    EXPECT_NE(build.out.find(ran + ", write"), std::string::npos) << build.out;

    write_ray_file(scratch / "r.bin", std::vector<Ray>(3000, Ray{{0, 0, 50}, {0, 0, -1}, 0.0f, 1e30f}));
    const std::vector<std::string> trace_args = {sg.string(), "--rays", (scratch / "r.bin").string(),
                                                 "-o", (scratch / "h.bin").string(), "--threads",
                                                 asked};
    const ToolRun trace = run_tool(SG_TRACE_EXE, trace_args, scratch);
    ASSERT_EQ(trace.exit_code, 0) << describe(trace);
    EXPECT_EQ(trace.err, warning) << "oneTBB's own warning must not appear";
    EXPECT_NE(trace.out.find(ran + " in "), std::string::npos) << trace.out;
    std::vector<std::string> quiet_json = trace_args;
    quiet_json.push_back("-q");
    quiet_json.push_back("--json");
    const ToolRun json = run_tool(SG_TRACE_EXE, quiet_json, scratch);
    ASSERT_EQ(json.exit_code, 0) << describe(json);
    EXPECT_EQ(json.err, warning) << "-q hides neither the warning nor --json";
    EXPECT_EQ(nlohmann::json::parse(json.out).at("threads"), hardware);
#ifdef SG_RENDER_EXE
    const ToolRun render = run_tool(SG_RENDER_EXE, {sg.string(), "-o", (scratch / "i.png").string(),
                                                    "--width", "16", "--height", "16",
                                                    "--threads", asked},
                                    scratch);
    ASSERT_EQ(render.exit_code, 0) << describe(render);
    EXPECT_EQ(render.err, warning);
    EXPECT_NE(render.out.find(ran + ": "), std::string::npos) << render.out;
#endif
}

TEST(ToolsConvention, ClashingBuildFlagsAreReportedByFlag)
{
    ScratchDir scratch;
    const std::string mesh = assimp_model("OFF/Cube.off").string();
    const std::string out = (scratch / "x.sg").string();
    const ToolRun both = run_tool(
        SG_BUILD_EXE, {mesh, "-o", out, "--resolution-min", "9", "--resolution-max", "8"}, scratch);
    EXPECT_EQ(both.exit_code, 1) << describe(both);
    EXPECT_NE(both.err.find("error: --resolution-min 9 is above --resolution-max 8 "),
              std::string::npos)
        << both.err;
    EXPECT_EQ(both.err.find("BuildConfig"), std::string::npos) << both.err;
    const BuildConfig defaults{};
    const std::string above = std::to_string(defaults.resolution_max + 4);
    const ToolRun one = run_tool(SG_BUILD_EXE, {mesh, "-o", out, "--resolution-min", above},
                                 scratch);
    EXPECT_EQ(one.exit_code, 1) << describe(one);
    EXPECT_NE(one.err.find("--resolution-min " + above + " is above --resolution-max " +
                           std::to_string(defaults.resolution_max) + " (its default)"),
              std::string::npos)
        << one.err;
    EXPECT_FALSE(fs::exists(out));
}

TEST(ToolsConvention, AFlagGivenTwiceIsReportedInOurWords)
{
    ScratchDir scratch;
    const ToolRun run = run_tool(SG_BUILD_EXE, {assimp_model("OFF/Cube.off").string(), "-o",
                                                (scratch / "x.sg").string(), "--leaf-size", "4",
                                                "--leaf-size", "8"},
                                 scratch);
    EXPECT_EQ(run.exit_code, 1) << describe(run);
    EXPECT_EQ(run.err, "error: --leaf-size is given 2 times (4, 8); give it once (run with --help "
                       "for usage)\n");
    const ToolRun trace = run_tool(SG_TRACE_EXE, {"a.sg", "--rays", "r.bin", "-o", "h.bin",
                                                  "--out", "h2.bin"},
                                   scratch);
    EXPECT_EQ(trace.exit_code, 1) << describe(trace);
    EXPECT_NE(trace.err.find("--output is given 2 times (h.bin, h2.bin)"), std::string::npos)
        << trace.err;
    // A flag of a subcommand (sg-rays' modes) is reported the same way.
    const ToolRun rays = run_tool(SG_RAYS_EXE, {"random", "a.sg", "-o", "r.bin", "--count", "3",
                                                "--count", "4"},
                                  scratch);
    EXPECT_EQ(rays.exit_code, 1) << describe(rays);
    EXPECT_NE(rays.err.find("--count is given 2 times (3, 4); give it once"), std::string::npos)
        << rays.err;
    EXPECT_EQ(rays.err.find("At Most"), std::string::npos) << rays.err;
    EXPECT_FALSE(fs::exists(scratch / "r.bin"));
}

TEST(ToolsConvention, BuildConfigJsonKeysAreTheFieldTable)
{
    // sg-build and sg-stats print one key per BuildConfig field, in the order of
    // build_config.hpp; the values are those of the flags and of the file.
    ScratchDir scratch;
    const fs::path sg = scratch / "x.sg";
    const ToolRun build = run_tool(SG_BUILD_EXE, {assimp_model("OFF/Cube.off").string(), "-o",
                                                  sg.string(), "--json", "--leaf-size", "3",
                                                  "--no-clip-triangles", "--min-cell-width",
                                                  "0.25"},
                                   scratch);
    ASSERT_EQ(build.exit_code, 0) << describe(build);
    const ToolRun stats = run_tool(SG_STATS_EXE, {sg.string(), "--json"}, scratch);
    ASSERT_EQ(stats.exit_code, 0) << describe(stats);
    const std::vector<std::string> fields = {
        "resolution_min", "resolution_max", "resolution_sigma", "leaf_size",
        "max_depth", "no_progress_fraction", "min_cell_width", "stop_by_cost",
        "bounding_planes", "bounding_nodes", "clip_triangles", "threads"};
    for (const std::string& output : {build.out, stats.out}) {
        const nlohmann::ordered_json config = nlohmann::ordered_json::parse(output).at("build_config");
        std::vector<std::string> keys;
        for (const auto& item : config.items()) keys.push_back(item.key());
        EXPECT_EQ(keys, fields);
        EXPECT_EQ(config.at("leaf_size"), 3);
        EXPECT_EQ(config.at("clip_triangles"), false);
        EXPECT_EQ(config.at("min_cell_width"), 0.25);
        EXPECT_EQ(config.at("bounding_planes"), true);
    }
}

}  // namespace
}  // namespace sg::test
