#include "points_run.hpp"

#include <chrono>
#include <cmath>
#include <memory>
#include <vector>

#include "grid_field.hpp"
#include "invalid_entries.hpp"
#include "point_queries.hpp"
#include "points_report.hpp"
#include "sampling_grid.hpp"
#include "splitgrid/formats/output_file.hpp"
#include "splitgrid/formats/point_file.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/mesh_edges.hpp"
#include "splitgrid/version.hpp"

#include <spdlog/spdlog.h>
#include <tbb/task_arena.h>

namespace sg::apps {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// Warns once when inside and outside by parity are not defined everywhere: some edge is
/// shared by an odd number of triangles.
void warn_if_open(const fs::path& file, const EdgeReport& edges)
{
    if (edges.is_closed()) return;
    spdlog::warn(
        "{}: the mesh is not closed: {} open edges (shared by an odd number of "
        "triangles) and {} non-manifold edges (shared by more than two) of {}; inside "
        "and outside may be wrong near the openings (--nsamples above 1 takes the "
        "majority of more rays)",
        file.string(), edges.open_edges, edges.nonmanifold_edges, edges.edges);
}

void write_point_answers(OutputFile& output, PointQuery query, const PointAnswers& answers)
{
    switch (query) {
    case PointQuery::occupancy:
        write_occupancy_file(output, answers.values);
        return;
    case PointQuery::distance:
        write_distance_file(output, answers.values);
        return;
    case PointQuery::signed_distance:
        write_signed_distance_file(output, answers.values);
        return;
    case PointQuery::closest:
        write_closest_point_file(output, answers.closest);
        return;
    }
}

GridFieldFacts grid_facts(const PointsOptions& o, const SgContents& contents)
{
    GridFieldFacts facts;
    facts.texts = {{"source_name", contents.source_name},
                   {"structure_name", o.file.filename().string()},
                   {"splitgrid_version", std::string(version_string)},
                   {"query", std::string(query_name(o.query))}};
    facts.numbers = {{"padding", o.padding}};
    if (casts_rays(o.query)) facts.numbers.emplace_back("nsamples", o.nsamples);
    // Only a limit given: VTK's XML writer records an infinite value's range as 1e299.
    if (measures_distance(o.query) && !std::isinf(o.max_distance))
        facts.numbers.emplace_back("max_distance", static_cast<double>(o.max_distance));
    return facts;
}

}  // namespace

void run_points(const PointsOptions& o)
{
    // An output that would destroy an input, or that cannot be written, is refused before
    // anything is read; the temporary file exists from here on.
    std::vector<fs::path> inputs{o.file};
    if (!o.grid) inputs.push_back(o.points);
    refuse_output_over_input(o.out, inputs);
    const std::unique_ptr<OutputFile> output = reserve_output(o.out);
    const unsigned threads_asked = threads_to_use(o.threads);
    const std::string isa = kernel_isa_in_use();
    const SgContents contents = read_sg_file(o.file);
    const MeshView mesh = contents.mesh.view();

    PointsRun run;
    run.options = &o;
    run.isa = isa;
    LoadedPoints loaded;
    std::size_t nonfinite = 0;
    PointBlocks blocks;
    const std::size_t block_size = block_size_for(o.query);
    if (o.grid) {
        run.grid = grid_around(bounds(mesh), *o.grid, o.padding);
        blocks = brick_blocks(*run.grid);
        spdlog::debug("{}: {} triangles; a {}x{}x{} grid of {} points", o.file.string(),
                      contents.mesh.triangles.size(), (*o.grid)[0], (*o.grid)[1], (*o.grid)[2],
                      blocks.point_count);
    } else {
        loaded = read_points(o.points);
        run.points_from_text = loaded.source == PointSource::text;
        spdlog::debug("{}: {} triangles; {}: {} points ({})", o.file.string(),
                      contents.mesh.triangles.size(), o.points.string(), loaded.points.size(),
                      run.points_from_text ? "text" : "point file");
        nonfinite = check_invalid_entries(
            o.points, loaded.points, [](Vec3f p) { return !is_finite(p); },
            {"point", "a NaN or infinite coordinate", "NaN"}, o.strict);
        blocks = morton_blocks(loaded.points, contents.grid.root_box, block_size);
    }

    tbb::task_arena arena(threads_asked == 0 ? tbb::task_arena::automatic
                                             : static_cast<int>(threads_asked));
    if (casts_rays(o.query)) {
        EdgeReport edges;
        arena.execute([&] { edges = edge_report(mesh); });
        warn_if_open(o.file, edges);
        run.edges = edges;
    }

    const auto start = Clock::now();
    const PointAnswers answers = answer_points(contents, o.settings(), blocks, arena);
    run.seconds = seconds_since(start);
    run.threads = arena.max_concurrency();
    if (run.grid)
        write_grid_field(*output, *run.grid, o.query, answers, grid_facts(o, contents));
    else
        write_point_answers(*output, o.query, answers);
    report_points(run, count_answers(o.query, answers, nonfinite));
}

}  // namespace sg::apps
