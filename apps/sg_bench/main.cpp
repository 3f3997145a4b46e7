/// sg-bench: the Split Grid against a uniform grid, a kd-tree, a BVH and Intel Embree on the
/// same scenes and the same rays: build time, memory, rays per second and correctness, as a
/// table on stdout, results.json, results.csv and PNG charts in the output folder.

#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "bench_report.hpp"
#include "bench_run.hpp"
#include "cli_common.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "splitgrid/formats/text_file.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

extern char** environ;

namespace {

namespace fs = std::filesystem;
using sg::bench::BenchPlan;

struct Options {
    std::vector<fs::path> meshes;
    fs::path out = "sg-bench-results";
    bool quick = false;
    // Comma-separated lists, split by bench() (one token each, so that they never swallow
    // the MESH arguments that follow).
    std::string structures_text;
    std::string threads_text;
    fs::path scale_model;
    std::string scale_sizes_text;
    std::string arena_sizes_text;
    bool no_sweep = false;
    bool no_charts = false;
    fs::path charts_script = SG_BENCH_CHARTS_SCRIPT;
    BenchPlan plan;
    sg::apps::LogOptions log;
};

std::string cpu_model()
{
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            if (colon != std::string::npos) return line.substr(colon + 2);
        }
    return "unknown";
}

std::vector<std::string> split_list(const std::string& text)
{
    std::vector<std::string> items;
    std::string item;
    std::istringstream in(text);
    while (std::getline(in, item, ','))
        if (!item.empty()) items.push_back(item);
    return items;
}

/// "1e6" or "2500000" as a triangle count in [1, 4e9]; a usage error otherwise.
std::vector<std::size_t> counts_of(const std::string& text, const char* flag)
{
    std::vector<std::size_t> counts;
    for (const std::string& item : split_list(text)) {
        double value = 0.0;
        const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), value);
        if (ec != std::errc{} || ptr != item.data() + item.size() || !(value >= 1.0 && value <= 4e9))
            throw CLI::ValidationError(
                fmt::format("{}: {} is not a triangle count in [1, 4e9]", flag, item));
        counts.push_back(static_cast<std::size_t>(std::llround(value)));
    }
    return counts;
}

std::vector<unsigned> threads_of(const std::string& text)
{
    std::vector<unsigned> threads;
    for (const std::string& item : split_list(text)) {
        unsigned value = 0;
        const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), value);
        if (ec != std::errc{} || ptr != item.data() + item.size() || value < 1 || value > 1024)
            throw CLI::ValidationError(
                fmt::format("--threads: {} is not a thread count in [1, 1024]", item));
        threads.push_back(value);
    }
    return threads;
}

// "arena_1e+06" is awkward in file names: 1e6 -> "1e6", 2.5e6 -> "2.5e6".
std::string size_label(std::size_t n)
{
    int exponent = 0;
    double mantissa = static_cast<double>(n);
    while (mantissa >= 10.0) {
        mantissa /= 10.0;
        ++exponent;
    }
    return fmt::format("{:g}e{}", mantissa, exponent);
}

sg::bench::BenchScene load_scene(const fs::path& path)
{
    sg::ImportedMesh imported = sg::import_mesh(path);
    for (const std::string& warning : imported.report.warnings) spdlog::warn("{}", warning);
    if (imported.mesh.triangles.empty())
        throw sg::InputError(path.string() + ": no usable triangles");
    return {path.stem().string(), path.string(), std::move(imported.mesh)};
}

// Runs the chart script; a failure is a warning, since the JSON and CSV are written already.
void make_charts(const Options& options, const fs::path& json)
{
    // Debian's interpreter, where python3-matplotlib lives, before any other python3.
    const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    std::vector<std::string> args{python, options.charts_script.string(), json.string(),
                                  options.out.string()};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    const int error = ::posix_spawnp(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ);
    if (error != 0) {
        spdlog::warn("charts not made: cannot start python3: {}", std::strerror(error));
        return;
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) break;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        spdlog::warn("charts not made: {} failed (python3-matplotlib installed?)",
                     options.charts_script.string());
}

void apply_quick_defaults(CLI::App& app, Options& o)
{
    auto unset = [&](const char* flag) { return app.count(flag) == 0; };
    BenchPlan& p = o.plan;
    if (unset("--width")) p.sizes.width = 160;
    if (unset("--height")) p.sizes.height = 120;
    if (unset("--incoherent-rays")) p.sizes.incoherent_rays = 20'000;
    if (unset("--build-repeats")) p.build_repeats = 1;
    if (unset("--trace-repeats")) p.trace_repeats = 1;
    if (unset("--oracle-rays")) p.oracle_rays = 100;
    if (unset("--watertight-triangles")) p.watertight_triangles = 10'000;
    if (unset("--watertight-rays")) p.watertight_rays = 20'000;
    if (unset("--sweep-rays")) p.sweep_rays = 20'000;
}

void bench(CLI::App& app, Options& o)
{
    const auto start = std::chrono::steady_clock::now();
    if (o.quick) apply_quick_defaults(app, o);
    BenchPlan& plan = o.plan;
    plan.sweep = !o.no_sweep;
    const std::vector<std::string> structures = split_list(o.structures_text);
    plan.structures = structures.empty() ? sg::bench::structure_names() : structures;
    for (const std::string& s : plan.structures) {
        const auto names = sg::bench::structure_names();
        if (std::find(names.begin(), names.end(), s) == names.end())
            throw CLI::ValidationError(fmt::format(
                "--structures: unknown structure '{}' (this build knows {})", s, fmt::join(names, ", ")));
    }
    plan.thread_counts = threads_of(o.threads_text);
    if (plan.thread_counts.empty()) {
        plan.thread_counts = {1};
        const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
        if (hw > 1) plan.thread_counts.push_back(hw);
    }
    plan.scale_sizes = counts_of(o.scale_sizes_text, "--scale-sizes");
    const std::vector<std::size_t> arena_sizes = counts_of(o.arena_sizes_text, "--arena-sizes");
    if (o.meshes.empty() && (arena_sizes.empty() || o.scale_model.empty()))
        throw CLI::ValidationError("give at least one MESH (or --arena-sizes with --scale-model)");

    // Check the output folder before any long work: its parent must exist.
    const fs::path parent = o.out.has_parent_path() ? o.out.parent_path() : fs::path(".");
    if (!fs::is_directory(parent))
        throw sg::IoError(o.out.string() + ": folder " + parent.string() + " does not exist");
    if (fs::exists(o.out) && !fs::is_directory(o.out))
        throw sg::IoError(o.out.string() + ": exists and is not a folder");

    std::vector<sg::bench::BenchScene> scenes;
    for (const fs::path& m : o.meshes) {
        spdlog::debug("loading {}", m.string());
        scenes.push_back(load_scene(m));
    }
    sg::bench::BenchScene model;
    if (!o.scale_model.empty()) model = load_scene(o.scale_model);
    else if (!scenes.empty()) model = scenes.front();
    for (const std::size_t n : arena_sizes) {
        sg::bench::BenchScene arena;
        arena.mesh = sg::bench::scale_scene(model.mesh.view(), n, plan.seed);
        arena.name = "arena_" + size_label(arena.mesh.triangles.size());
        arena.source = fmt::format("{} arranged to {} triangles (make_arena_scene)", model.source,
                                   arena.mesh.triangles.size());
        scenes.push_back(std::move(arena));
    }

    const sg::bench::BenchResults results = sg::bench::run_bench(
        scenes, model, plan, [](const std::string& line) { spdlog::info("{}", line); });

    sg::bench::RunInfo info;
    info.quick = o.quick;
    info.machine = cpu_model();
    info.hardware_threads = std::thread::hardware_concurrency();
    info.compiler = "g++ " __VERSION__;
    info.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    fs::create_directories(o.out);
    const fs::path json = o.out / "results.json";
    sg::write_text_file(json, sg::bench::results_json(results, plan, info).dump(2) + "\n");
    sg::write_text_file(o.out / "results.csv", sg::bench::results_csv(results, plan));
    std::cout << sg::bench::results_table(results, plan);
    if (!o.no_charts) make_charts(o, json);
    std::cout << fmt::format("\nwrote {} and results.csv in {:.1f} s\n", json.string(), info.seconds);
}

}  // namespace

int main(int argc, char** argv)
{
    Options o;
    CLI::App app{"", "sg-bench"};
    sg::apps::describe_tool(
        app,
        "Measures the Split Grid against a uniform grid, a kd-tree, a BVH and Intel Embree on\n"
        "the same scenes and the same rays: build time (median of --build-repeats builds) on\n"
        "each thread count, memory (structure, and structure + mesh, per triangle), Mrays/s\n"
        "(median of --trace-repeats passes) for four workloads, and correctness (brute force\n"
        "on a sample of every workload, and every ray against the first structure). Then rays\n"
        "from inside a closed sphere for each triangle test and padding (leaks per million),\n"
        "a Split Grid parameter sweep on the first scene, and memory against scene size.",
        "Workloads: primary (one ray per pixel of a --width x --height camera framing the\n"
        "scene), path (those rays plus up to --bounces diffuse bounces each, the paper's\n"
        "Figure 3 workload), incoherent (random origins in the scene box, random directions),\n"
        "shadow (any-hit rays from primary hits to a light above the scene).\n"
        "Outputs in --out: results.json (docs/BENCH.md), results.csv, and *.png charts made\n"
        "by scripts/bench_charts.py (python3-matplotlib). Timings depend on the machine's\n"
        "load: compare structures within one run.");
    app.add_option("MESH", o.meshes, "Scenes to measure (any mesh Assimp reads)");
    app.add_option("-o,--out", o.out, "Output folder, created if missing (its parent must exist)")
        ->capture_default_str();
    app.add_flag("--quick", o.quick,
                 "Small workloads and one repeat, for a smoke test in under a minute: 160x120 "
                 "images, 20k incoherent rays, 10k-triangle sphere; flags given explicitly win");
    app.add_option("--structures", o.structures_text,
                   "Structures to measure, comma-separated, the first being the reference of "
                   "the cross-check (default: all this build has: " +
                       fmt::format("{}", fmt::join(sg::bench::structure_names(), ",")) + ")")
        ;
    app.add_option("--threads", o.threads_text,
                   "Thread counts to build and trace with, comma-separated (default: 1 and "
                   "the hardware threads)")
        ;
    app.add_option("--scale-model", o.scale_model,
                   "Mesh the scale series and arena scenes are made from (default: first MESH)");
    app.add_option("--scale-sizes", o.scale_sizes_text,
                   "Triangle counts of the memory-against-size series, comma-separated, e.g. "
                   "1e3,1e4,1e5,1e6,1e7 (default: none). Below the model's size a patch of it, "
                   "above it copies in an arena")
        ;
    app.add_option("--arena-sizes", o.arena_sizes_text,
                   "Also measure arena scenes of these triangle counts (copies of the scale "
                   "model on a floor, make_arena_scene), e.g. 2.5e6,1e7")
        ;
    app.add_option("--width", o.plan.sizes.width, "Image width of the primary and path rays")
        ->check(CLI::Range(1, 16384))->capture_default_str();
    app.add_option("--height", o.plan.sizes.height, "Image height")
        ->check(CLI::Range(1, 16384))->capture_default_str();
    app.add_option("--bounces", o.plan.sizes.bounces, "Diffuse bounces of the path workload")
        ->check(CLI::Range(0u, 64u))->capture_default_str();
    app.add_option("--incoherent-rays", o.plan.sizes.incoherent_rays, "Rays of the incoherent workload")
        ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 30))->capture_default_str();
    app.add_option("--build-repeats", o.plan.build_repeats, "Builds per structure and thread count")
        ->check(CLI::Range(1u, 1000u))->capture_default_str();
    app.add_option("--trace-repeats", o.plan.trace_repeats, "Passes per workload and thread count")
        ->check(CLI::Range(1u, 1000u))->capture_default_str();
    app.add_option("--oracle-rays", o.plan.oracle_rays,
                   "Brute-force sample per workload (fewer on big scenes: at most 4e8 "
                   "ray/triangle tests per sample, at least 20 rays)")
        ->check(CLI::Range(std::size_t{0}, std::size_t{1} << 24))->capture_default_str();
    app.add_option("--watertight-triangles", o.plan.watertight_triangles,
                   "Triangles of the closed sphere of the watertightness workload")
        ->check(CLI::Range(std::size_t{100}, std::size_t{1} << 26))->capture_default_str();
    app.add_option("--watertight-rays", o.plan.watertight_rays,
                   "Rays from inside the sphere, per position (0 skips the workload)")
        ->check(CLI::Range(std::size_t{0}, std::size_t{1} << 30))->capture_default_str();
    app.add_option("--sweep-rays", o.plan.sweep_rays, "Path rays traced per sweep point")
        ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 30))->capture_default_str();
    app.add_flag("--no-sweep", o.no_sweep, "Skip the Split Grid parameter sweep");
    app.add_flag("--no-charts", o.no_charts, "Write results.json and results.csv only");
    app.add_option("--charts-script", o.charts_script, "The chart script")->capture_default_str();
    app.add_option("--seed", o.plan.seed, "Seed of every random workload")->capture_default_str();
    sg::apps::add_build_config_flags(app, o.plan.configs.split_grid, false);
    sg::apps::add_log_flags(app, o.log);
    return sg::apps::run_tool(app, argc, argv, o.log, [&] { bench(app, o); });
}
