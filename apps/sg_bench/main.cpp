/// sg-bench: the Split Grid against a uniform grid, a kd-tree, a BVH and Intel Embree on the
/// same scenes and the same rays: build time, memory, rays per second and correctness, as a
/// table on stdout, results.json, results.csv and PNG charts in the output folder. This file
/// runs what the options (bench_options.hpp) ask for: the scenes are read, the outputs
/// reserved, the measurements run (bench_run.hpp, dynamic.hpp) and written.

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "bench_charts.hpp"
#include "bench_options.hpp"
#include "bench_report.hpp"
#include "bench_run.hpp"
#include "cli_common.hpp"
#include "splitgrid/error.hpp"
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
using sg::bench::BenchOptions;
using sg::bench::BenchPlan;
using sg::bench::Chart;

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

/// Every file sg-bench may write into the output folder.
std::vector<fs::path> output_files(const fs::path& out)
{
    std::vector<fs::path> files{out / "results.json", out / "results.csv"};
    for (const Chart& chart : sg::bench::charts()) files.push_back(out / chart.file);
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

void bench(const CLI::App& app, BenchOptions& o)
{
    const auto start = std::chrono::steady_clock::now();
    const sg::bench::ResolvedOptions resolved = sg::bench::resolve_options(app, o);
    const std::string isa = sg::apps::kernel_isa_in_use();
    const BenchPlan& plan = resolved.plan;
    const sg::bench::DynamicPlan& dynamic_plan = resolved.dynamic_plan;
    const std::vector<std::size_t>& arena_sizes = resolved.arena_sizes;

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
    std::unique_ptr<sg::apps::OutputFolder> points_folder;
    if (!plan.save_points.empty()) {
        const fs::path& points = plan.save_points;
        const fs::path points_parent =
            points.has_parent_path() ? points.parent_path() : fs::path(".");
        if (!fs::is_directory(points_parent))
            throw sg::IoError(points.string() + ": folder " + points_parent.string() +
                              " does not exist (--save-points)");
        if (fs::exists(points) && !fs::is_directory(points))
            throw sg::IoError(points.string() + ": exists and is not a folder (--save-points)");
        points_folder = std::make_unique<sg::apps::OutputFolder>(points);
    }
    sg::apps::OutputFolder folder(o.out);
    const fs::path json = o.out / "results.json";
    const fs::path csv = o.out / "results.csv";
    const std::unique_ptr<sg::OutputFile> json_output = sg::apps::reserve_output(json);
    const std::unique_ptr<sg::OutputFile> csv_output = sg::apps::reserve_output(csv);
    for (const Chart& chart : sg::bench::charts())
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
    info.kernel_isa = isa;
    info.seconds = sg::apps::seconds_since(start);

    sg::apps::Json document = sg::bench::results_json(results, plan, info);
    document["dynamic"] = sg::bench::dynamic_json(dynamic_results);
    sg::write_text_file(*json_output, document.dump(2) + "\n");
    sg::write_text_file(*csv_output, sg::bench::results_csv(results, plan));
    folder.keep();
    if (points_folder) points_folder->keep();
    if (!scenes.empty()) std::cout << sg::bench::results_table(results, plan);
    std::cout << sg::bench::dynamic_table(dynamic_results) << std::flush;

    std::vector<fs::path> written{json, csv};
    if (!o.no_charts) {
        const bool has_scale_model = !model.mesh.triangles.empty();
        for (const Chart& chart : sg::bench::charts())
            if (!sg::bench::chart_has_data(chart, plan, has_scale_model, !scenes.empty(),
                                           !dynamic_results.empty()))
                spdlog::info("no {}: it needs {}", chart.file, chart.needs);
        for (const fs::path& chart : sg::bench::make_charts(o.charts_script, json, o.out))
            written.push_back(chart);
    }
    spdlog::info("the run took {:.1f} s and wrote:", sg::apps::seconds_since(start));
    for (const fs::path& file : written) spdlog::info("  {}", file.string());
}

}  // namespace

int main(int argc, char** argv)
{
    BenchOptions o;
    CLI::App app{"", "sg-bench"};
    sg::bench::add_bench_options(app, o);
    return sg::apps::run_tool(app, argc, argv, o.log, [&] { bench(app, o); });
}
