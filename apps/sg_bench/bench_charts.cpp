// sg-bench's charts (bench_charts.hpp).

#include "bench_charts.hpp"

#include <sstream>
#include <string>

#include "splitgrid/error.hpp"
#include "splitgrid/formats/child_process.hpp"
#include "splitgrid/formats/temporary_paths.hpp"

#include <spdlog/spdlog.h>

namespace sg::bench {
namespace {

constexpr Chart chart_list[] = {
    {"figure3.png", "at least one scene"},
    {"speed_vs_accuracy.png", "the watertightness workload (--watertight-rays above 0)"},
    {"sweep_build_vs_trace.png", "the parameter sweep (left out by --no-sweep)"},
    {"memory_scaling.png", "the scale series (--scale-sizes)"},
    {"dynamic.png", "the dynamic workload (--dynamic-rigid or --dynamic-deform)"},
    {"point_workloads.png",
     "a point workload (--count-rays, --occupancy-points or --closest-points above 0)"},
    {"inside_tests.png", "the inside tests (--inside-vertices above 0)"},
};

/// Seconds the chart script may run: matplotlib draws the charts of a full run in seconds,
/// but its first run on a machine builds a font cache first.
constexpr double chart_time_limit_seconds = 600.0;

}  // namespace

std::span<const Chart> charts() noexcept { return chart_list; }

bool chart_has_data(const Chart& chart, const BenchPlan& plan, bool has_scale_model,
                    bool has_scenes, bool has_dynamic)
{
    const std::string file = chart.file;
    if (file == "dynamic.png") return has_dynamic;
    if (!has_scenes) return false;
    if (file == "speed_vs_accuracy.png") return plan.watertight_rays > 0;
    if (file == "sweep_build_vs_trace.png") return plan.sweep;
    if (file == "memory_scaling.png") return !plan.scale_sizes.empty() && has_scale_model;
    if (file == "point_workloads.png") return plan.points.any();
    if (file == "inside_tests.png") return plan.points.inside_vertices > 0;
    return true;
}

std::vector<std::filesystem::path> make_charts(const std::filesystem::path& script,
                                               const std::filesystem::path& json,
                                               const std::filesystem::path& out)
{
    namespace fs = std::filesystem;
    // Debian's interpreter, where python3-matplotlib lives, before any other python3.
    const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    // The script writes each chart to a temporary beside it first; an interrupt, which kills
    // the script, sweeps them.
    std::vector<CleanupEntry> cleanup;
    for (const Chart& chart : chart_list)
        cleanup.push_back(CleanupEntry::stale_temporaries(out / chart.file, "tmp"));
    ChildWait wait;
    wait.time_limit_seconds = chart_time_limit_seconds;
    ChildResult child;
    try {
        child = run_program({python, script.string(), json.string(), out.string()}, wait,
                            "cannot start " + python);
    } catch (const IoError& e) {
        spdlog::warn("charts not made: {}", e.what());
        return {};
    }
    if (child.reaped_elsewhere) return {};  // the interrupt cleanup killed it
    if (child.timed_out) {
        spdlog::warn("charts not made: {} was still running after {:g} s", script.string(),
                     chart_time_limit_seconds);
        return {};
    }
    if (!child.exited_cleanly()) {
        spdlog::warn("charts not made: {} {} (python3-matplotlib installed?)", script.string(),
                     exit_status_text(child.wait_status));
        return {};
    }
    std::vector<fs::path> written;
    std::istringstream lines(child.output);
    for (std::string line; std::getline(lines, line);)
        if (line.rfind("wrote ", 0) == 0) written.emplace_back(line.substr(6));
    return written;
}

}  // namespace sg::bench
