/// sg-trace: traces a batch of rays from a ray file through the Split Grid of a .sg file and
/// writes one hit record per ray (docs/FORMAT.md), for users who trace their own ray sets
/// and for checks against other tracers.

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <memory>
#include <vector>

#include "cli_common.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/output_file.hpp"
#include "splitgrid/formats/ray_file.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/traverse.hpp"
#include "splitgrid/version.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace {

namespace fs = std::filesystem;
using sg::apps::Json;
using Clock = std::chrono::steady_clock;

/// Rays per parallel task: large enough to amortise scheduling, small enough to balance
/// rays of very different cost.
constexpr std::size_t rays_per_block = 256;
constexpr std::uint32_t max_threads = 1024;

struct Options {
    fs::path file;
    fs::path rays;
    fs::path out;
    bool any_hit = false;
    bool strict = false;
    std::uint32_t threads = 0;
    bool json = false;
    sg::apps::LogOptions log;
};

/// The hit record of an any-hit query (docs/FORMAT.md): triangle id 0 if occluded,
/// 0xFFFFFFFF if not; t, u, v are 0 because the query stops at any hit, not the closest.
sg::Hit any_hit_record(bool is_occluded)
{
    sg::Hit hit;
    hit.triangle = is_occluded ? 0u : sg::invalid_triangle;
    hit.t = 0.0f;
    hit.u = 0.0f;
    hit.v = 0.0f;
    return hit;
}

/// Counts the invalid rays. They are the ray generator's fault, not the file's: by default
/// they are traced as misses (as every query answers them) with a warning, so that a wrong
/// generator does not pass for an empty scene; --strict refuses the file instead.
std::size_t check_invalid_rays(const Options& options, const std::vector<sg::Ray>& rays)
{
    const auto is_invalid = [](const sg::Ray& ray) { return !sg::is_valid(ray); };
    const auto invalid = static_cast<std::size_t>(std::count_if(rays.begin(), rays.end(),
                                                                is_invalid));
    if (invalid == 0) return 0;
    const auto first = std::find_if(rays.begin(), rays.end(), is_invalid) - rays.begin();
    const std::string what = fmt::format("{}: {} of {} rays are invalid ({}; the first is ray {})",
                                         options.rays.string(), invalid, rays.size(),
                                         sg::invalid_ray_description, first);
    if (options.strict) throw sg::InputError(what + ": refused by --strict");
    spdlog::warn("{}: the file is well formed, the rays are not; they are written as misses "
                 "(--strict refuses such a file)",
                 what);
    return invalid;
}

void trace(const Options& options)
{
    // An output that would destroy an input, or that cannot be written, is refused before
    // anything is read; the temporary file exists from here on.
    sg::apps::refuse_output_over_input(options.out, {options.file, options.rays});
    const std::unique_ptr<sg::OutputFile> output = sg::apps::reserve_output(options.out);
    const unsigned threads_asked = sg::apps::threads_to_use(options.threads);
    const sg::SgContents contents = sg::read_sg_file(options.file);
    const std::vector<sg::Ray> rays = sg::read_ray_file(options.rays);
    spdlog::debug("{}: {} triangles; {}: {} rays", options.file.string(),
                  contents.mesh.triangles.size(), options.rays.string(), rays.size());
    const std::size_t invalid_rays = check_invalid_rays(options, rays);

    const sg::SplitGrid& grid = contents.grid;
    const sg::MeshView mesh = contents.mesh.view();
    std::vector<sg::Hit> hits(rays.size());

    tbb::task_arena arena(threads_asked == 0 ? tbb::task_arena::automatic
                                             : static_cast<int>(threads_asked));
    const auto start = Clock::now();
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), rays_per_block),
                          [&](const tbb::blocked_range<std::size_t>& block) {
                              for (std::size_t i = block.begin(); i != block.end(); ++i)
                                  hits[i] = options.any_hit
                                                ? any_hit_record(sg::occluded(grid, mesh, rays[i]))
                                                : sg::intersect(grid, mesh, rays[i]);
                          });
    });
    const double seconds = sg::apps::seconds_since(start);
    sg::write_hit_file(*output, hits);

    const auto hit_count = static_cast<std::size_t>(
        std::count_if(hits.begin(), hits.end(), [](const sg::Hit& h) { return h.is_hit(); }));
    const double rays_per_second = seconds > 0.0 ? static_cast<double>(rays.size()) / seconds
                                                 : 0.0;
    const int threads = arena.max_concurrency();
    if (options.json) {
        Json j;
        j["schema_version"] = sg::apps::json_schema_version;
        j["splitgrid_version"] = sg::version_string;
        j["file"] = options.file.string();
        j["rays_file"] = options.rays.string();
        j["hits_file"] = options.out.string();
        j["mode"] = options.any_hit ? "any_hit" : "closest_hit";
        j["threads"] = threads;
        j["ray_count"] = rays.size();
        j["hit_count"] = hit_count;
        j["invalid_rays"] = invalid_rays;
        j["seconds"] = seconds;
        j["rays_per_second"] = rays_per_second;
        std::cout << j.dump(2) << '\n';
        return;
    }
    if (!options.log.shows_summary()) return;
    std::cout << fmt::format("traced {} rays ({}) on {} thread{} in {:.3f} s: {:.0f} rays/s; "
                             "{} hits ({:.1f}%), {} invalid rays, written to {}\n",
                             rays.size(), options.any_hit ? "any hit" : "closest hit", threads,
                             threads == 1 ? "" : "s",
                             seconds, rays_per_second, hit_count,
                             rays.empty() ? 0.0
                                          : 100.0 * static_cast<double>(hit_count) /
                                                static_cast<double>(rays.size()),
                             invalid_rays, options.out.string());
}

}  // namespace

int main(int argc, char** argv)
{
    Options options;
    CLI::App app{"", "sg-trace"};
    sg::apps::describe_tool(
        app,
        "Traces every ray of a ray file through the Split Grid of a .sg file and writes one\n"
        "hit record per ray, in ray order (ray and hit files: docs/FORMAT.md).",
        "Closest hit (default): triangle id (0xFFFFFFFF on a miss; ids are the triangle order\n"
        "of the .sg file), distance t and barycentrics u, v of the nearest hit in\n"
        "[t_min, t_max]. On a miss t is the ray's t_max.\n"
        "--any-hit: triangle id 0 if anything is hit in [t_min, t_max], 0xFFFFFFFF if not;\n"
        "t, u, v are 0.\n"
        "Invalid rays (NaN or infinite origin or direction, zero direction, NaN or infinite\n"
        "t_min, NaN t_max, t_min > t_max) are written as misses (t = the ray's t_max) with a\n"
        "warning that counts them; --strict refuses such a file instead (exit code 2).");
    app.add_option("FILE", options.file, "The .sg file")->required();
    app.add_option("--rays", options.rays, "Input ray file (SGRAY001)")->required();
    sg::apps::add_output_option(app, options.out,
                                "Output hit file (SGHIT001), written atomically; it may not be "
                                "FILE or the ray file");
    app.add_flag("--any-hit", options.any_hit, "Occlusion queries instead of closest hits");
    app.add_flag("--strict", options.strict,
                 "Refuse a ray file with invalid rays (exit code 2, no hit file written) "
                 "instead of tracing them as misses with a warning");
    sg::apps::add_count_option(app, "--threads", options.threads, 0, max_threads,
                               "Worker threads, 0 = all hardware threads.");
    app.add_flag("--json", options.json, "Print one JSON object (docs/STATS_JSON.md) instead "
                                         "of the summary");
    sg::apps::add_log_flags(app, options.log);
    return sg::apps::run_tool(app, argc, argv, options.log, [&] { trace(options); });
}
