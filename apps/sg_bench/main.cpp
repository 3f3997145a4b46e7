/// sg-bench: the Split Grid against a uniform grid, a kd-tree, a BVH and Intel Embree on the
/// same scenes and the same rays: build time, memory, rays per second and correctness, as a
/// table on stdout, results.json, results.csv and PNG charts in the output folder.

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "bench_report.hpp"
#include "bench_run.hpp"
#include "cli_common.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/child_process.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "splitgrid/formats/output_file.hpp"
#include "splitgrid/formats/temporary_paths.hpp"
#include "splitgrid/formats/text_file.hpp"
#include "splitgrid/mesh_order.hpp"
#include "splitgrid/query.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

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
    std::vector<fs::path> dynamic_rigid;
    std::vector<fs::path> dynamic_deform;
    std::uint32_t dynamic_frames = 30;
    std::size_t dynamic_triangles = 1'000'000;
    std::string dynamic_rays_text = "1e4,1e5,1e6";
    std::string dynamic_structures_text;
    bool dynamic_every_frame = false;
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

/// "1e6" or "2500000" as a count of `what` (triangles, rays) in [1, 4e9]; a usage error
/// otherwise.
std::vector<std::size_t> counts_of(const std::string& text, const char* flag,
                                   const char* what = "triangle")
{
    std::vector<std::size_t> counts;
    for (const std::string& item : split_list(text)) {
        double value = 0.0;
        const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), value);
        if (ec != std::errc{} || ptr != item.data() + item.size() || !(value >= 1.0 && value <= 4e9))
            throw CLI::ValidationError(
                fmt::format("{}: {} is not a {} count in [1, 4e9]", flag, item, what));
        counts.push_back(static_cast<std::size_t>(std::llround(value)));
    }
    return counts;
}

/// The structures a comma-separated `text` names (all of `known` when it names none); a usage
/// error naming `flag` for a name not in `known`.
std::vector<std::string> structures_of(const std::string& text,
                                       const std::vector<std::string>& known, const char* flag)
{
    std::vector<std::string> names = split_list(text);
    if (names.empty()) return known;
    for (const std::string& name : names)
        if (std::find(known.begin(), known.end(), name) == known.end())
            throw CLI::ValidationError(
                fmt::format("{}: unknown structure '{}' (this build knows {})", flag, name,
                            fmt::join(known, ", ")));
    return names;
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

/// The charts scripts/bench_charts.py draws, each from a part of the run (docs/BENCH.md).
struct Chart {
    const char* file;
    const char* needs;  ///< why it may be missing, for the notice
};
constexpr Chart charts[] = {
    {"figure3.png", "at least one scene"},
    {"speed_vs_accuracy.png", "the watertightness workload (--watertight-rays above 0)"},
    {"sweep_build_vs_trace.png", "the parameter sweep (left out by --no-sweep)"},
    {"memory_scaling.png", "the scale series (--scale-sizes)"},
    {"dynamic.png", "the dynamic workload (--dynamic-rigid or --dynamic-deform)"},
};

/// Whether the run measures what `chart` draws.
bool chart_has_data(const Chart& chart, const BenchPlan& plan, bool has_scale_model,
                    bool has_scenes, bool has_dynamic)
{
    const std::string file = chart.file;
    if (file == "dynamic.png") return has_dynamic;
    if (!has_scenes) return false;
    if (file == "speed_vs_accuracy.png") return plan.watertight_rays > 0;
    if (file == "sweep_build_vs_trace.png") return plan.sweep;
    if (file == "memory_scaling.png") return !plan.scale_sizes.empty() && has_scale_model;
    return true;
}

/// Every file sg-bench may write into the output folder.
std::vector<fs::path> output_files(const fs::path& out)
{
    std::vector<fs::path> files{out / "results.json", out / "results.csv"};
    for (const Chart& chart : charts) files.push_back(out / chart.file);
    return files;
}

/// Refuses a run whose outputs would replace one of `inputs` (`read_by` as in
/// refuse_output_over_input).
void refuse_outputs_over(const fs::path& out, const std::vector<fs::path>& inputs,
                         const fs::path& read_by = {})
{
    sg::apps::refuse_output_over_input(out, inputs, read_by);
    for (const fs::path& file : output_files(out))
        sg::apps::refuse_output_over_input(file, inputs, read_by);
}

/// Reads a scene, its triangles in the order `mesh_order` names (BenchPlan::mesh_order;
/// "shuffled" with `seed`): every structure is built from the same arrays.
sg::bench::BenchScene load_scene(const fs::path& path, const fs::path& out,
                                 const std::string& mesh_order, std::uint32_t seed)
{
    sg::ImportedMesh imported = sg::import_mesh(path);
    refuse_outputs_over(out, sg::apps::as_paths(imported.report.opened_files), path);
    for (const std::string& warning : imported.report.warnings) spdlog::warn("{}", warning);
    if (imported.mesh.triangles.empty())
        throw sg::InputError(path.string() + ": no usable triangles");
    if (mesh_order != "file") {
        std::vector<std::uint32_t> order;
        if (mesh_order == "morton") {
            order = sg::morton_order(imported.mesh.view());
        } else {
            order.resize(imported.mesh.triangles.size());
            std::iota(order.begin(), order.end(), 0u);
            // Fisher-Yates on the generator's own outputs, which the standard fixes, so that a
            // seed gives the same order with every standard library (std::shuffle's varies).
            std::mt19937 rng(seed);
            for (std::size_t i = order.size(); i > 1; --i)
                std::swap(order[i - 1], order[rng() % i]);
        }
        sg::reorder_triangles(imported.mesh, order);
        spdlog::info("{}: triangles and vertices put in {} order", path.string(), mesh_order);
    }
    return {path.stem().string(), path.string(), std::move(imported.mesh)};
}

/// Scene names are file stems, which repeat (two glTF scenes are both "scene.gltf"): a stem
/// that several scene files share gets its folder's name in front ("balloon_scene"), and a
/// name that still repeats a number behind ("scene_2"), so that every scene's results can be
/// told apart.
void make_names_unique(std::vector<sg::bench::BenchScene>& scenes,
                       const std::vector<fs::path>& files)
{
    const auto count_of = [&](const std::string& name) {
        return std::count_if(scenes.begin(), scenes.end(),
                             [&](const sg::bench::BenchScene& s) { return s.name == name; });
    };
    std::vector<std::string> names;
    for (std::size_t k = 0; k < scenes.size(); ++k) {
        std::string name = scenes[k].name;
        if (k < files.size() && count_of(name) > 1 && files[k].has_parent_path() &&
            files[k].parent_path().has_filename())
            name = files[k].parent_path().filename().string() + "_" + name;
        names.push_back(name);
    }
    for (std::size_t k = 0; k < scenes.size(); ++k) {
        std::string name = names[k];
        for (int n = 2; std::count(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(k),
                                   name) > 0;
             ++n)
            name = names[k] + "_" + std::to_string(n);
        names[k] = name;
        scenes[k].name = name;
    }
}

/// Seconds the chart script may run: matplotlib draws the charts of a full run in seconds,
/// but its first run on a machine builds a font cache first.
constexpr double chart_time_limit_seconds = 600.0;

/// Runs the chart script with its stdout read through a pipe: its "wrote PATH" lines become
/// the list of charts (logged on stderr, so that stdout keeps only the table); its stderr is
/// ours. An interrupt kills the script and removes the temporary files it leaves beside the
/// charts. A failure, or a script still running at the time limit, is a warning, since the
/// JSON and CSV are written already. Returns the charts written.
std::vector<fs::path> make_charts(const Options& options, const fs::path& json)
{
    // Debian's interpreter, where python3-matplotlib lives, before any other python3.
    const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    std::vector<sg::CleanupEntry> cleanup;
    for (const Chart& chart : charts)
        cleanup.push_back(sg::CleanupEntry::stale_temporaries(options.out / chart.file, "tmp"));
    sg::ChildWait wait;
    wait.time_limit_seconds = chart_time_limit_seconds;
    sg::ChildResult child;
    try {
        child = sg::run_program({python, options.charts_script.string(), json.string(),
                                 options.out.string()},
                                wait, "cannot start " + python);
    } catch (const sg::IoError& e) {
        spdlog::warn("charts not made: {}", e.what());
        return {};
    }
    if (child.reaped_elsewhere) return {};  // the interrupt cleanup killed it
    if (child.timed_out) {
        spdlog::warn("charts not made: {} was still running after {:g} s",
                     options.charts_script.string(), chart_time_limit_seconds);
        return {};
    }
    if (!child.exited_cleanly()) {
        spdlog::warn("charts not made: {} {} (python3-matplotlib installed?)",
                     options.charts_script.string(), sg::exit_status_text(child.wait_status));
        return {};
    }
    std::vector<fs::path> written;
    std::istringstream lines(child.output);
    for (std::string line; std::getline(lines, line);)
        if (line.rfind("wrote ", 0) == 0) written.emplace_back(line.substr(6));
    return written;
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

/// Embree, for --version, when this build measures it.
std::vector<sg::LibraryVersion> embree_library()
{
    if (!sg::bench::has_embree()) return {};
    return {{"Embree", sg::bench::embree_version()}};
}

/// The thread counts of --threads (or 1 and the hardware's), each at most the hardware's
/// threads (one warning otherwise, threads_to_use), without repeats.
std::vector<unsigned> thread_counts_of(const std::string& text)
{
    std::vector<unsigned> asked = threads_of(text);
    if (asked.empty()) {
        asked = {1};
        const unsigned hw = sg::apps::threads_that_run(0);
        if (hw > 1) asked.push_back(hw);
    }
    std::vector<unsigned> counts;
    for (const unsigned t : asked) {
        const unsigned used = sg::apps::threads_to_use(t);
        if (std::find(counts.begin(), counts.end(), used) == counts.end()) counts.push_back(used);
    }
    return counts;
}

void bench(CLI::App& app, Options& o)
{
    const auto start = std::chrono::steady_clock::now();
    if (o.quick) apply_quick_defaults(app, o);
    BenchPlan& plan = o.plan;
    plan.sweep = !o.no_sweep;
    plan.structures =
        structures_of(o.structures_text, sg::bench::structure_names(), "--structures");
    plan.thread_counts = thread_counts_of(o.threads_text);
    plan.scale_sizes = counts_of(o.scale_sizes_text, "--scale-sizes");
    const std::vector<std::size_t> arena_sizes = counts_of(o.arena_sizes_text, "--arena-sizes");
    const bool dynamic = !o.dynamic_rigid.empty() || !o.dynamic_deform.empty();
    if (o.meshes.empty() && (arena_sizes.empty() || o.scale_model.empty()) && !dynamic)
        throw CLI::ValidationError("give at least one MESH (or --arena-sizes with --scale-model, "
                                   "or a dynamic scene)");
    sg::bench::DynamicPlan dynamic_plan;
    if (dynamic) {
        dynamic_plan.structures = structures_of(
            o.dynamic_structures_text, sg::bench::frame_structure_names(), "--dynamic-structures");
        for (auto s = dynamic_plan.structures.begin(); s != dynamic_plan.structures.end(); ++s) {
            if (std::find(dynamic_plan.structures.begin(), s, *s) != s)
                throw CLI::ValidationError(
                    fmt::format("--dynamic-structures: '{}' given twice", *s));
        }
        dynamic_plan.frames = o.dynamic_frames;
        if (o.dynamic_every_frame) dynamic_plan.slow_factor = 0.0;
        // Ascending and without repeats: the largest budget is the last (the per-ray cost of
        // the chart and report is read from it).
        std::vector<std::size_t> budgets = counts_of(o.dynamic_rays_text, "--dynamic-rays", "ray");
        std::sort(budgets.begin(), budgets.end());
        budgets.erase(std::unique(budgets.begin(), budgets.end()), budgets.end());
        if (budgets.empty())
            throw CLI::ValidationError("--dynamic-rays: give at least one ray count");
        dynamic_plan.ray_budgets = budgets;
        dynamic_plan.threads = plan.thread_counts.back();
        dynamic_plan.bounces = plan.sizes.bounces;
        dynamic_plan.seed = plan.seed;
        dynamic_plan.configs = plan.configs;
    }

    // The outputs are checked and reserved before any long work: the folder's parent must
    // exist, no output may be an input, and results.json and results.csv get their
    // temporary files now (so a folder that cannot be written is found at once).
    std::vector<fs::path> inputs = o.meshes;
    inputs.insert(inputs.end(), o.dynamic_rigid.begin(), o.dynamic_rigid.end());
    inputs.insert(inputs.end(), o.dynamic_deform.begin(), o.dynamic_deform.end());
    if (!o.scale_model.empty()) inputs.push_back(o.scale_model);
    inputs.push_back(o.charts_script);
    refuse_outputs_over(o.out, inputs);
    const fs::path parent = o.out.has_parent_path() ? o.out.parent_path() : fs::path(".");
    if (!fs::is_directory(parent))
        throw sg::IoError(o.out.string() + ": folder " + parent.string() + " does not exist");
    if (fs::exists(o.out) && !fs::is_directory(o.out))
        throw sg::IoError(o.out.string() + ": exists and is not a folder");
    sg::apps::OutputFolder folder(o.out);
    const fs::path json = o.out / "results.json";
    const fs::path csv = o.out / "results.csv";
    const std::unique_ptr<sg::OutputFile> json_output = sg::apps::reserve_output(json);
    const std::unique_ptr<sg::OutputFile> csv_output = sg::apps::reserve_output(csv);
    for (const Chart& chart : charts)
        sg::apps::report_stale_removed(sg::remove_stale_temporaries(o.out / chart.file, "tmp"));

    std::vector<sg::bench::BenchScene> scenes;
    for (const fs::path& m : o.meshes) {
        spdlog::debug("loading {}", m.string());
        scenes.push_back(load_scene(m, o.out, plan.mesh_order, plan.seed));
    }
    sg::bench::BenchScene model;
    if (!o.scale_model.empty())
        model = load_scene(o.scale_model, o.out, plan.mesh_order, plan.seed);
    else if (!scenes.empty()) model = scenes.front();
    for (const std::size_t n : arena_sizes) {
        sg::bench::BenchScene arena;
        arena.mesh = sg::bench::scale_scene(model.mesh.view(), n, plan.seed);
        arena.name = "arena_" + size_label(arena.mesh.triangles.size());
        arena.source = fmt::format("{} arranged to {} triangles (make_arena_scene)", model.source,
                                   arena.mesh.triangles.size());
        scenes.push_back(std::move(arena));
    }
    make_names_unique(scenes, o.meshes);
    std::vector<sg::bench::DynamicScene> dynamic_scenes;
    const auto add_dynamic = [&](const fs::path& m, sg::bench::Motion motion) {
        const sg::bench::BenchScene loaded = load_scene(m, o.out, plan.mesh_order, plan.seed);
        dynamic_scenes.push_back(sg::bench::make_dynamic_scene(
            loaded.name, loaded.source, loaded.mesh.view(), motion, o.dynamic_triangles));
    };
    for (const fs::path& m : o.dynamic_rigid) add_dynamic(m, sg::bench::Motion::rigid);
    for (const fs::path& m : o.dynamic_deform) add_dynamic(m, sg::bench::Motion::deform);

    const sg::bench::BenchLog log = [](const std::string& line) { spdlog::info("{}", line); };
    // Without a static scene (only dynamic ones) the static part is left out altogether.
    sg::bench::BenchResults results;
    if (!scenes.empty()) results = sg::bench::run_bench(scenes, model, plan, log);
    std::vector<sg::bench::DynamicResult> dynamic_results;
    for (const sg::bench::DynamicScene& d : dynamic_scenes)
        dynamic_results.push_back(sg::bench::run_dynamic(d, dynamic_plan, log));

    sg::bench::RunInfo info;
    info.quick = o.quick;
    info.machine = cpu_model();
    info.hardware_threads = sg::apps::threads_that_run(0);
    info.compiler = "g++ " __VERSION__;
    info.kernel_isa = std::string(sg::isa_name(sg::kernel_isa()));
    info.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    sg::apps::Json document = sg::bench::results_json(results, plan, info);
    document["dynamic"] = sg::bench::dynamic_json(dynamic_results);
    sg::write_text_file(*json_output, document.dump(2) + "\n");
    sg::write_text_file(*csv_output, sg::bench::results_csv(results, plan));
    folder.keep();
    if (!scenes.empty()) std::cout << sg::bench::results_table(results, plan);
    std::cout << sg::bench::dynamic_table(dynamic_results) << std::flush;

    std::vector<fs::path> written{json, csv};
    if (!o.no_charts) {
        const bool has_scale_model = !model.mesh.triangles.empty();
        for (const Chart& chart : charts)
            if (!chart_has_data(chart, plan, has_scale_model, !scenes.empty(),
                                !dynamic_results.empty()))
                spdlog::info("no {}: it needs {}", chart.file, chart.needs);
        for (const fs::path& chart : make_charts(o, json)) written.push_back(chart);
    }
    spdlog::info("the run took {:.1f} s and wrote:",
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    for (const fs::path& file : written) spdlog::info("  {}", file.string());
}

}  // namespace

int main(int argc, char** argv)
{
    Options o;
    CLI::App app{"", "sg-bench"};
    sg::apps::describe_tool(
        app,
        "Measures the Split Grid (built from the build flags, and as splitgrid_poster with the\n"
        "poster preset applied over them) against a uniform grid, a kd-tree, a BVH and Intel\n"
        "Embree on the same scenes and the same rays: build time (median of --build-repeats builds,\n"
        "after one untimed build) on each thread count, memory (structure, and structure + mesh,\n"
        "per triangle, and the most a build held at once), Mrays/s\n"
        "(median of --trace-repeats passes) for four workloads, and correctness (brute force\n"
        "on a sample of every workload, and every ray against the first structure). Then rays\n"
        "from inside a closed sphere for each triangle test and padding (leaks per million),\n"
        "a Split Grid parameter sweep on the first scene, and memory against scene size.\n"
        "Dynamic scenes (--dynamic-rigid, --dynamic-deform; with them MESH may be left\n"
        "out): every frame, each structure rebuilt or refitted on the moved mesh, then one\n"
        "frame of path rays traced per --dynamic-rays budget; time per frame against rays.",
        "Workloads: primary (one ray per pixel of a --width x --height camera framing the\n"
        "scene), path (those rays plus up to --bounces diffuse bounces each, the paper's\n"
        "Figure 3 workload), incoherent (random origins in the scene box, random directions),\n"
        "shadow (any-hit rays from primary hits to a light above the scene).\n"
        "Outputs in -o/--output: results.json (docs/BENCH.md), results.csv, and the charts\n"
        "of scripts/bench_charts.py (python3-matplotlib): figure3.png, speed_vs_accuracy.png\n"
        "(not with --watertight-rays 0), sweep_build_vs_trace.png (not with --no-sweep) and\n"
        "memory_scaling.png (only with --scale-sizes), dynamic.png (only with a dynamic\n"
        "scene). stdout holds the table; progress,\n"
        "notices and the list of files written go to stderr. Timings depend on the\n"
        "machine's load: compare structures within one run.",
        embree_library());
    app.add_option("MESH", o.meshes, "Scenes to measure (any mesh Assimp reads)");
    sg::apps::add_output_option(app, o.out,
                                sg::apps::help_text("Output folder, created if missing (its "
                                                    "parent must exist).",
                                                    {}, o.out.string()),
                                false, "DIR");
    app.add_flag("--quick", o.quick,
                 "Small workloads and one repeat, for a smoke test in under a minute: 160x120 "
                 "images, 20k incoherent rays, 10k-triangle sphere; flags given explicitly win");
    app.add_option("--structures", o.structures_text,
                   sg::apps::help_text("Structures to measure, comma-separated, the first being "
                                       "the reference of the cross-check.",
                                       {},
                                       "all this build has: " +
                                           fmt::format("{}", fmt::join(sg::bench::structure_names(), ","))))
        ->type_name("LIST");
    app.add_option("--threads", o.threads_text,
                   sg::apps::help_text("Thread counts to build and trace with, comma-separated "
                                       "(above the hardware's threads: the hardware's, with a "
                                       "warning).",
                                       "[1, 1024] each", "1 and the hardware threads"))
        ->type_name("LIST");
    app.add_option("--scale-model", o.scale_model,
                   sg::apps::help_text("Mesh the scale series and arena scenes are made from.",
                                       {}, "the first MESH"))
        ->type_name("MESH");
    app.add_option("--scale-sizes", o.scale_sizes_text,
                   sg::apps::help_text("Triangle counts of the memory-against-size series (and "
                                       "its chart), comma-separated, e.g. 1e3,1e4,1e5,1e6,1e7. "
                                       "Below the model's size a patch of it, above it copies "
                                       "in an arena.",
                                       {}, "none"))
        ->type_name("LIST");
    app.add_option("--arena-sizes", o.arena_sizes_text,
                   sg::apps::help_text("Also measure arena scenes of these triangle counts "
                                       "(copies of the scale model on a floor, "
                                       "make_arena_scene), e.g. 2.5e6,1e7.",
                                       {}, "none"))
        ->type_name("LIST");
    sg::apps::add_count_option(app, "--width", o.plan.sizes.width, 1, 16384,
                               "Image width of the primary and path rays.");
    sg::apps::add_count_option(app, "--height", o.plan.sizes.height, 1, 16384, "Image height.");
    sg::apps::add_count_option(app, "--bounces", o.plan.sizes.bounces, 0, 64,
                               "Diffuse bounces of the path workload.");
    sg::apps::add_count_option(app, "--incoherent-rays", o.plan.sizes.incoherent_rays, 1,
                               std::uint64_t{1} << 30, "Rays of the incoherent workload.");
    sg::apps::add_count_option(app, "--build-repeats", o.plan.build_repeats, 1, 1000,
                               "Builds per structure and thread count.");
    sg::apps::add_count_option(app, "--trace-repeats", o.plan.trace_repeats, 1, 1000,
                               "Passes per workload and thread count.");
    sg::apps::add_count_option(app, "--oracle-rays", o.plan.oracle_rays, 0,
                               std::uint64_t{1} << 24,
                               "Brute-force sample per workload (fewer on big scenes: at most "
                               "4e8 ray/triangle tests per sample, at least 20 rays).");
    sg::apps::add_count_option(app, "--watertight-triangles", o.plan.watertight_triangles, 100,
                               std::uint64_t{1} << 26,
                               "Triangles of the closed sphere of the watertightness workload.");
    sg::apps::add_count_option(app, "--watertight-rays", o.plan.watertight_rays, 0,
                               std::uint64_t{1} << 30,
                               "Rays from inside the sphere, per position (0 skips the "
                               "workload and its chart).");
    sg::apps::add_count_option(app, "--sweep-rays", o.plan.sweep_rays, 1, std::uint64_t{1} << 30,
                               "Path rays traced per sweep point.");
    app.add_option("--dynamic-rigid", o.dynamic_rigid,
                   sg::apps::help_text("Dynamic workload: copies of this mesh (enough for "
                                       "--dynamic-triangles) turning and circling on an arena, "
                                       "every structure rebuilt or refitted on each frame and "
                                       "tracing a frame of path rays (repeatable).",
                                       {}, "none"))
        ->type_name("MESH");
    app.add_option("--dynamic-deform", o.dynamic_deform,
                   sg::apps::help_text("Dynamic workload: this mesh twisting and swelling "
                                       "(repeatable).",
                                       {}, "none"))
        ->type_name("MESH");
    sg::apps::add_count_option(app, "--dynamic-frames", o.dynamic_frames, 1, 100'000,
                               "Frames of each dynamic scene.");
    sg::apps::add_count_option(app, "--dynamic-triangles", o.dynamic_triangles, 1,
                               std::uint64_t{1} << 31,
                               "Fewest triangles of a --dynamic-rigid scene.");
    app.add_option("--dynamic-rays", o.dynamic_rays_text,
                   sg::apps::help_text("Path rays traced per frame, comma-separated: each "
                                       "budget is one frame of the path workload, traced "
                                       "after the update.",
                                       {}, o.dynamic_rays_text))
        ->type_name("LIST");
    app.add_option("--dynamic-structures", o.dynamic_structures_text,
                   sg::apps::help_text("Structures of the dynamic workload, comma-separated "
                                       "(the first is the yardstick of the slow rule; the rays "
                                       "come from our BVH, refitted): any of --structures "
                                       "(rebuilt each frame), bvh_refit, embree_low, "
                                       "embree_refit.",
                                       {},
                                       fmt::format("{}", fmt::join(sg::bench::frame_structure_names(), ","))))
        ->type_name("LIST");
    app.add_flag("--dynamic-every-frame", o.dynamic_every_frame,
                 "Run every dynamic structure on every frame (by default one whose update on "
                 "frame 1 takes over 10x the first structure's runs on every tenth frame only)");
    app.add_flag("--no-sweep", o.no_sweep, "Skip the Split Grid parameter sweep (and its chart)");
    app.add_flag("--no-charts", o.no_charts, "Write results.json and results.csv only");
    app.add_option("--charts-script", o.charts_script,
                   sg::apps::help_text("The chart script.", {}, o.charts_script.string()))
        ->type_name("FILE");
    app.add_option("--mesh-order", o.plan.mesh_order,
                   sg::apps::help_text(
                       "Order of every scene's triangles (and of the vertices, by first use), "
                       "the same arrays for every structure: shows how much a structure that "
                       "reads the mesh through triangle ids depends on it. file: as the file "
                       "gives them. morton: along a Morton curve of the triangles' centroids, "
                       "near in space near in memory (morton_order). shuffled: at random "
                       "(with --seed), near in space far apart in memory.",
                       {}, "file"))
        ->check(CLI::IsMember({"file", "morton", "shuffled"}))
        ->type_name("NAME");
    sg::apps::add_count_option(app, "--seed", o.plan.seed, 0,
                               std::numeric_limits<std::uint32_t>::max(),
                               "Seed of every random workload.");
    sg::apps::add_build_config_flags(app, o.plan.configs.split_grid, false);
    sg::apps::add_log_flags(app, o.log);
    return sg::apps::run_tool(app, argc, argv, o.log, [&] { bench(app, o); });
}
