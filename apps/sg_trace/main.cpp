/// sg-trace: traces a batch of rays from a ray file through the Split Grid of a .sg file and
/// writes the answer of one query per ray (closest hit, any hit, hit count or every hit;
/// docs/FORMAT.md), for users who trace their own ray sets and for checks against other
/// tracers.

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iostream>
#include <iterator>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cli_common.hpp"
#include "invalid_entries.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/intersection_file.hpp"
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

/// What sg-trace answers for each ray (--query).
enum class Query { closest, any, count, all };

/// --query's names, in Query's order.
constexpr std::string_view query_names[] = {"closest", "any", "count", "all"};
/// The JSON's older name of each query ("mode"), in Query's order.
constexpr std::string_view mode_names[] = {"closest_hit", "any_hit", "hit_count", "all_hits"};
/// The summary's name of each query, in Query's order.
constexpr std::string_view query_titles[] = {"closest hit", "any hit", "hit count", "all hits"};

struct Options {
    fs::path file;
    fs::path rays;
    fs::path out;
    std::string query_name = "closest";
    bool any_hit = false;
    bool strict = false;
    std::uint32_t threads = 0;
    bool json = false;
    sg::apps::LogOptions log;

    /// --query, or Query::any for --any-hit (the two are never given together).
    [[nodiscard]] Query query() const
    {
        if (any_hit) return Query::any;
        const auto* name = std::find(std::begin(query_names), std::end(query_names), query_name);
        return static_cast<Query>(name - std::begin(query_names));
    }
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

/// The scene and rays every query runs on, and the arena of --threads.
struct TraceJob {
    const sg::SplitGrid& grid;
    sg::MeshView mesh;
    std::span<const sg::Ray> rays;
    tbb::task_arena& arena;

    /// Calls work(first, last) for blocks of about rays_per_block rays, in parallel.
    template <class Work>
    void for_blocks(Work work) const
    {
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), rays_per_block),
                              [&](const tbb::blocked_range<std::size_t>& block) {
                                  work(block.begin(), block.end());
                              });
        });
    }
};

/// A query's answers, ready to be written, and what the summary says of them.
struct Answer {
    std::function<void(sg::OutputFile&)> write;
    std::size_t hit_rays = 0;      ///< rays that hit something
    std::uint64_t total_hits = 0;  ///< count and all: the hits of all rays
};

template <class T>
std::span<T> part_of(std::vector<T>& all, std::size_t first, std::size_t last)
{
    return std::span<T>(all).subspan(first, last - first);
}

Answer closest_or_any(const TraceJob& job, Query query)
{
    auto hits = std::make_shared<std::vector<sg::Hit>>(job.rays.size());
    if (query == Query::closest) {
        job.for_blocks([&](std::size_t first, std::size_t last) {
            sg::intersect(job.grid, job.mesh, job.rays.subspan(first, last - first),
                          part_of(*hits, first, last));
        });
    } else {
        std::vector<std::uint8_t> occluded(job.rays.size());
        job.for_blocks([&](std::size_t first, std::size_t last) {
            sg::occluded(job.grid, job.mesh, job.rays.subspan(first, last - first),
                         part_of(occluded, first, last));
        });
        for (std::size_t i = 0; i < hits->size(); ++i)
            (*hits)[i] = any_hit_record(occluded[i] != 0);
    }
    Answer answer{[hits](sg::OutputFile& output) { sg::write_hit_file(output, *hits); }};
    answer.hit_rays = static_cast<std::size_t>(
        std::count_if(hits->begin(), hits->end(), [](const sg::Hit& h) { return h.is_hit(); }));
    return answer;
}

Answer count(const TraceJob& job)
{
    auto counts = std::make_shared<std::vector<std::int32_t>>(job.rays.size());
    job.for_blocks([&](std::size_t first, std::size_t last) {
        sg::count_intersections(job.grid, job.mesh, job.rays.subspan(first, last - first),
                                part_of(*counts, first, last));
    });
    Answer answer{[counts](sg::OutputFile& output) { sg::write_hit_count_file(output, *counts); }};
    for (const std::int32_t c : *counts) {
        answer.hit_rays += c > 0 ? 1 : 0;
        answer.total_hits += static_cast<std::uint64_t>(c);
    }
    return answer;
}

Answer all(const TraceJob& job)
{
    // Ray ids are 32-bit in the list (Open3D's layout); such a ray file would take 128 GiB.
    constexpr std::size_t max_rays = std::numeric_limits<std::uint32_t>::max();
    if (job.rays.size() > max_rays)
        throw sg::InputError(fmt::format("--query all lists the hits of at most {} rays; the "
                                         "ray file has {}",
                                         max_rays, job.rays.size()));
    // One list per fixed block of rays, joined in ray order: the file does not depend on the
    // thread count.
    std::vector<sg::IntersectionList> parts((job.rays.size() + rays_per_block - 1) /
                                            rays_per_block);
    job.arena.execute([&] {
        tbb::parallel_for(std::size_t{0}, parts.size(), [&](std::size_t part) {
            const std::size_t first = part * rays_per_block;
            const std::size_t last = std::min(job.rays.size(), first + rays_per_block);
            sg::list_intersections(job.grid, job.mesh, job.rays.subspan(first, last - first),
                                   parts[part]);
        });
    });
    auto list = std::make_shared<sg::IntersectionList>(sg::concatenate(parts));
    Answer answer{[list](sg::OutputFile& output) { sg::write_hit_list_file(output, *list); }};
    for (std::size_t k = 0; k < list->ray_count(); ++k)
        answer.hit_rays += list->ray_splits[k + 1] > list->ray_splits[k] ? 1 : 0;
    answer.total_hits = list->hits.size();
    return answer;
}

void trace(const Options& options)
{
    // An output that would destroy an input, or that cannot be written, is refused before
    // anything is read; the temporary file exists from here on.
    sg::apps::refuse_output_over_input(options.out, {options.file, options.rays});
    const std::unique_ptr<sg::OutputFile> output = sg::apps::reserve_output(options.out);
    const unsigned threads_asked = sg::apps::threads_to_use(options.threads);
    const std::string isa = sg::apps::kernel_isa_in_use();
    const sg::SgContents contents = sg::read_sg_file(options.file);
    const std::vector<sg::Ray> rays = sg::read_ray_file(options.rays);
    spdlog::debug("{}: {} triangles; {}: {} rays", options.file.string(),
                  contents.mesh.triangles.size(), options.rays.string(), rays.size());
    const std::size_t invalid_rays = sg::apps::check_invalid_entries(
        options.rays, rays, [](const sg::Ray& ray) { return !sg::is_valid(ray); },
        {"ray", sg::invalid_ray_description, "misses"}, options.strict);

    tbb::task_arena arena(threads_asked == 0 ? tbb::task_arena::automatic
                                             : static_cast<int>(threads_asked));
    const TraceJob job{contents.grid, contents.mesh.view(), rays, arena};
    const Query query = options.query();
    // The time covers the queries and, for all hits, joining the lists; not reading the
    // inputs nor writing the output.
    const auto start = Clock::now();
    Answer answer;
    switch (query) {
    case Query::closest:
    case Query::any: answer = closest_or_any(job, query); break;
    case Query::count: answer = count(job); break;
    case Query::all: answer = all(job); break;
    }
    const double seconds = sg::apps::seconds_since(start);
    answer.write(*output);

    const double rays_per_second = seconds > 0.0 ? static_cast<double>(rays.size()) / seconds
                                                 : 0.0;
    const int threads = arena.max_concurrency();
    const bool counts_hits = query == Query::count || query == Query::all;
    const auto q = static_cast<std::size_t>(query);
    if (options.json) {
        Json j;
        j["schema_version"] = sg::apps::json_schema_version;
        j["splitgrid_version"] = sg::version_string;
        j["file"] = options.file.string();
        j["rays_file"] = options.rays.string();
        j["hits_file"] = options.out.string();
        j["query"] = query_names[q];
        j["mode"] = mode_names[q];
        j["threads"] = threads;
        j["isa"] = isa;
        j["ray_count"] = rays.size();
        j["hit_count"] = answer.hit_rays;
        if (counts_hits) j["total_hits"] = answer.total_hits;
        j["invalid_rays"] = invalid_rays;
        j["seconds"] = seconds;
        j["rays_per_second"] = rays_per_second;
        std::cout << j.dump(2) << '\n';
        return;
    }
    if (!options.log.shows_summary()) return;
    const double hit_percent = rays.empty() ? 0.0
                                            : 100.0 * static_cast<double>(answer.hit_rays) /
                                                  static_cast<double>(rays.size());
    const std::string hits =
        counts_hits ? fmt::format("{} rays hit ({:.1f}%), {} hits in all", answer.hit_rays,
                                  hit_percent, answer.total_hits)
                    : fmt::format("{} hits ({:.1f}%)", answer.hit_rays, hit_percent);
    std::cout << fmt::format("traced {} rays ({}) on {} thread{} in {:.3f} s: {:.0f} rays/s; "
                             "{}, {} invalid rays, written to {}\n",
                             rays.size(), query_titles[q], threads, threads == 1 ? "" : "s",
                             seconds, rays_per_second, hits, invalid_rays, options.out.string());
}

}  // namespace

int main(int argc, char** argv)
{
    Options options;
    CLI::App app{"", "sg-trace"};
    sg::apps::describe_tool(
        app,
        "Traces every ray of a ray file through the Split Grid of a .sg file and writes the\n"
        "answer of one query per ray, in ray order (the files: docs/FORMAT.md).",
        "Queries (--query):\n"
        "  closest (default): a hit file (SGHIT001), per ray the triangle id (0xFFFFFFFF on a\n"
        "    miss; ids are the triangle order of the .sg file), distance t and barycentrics\n"
        "    u, v of the nearest hit in [t_min, t_max]. On a miss t is the ray's t_max.\n"
        "  any: the same hit file, triangle id 0 if anything is hit in [t_min, t_max],\n"
        "    0xFFFFFFFF if not; t, u, v are 0 (the search stops at the first hit it meets).\n"
        "    --any-hit is the same.\n"
        "  count: a hit count file (SGCNT001), per ray an int32: the distinct triangles hit in\n"
        "    [t_min, t_max], a ray through an edge or a vertex counting as a slightly moved\n"
        "    ray would (exact), so its parity tells inside from outside of a closed mesh.\n"
        "  all: a hit list file (SGALL001), every hit of every ray in Open3D's layout:\n"
        "    ray_splits (ray k's hits are hits[ray_splits[k] .. ray_splits[k+1])), then per\n"
        "    hit ray id, triangle id, t, u, v; each ray's hits sorted by t, then triangle id,\n"
        "    each triangle once.\n"
        "Invalid rays (NaN or infinite origin or direction, zero direction, NaN or infinite\n"
        "t_min, NaN t_max, t_min > t_max) are written as misses (t = the ray's t_max; count 0;\n"
        "no hits) with a warning that counts them; --strict refuses such a file instead (exit\n"
        "code 2). The files do not depend on --threads.");
    app.add_option("FILE", options.file, "The .sg file")->required();
    app.add_option("--rays", options.rays, "Input ray file (SGRAY001)")->required();
    sg::apps::add_output_option(app, options.out,
                                "Output file (SGHIT001, SGCNT001 or SGALL001 by --query), "
                                "written atomically; it may not be FILE or the ray file");
    CLI::Option* query =
        app.add_option("--query", options.query_name,
                       sg::apps::help_text("What to find along each ray: closest, any, count "
                                           "or all (see below).",
                                           {}, "closest"))
            ->check(CLI::IsMember({"closest", "any", "count", "all"}));
    CLI::Option* any_hit = app.add_flag("--any-hit", options.any_hit,
                                        "The same as --query any (kept for older scripts); not "
                                        "together with --query");
    app.add_flag("--strict", options.strict,
                 "Refuse a ray file with invalid rays (exit code 2, no output written) "
                 "instead of tracing them as misses with a warning");
    sg::apps::add_count_option(app, "--threads", options.threads, 0, max_threads,
                               "Worker threads, 0 = all hardware threads.");
    app.add_flag("--json", options.json, "Print one JSON object (docs/STATS_JSON.md) instead "
                                         "of the summary");
    sg::apps::add_log_flags(app, options.log);
    app.parse_complete_callback([query, any_hit] {
        if (query->count() > 0 && any_hit->count() > 0)
            throw CLI::ValidationError("--any-hit and --query are both given; --any-hit is "
                                       "--query any: give one of them");
    });
    return sg::apps::run_tool(app, argc, argv, options.log, [&] { trace(options); });
}
