#include "points_options.hpp"

#include <algorithm>
#include <cctype>
#include <memory>

#include "grid_field.hpp"

#include <spdlog/fmt/fmt.h>

namespace sg::apps {
namespace {

/// The most rays per point: a vote of more rays changes nothing on a closed mesh and little
/// on an open one.
constexpr std::uint32_t max_nsamples = 999;
constexpr std::uint32_t max_threads = 1024;
constexpr double max_padding = 10.0;

/// The options as CLI11 reads them, before they are checked together.
struct RawOptions {
    std::string query;
    std::string grid;
    double max_distance = 0.0;
    CLI::Option* points = nullptr;
    CLI::Option* grid_option = nullptr;
    CLI::Option* padding = nullptr;
    CLI::Option* nsamples = nullptr;
    CLI::Option* max_distance_option = nullptr;
};

CLI::Validator grid_counts_validator()
{
    return CLI::Validator(
        [](std::string& text) -> std::string {
            GridCounts counts{};
            return parse_grid_counts(text, counts);
        },
        "", "");
}

bool has_extension(const std::filesystem::path& path, std::string_view extension)
{
    std::string e = path.extension().string();
    std::transform(e.begin(), e.end(), e.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return e == extension;
}

void check_together(PointsOptions& options, const RawOptions& raw)
{
    for (const PointQuery q : every_query())
        if (raw.query == query_name(q)) options.query = q;
    const bool on_grid = raw.grid_option->count() > 0;
    if (on_grid && raw.points->count() > 0)
        throw CLI::ValidationError(
            "--points and --grid are both given: give one (the points "
            "of a file, or a grid of points around the mesh)");
    if (!on_grid && raw.points->count() == 0)
        throw CLI::ValidationError(
            "give the points to query: --points FILE, or --grid NX,NY,NZ "
            "for a grid of points around the mesh");
    if (raw.padding->count() > 0 && !on_grid)
        throw CLI::ValidationError(
            fmt::format("--padding {} applies to --grid only", options.padding));
    if (raw.nsamples->count() > 0 && !casts_rays(options.query))
        throw CLI::ValidationError(fmt::format(
            "--nsamples {} applies to --query occupancy and signed-distance (rays per point), "
            "not to --query {}",
            options.nsamples, query_name(options.query)));
    if (options.nsamples % 2 == 0)
        throw CLI::ValidationError(fmt::format(
            "--nsamples {} is even; give an odd number (the majority of the rays decides)",
            options.nsamples));
    if (raw.max_distance_option->count() > 0) {
        if (!measures_distance(options.query))
            throw CLI::ValidationError(fmt::format(
                "--max-distance {} applies to --query distance, signed-distance and closest, "
                "not to --query {}",
                raw.max_distance, query_name(options.query)));
        options.max_distance = static_cast<float>(raw.max_distance);
        if (!(options.max_distance > 0.0f))
            throw CLI::ValidationError(
                fmt::format("--max-distance {} is 0 in float32; give a larger distance",
                            raw.max_distance));
    }
    if (!on_grid) return;
    if (const std::string why = why_no_grid_field(); !why.empty()) throw CLI::ValidationError(why);
    if (!has_extension(options.out, ".vti"))
        throw CLI::ValidationError(fmt::format(
            "-o {}: --grid writes VTK image data; name the output FILE.vti (ParaView picks its "
            "reader by the extension)",
            options.out.string()));
    GridCounts counts{};
    (void)parse_grid_counts(raw.grid, counts);  // checked by the option's validator
    options.grid = counts;
}

}  // namespace

void add_points_options(CLI::App& app, PointsOptions& options)
{
    // The raw values live as long as the app: the parse callback reads them.
    auto raw = std::make_shared<RawOptions>();
    app.add_option("FILE", options.file, "The .sg file")->required();
    raw->points = app.add_option("--points", options.points,
                                 help_text("Input points: a point file (SGPTS001) or a text or "
                                           "CSV file of 'x y z' lines; this or --grid.",
                                           "", "none"));
    raw->grid_option =
        app.add_option("--grid", raw->grid,
                       help_text(fmt::format("Instead of --points: a grid of NX x NY x NZ "
                                             "points around the mesh (x fastest), e.g. "
                                             "96,96,96; the output is VTK image data (.vti) "
                                             "for ParaView. At most {} points in all.",
                                             max_grid_points),
                                 "", "none"))
            ->type_name("NX,NY,NZ")
            ->check(grid_counts_validator());
    raw->padding = add_real_option(
        app, "--padding", options.padding, 0.0, max_padding, false,
        "With --grid: the space around the mesh's box on every side, as a share of the box's "
        "diagonal.");
    add_output_option(app, options.out,
                      "Output file (SGOCC001, SGDST001, SGSDF001 or SGCLP001 by the query; "
                      "with --grid a .vti file), written atomically; it may not be FILE or "
                      "the points file");
    std::vector<std::string> names;
    for (const PointQuery q : every_query()) names.emplace_back(query_name(q));
    app.add_option("--query", raw->query,
                   "What to answer for each point: occupancy, distance, signed-distance or "
                   "closest (see below).")
        ->required()
        ->check(CLI::IsMember(names));
    raw->nsamples = add_count_option(
        app, "--nsamples", options.nsamples, 1, max_nsamples,
        "Rays per point for occupancy and signed-distance (the side), an odd number: the first "
        "along the axis that leaves the mesh's box soonest, the others spread evenly over the "
        "sphere; the majority decides.");
    raw->max_distance_option = add_real_option(
        app, "--max-distance", raw->max_distance, 0.0,
        static_cast<double>(std::numeric_limits<float>::max()), true,
        "For distance, signed-distance and closest: search no farther; a point farther from "
        "the mesh is answered +inf (closest: no triangle), and costs less.",
        "none");
    app.add_flag("--strict", options.strict,
                 "Refuse a points file with NaN or infinite coordinates (exit code 2, no output "
                 "written) instead of answering them NaN with a warning");
    add_count_option(app, "--threads", options.threads, 0, max_threads,
                     "Worker threads, 0 = all hardware threads.");
    app.add_flag("--json", options.json,
                 "Print one JSON object (docs/STATS_JSON.md) instead "
                 "of the summary");
    add_log_flags(app, options.log);
    app.parse_complete_callback([&options, raw] { check_together(options, *raw); });
}

}  // namespace sg::apps
