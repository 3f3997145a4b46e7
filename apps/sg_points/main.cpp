/// sg-points: point queries against the mesh of a .sg file, through its Split Grid: for each
/// point of a point file (or a text file of points), inside or outside (occupancy), written
/// to a point result file (docs/FORMAT.md, section 6).

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "invalid_entries.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/output_file.hpp"
#include "splitgrid/formats/point_file.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/mesh_edges.hpp"
#include "splitgrid/occupancy.hpp"
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

/// Points per parallel task: each costs --nsamples walks through the grid.
constexpr std::size_t points_per_block = 256;
constexpr std::uint32_t max_threads = 1024;
/// The most rays per point: a vote of more rays changes nothing on a closed mesh and little
/// on an open one.
constexpr std::uint32_t max_nsamples = 999;

struct Options {
    fs::path file;
    fs::path points;
    fs::path out;
    std::string query;
    std::uint32_t nsamples = 1;
    bool strict = false;
    std::uint32_t threads = 0;
    bool json = false;
    sg::apps::LogOptions log;
};

/// Warns once when inside and outside by parity are not defined everywhere: some edge is
/// shared by an odd number of triangles.
void warn_if_open(const Options& options, const sg::EdgeReport& edges)
{
    if (edges.is_closed()) return;
    spdlog::warn("{}: the mesh is not closed: {} open edges (shared by an odd number of "
                 "triangles) and {} non-manifold edges (shared by more than two) of {}; inside "
                 "and outside may be wrong near the openings (--nsamples above 1 takes the "
                 "majority of more rays)",
                 options.file.string(), edges.open_edges, edges.nonmanifold_edges, edges.edges);
}

void occupancy(const Options& options)
{
    // An output that would destroy an input, or that cannot be written, is refused before
    // anything is read; the temporary file exists from here on.
    sg::apps::refuse_output_over_input(options.out, {options.file, options.points});
    const std::unique_ptr<sg::OutputFile> output = sg::apps::reserve_output(options.out);
    const unsigned threads_asked = sg::apps::threads_to_use(options.threads);
    const std::string isa = sg::apps::kernel_isa_in_use();
    const sg::SgContents contents = sg::read_sg_file(options.file);
    const sg::LoadedPoints loaded = sg::read_points(options.points);
    const std::vector<sg::Vec3f>& points = loaded.points;
    const bool from_text = loaded.source == sg::PointSource::text;
    spdlog::debug("{}: {} triangles; {}: {} points ({})", options.file.string(),
                  contents.mesh.triangles.size(), options.points.string(), points.size(),
                  from_text ? "text" : "point file");
    const std::size_t nonfinite = sg::apps::check_invalid_entries(
        options.points, points, [](sg::Vec3f p) { return !sg::is_finite(p); },
        {"point", "a NaN or infinite coordinate", "NaN"}, options.strict);

    tbb::task_arena arena(threads_asked == 0 ? tbb::task_arena::automatic
                                             : static_cast<int>(threads_asked));
    const sg::MeshView mesh = contents.mesh.view();
    sg::EdgeReport edges;
    arena.execute([&] { edges = sg::edge_report(mesh); });
    warn_if_open(options, edges);

    std::vector<float> inside(points.size());
    const auto start = Clock::now();
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), points_per_block),
                          [&](const tbb::blocked_range<std::size_t>& block) {
                              const std::size_t n = block.end() - block.begin();
                              sg::compute_occupancy(
                                  contents.grid, mesh,
                                  std::span<const sg::Vec3f>(points).subspan(block.begin(), n),
                                  std::span<float>(inside).subspan(block.begin(), n),
                                  options.nsamples);
                          });
    });
    const double seconds = sg::apps::seconds_since(start);
    sg::write_occupancy_file(*output, inside);

    const auto inside_count =
        static_cast<std::size_t>(std::count(inside.begin(), inside.end(), 1.0f));
    const std::size_t outside_count = points.size() - inside_count - nonfinite;
    const double points_per_second =
        seconds > 0.0 ? static_cast<double>(points.size()) / seconds : 0.0;
    const int threads = arena.max_concurrency();
    if (options.json) {
        Json j;
        j["schema_version"] = sg::apps::json_schema_version;
        j["splitgrid_version"] = sg::version_string;
        j["file"] = options.file.string();
        j["points_file"] = options.points.string();
        j["points_format"] = from_text ? "text" : "binary";
        j["output"] = options.out.string();
        j["query"] = options.query;
        j["isa"] = isa;
        j["nsamples"] = options.nsamples;
        j["threads"] = threads;
        j["point_count"] = points.size();
        j["inside"] = inside_count;
        j["outside"] = outside_count;
        j["nonfinite_points"] = nonfinite;
        j["edges"] = sg::apps::to_json(edges);
        j["seconds"] = seconds;
        j["points_per_second"] = points_per_second;
        std::cout << j.dump(2) << '\n';
        return;
    }
    if (!options.log.shows_summary()) return;
    std::cout << fmt::format("occupancy of {} points ({} ray{} per point) on {} thread{} in "
                             "{:.3f} s: {:.0f} points/s; {} inside, {} outside, {} non-finite, "
                             "written to {}\n",
                             points.size(), options.nsamples, options.nsamples == 1 ? "" : "s",
                             threads, threads == 1 ? "" : "s", seconds, points_per_second,
                             inside_count, outside_count, nonfinite, options.out.string());
}

}  // namespace

int main(int argc, char** argv)
{
    Options options;
    CLI::App app{"", "sg-points"};
    sg::apps::describe_tool(
        app,
        "Answers a query for every point of a point file against the mesh of a .sg file,\n"
        "through its Split Grid, and writes one answer per point, in point order (the files:\n"
        "docs/FORMAT.md).",
        "Points (--points): a point file (SGPTS001: 8 magic bytes, a uint64 count, float32\n"
        "x, y, z per point) or a text or CSV file, one point 'x y z' per line, separated by\n"
        "commas and/or blanks; inf and nan are allowed, blank lines and lines starting with #\n"
        "are skipped, and a first line that does not start with a number is a header. So a\n"
        "text file is all it takes: no converter is needed. An error names the line:\n"
        "'error: pts.csv:3: field 2 'x' is not a number'. The two are told apart by the\n"
        "content (a point file starts with SGPTS).\n"
        "Queries (--query):\n"
        "  occupancy: an occupancy file (SGOCC001: 8 magic bytes, a uint64 count, a float32\n"
        "    per point): 1 inside, 0 outside, by the parity of the triangles a ray from the\n"
        "    point crosses, counted exactly (edges and vertices decided as for a slightly\n"
        "    moved ray), so every point not within rounding of the surface is answered right\n"
        "    on a closed mesh; --nsamples rays per point take a majority vote, which helps\n"
        "    only where the mesh is not closed. A mesh with edges shared by an odd number of\n"
        "    triangles (open edges) gets one warning naming how many open and non-manifold\n"
        "    edges it has. Points outside the mesh's box are outside.\n"
        "Points with a NaN or infinite coordinate are answered NaN with a warning that counts\n"
        "them; --strict refuses such a file instead (exit code 2). The output does not\n"
        "depend on --threads.");
    app.add_option("FILE", options.file, "The .sg file")->required();
    app.add_option("--points", options.points,
                   "Input points: a point file (SGPTS001) or a text or CSV file of 'x y z' lines")
        ->required();
    sg::apps::add_output_option(app, options.out,
                                "Output file (SGOCC001 for occupancy), written atomically; it "
                                "may not be FILE or the points file");
    app.add_option("--query", options.query,
                   "What to answer for each point: occupancy (see below).")
        ->required()
        ->check(CLI::IsMember({"occupancy"}));
    CLI::Option* nsamples = sg::apps::add_count_option(
        app, "--nsamples", options.nsamples, 1, max_nsamples,
        "Rays per point for occupancy, an odd number: the first along the axis that leaves the "
        "mesh's box soonest, the others spread evenly over the sphere; the majority decides.");
    app.add_flag("--strict", options.strict,
                 "Refuse a points file with NaN or infinite coordinates (exit code 2, no output "
                 "written) instead of answering them NaN with a warning");
    sg::apps::add_count_option(app, "--threads", options.threads, 0, max_threads,
                               "Worker threads, 0 = all hardware threads.");
    app.add_flag("--json", options.json, "Print one JSON object (docs/STATS_JSON.md) instead "
                                         "of the summary");
    sg::apps::add_log_flags(app, options.log);
    app.parse_complete_callback([&options, nsamples] {
        if (options.nsamples % 2 == 0)
            throw CLI::ValidationError(fmt::format(
                "{} {} is even; give an odd number (the majority of the rays decides)",
                nsamples->get_name(), options.nsamples));
    });
    return sg::apps::run_tool(app, argc, argv, options.log, [&] { occupancy(options); });
}
