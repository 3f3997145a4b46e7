/// sg-build: reads any mesh Assimp can read, builds its Split Grid and writes both to a .sg
/// file. Prints a short summary (or one JSON object with --json) on stdout.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "cli_common.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "splitgrid/formats/output_file.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/stats.hpp"
#include "splitgrid/validate.hpp"
#include "splitgrid/version.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

namespace {

namespace fs = std::filesystem;
using sg::apps::Json;
using Clock = std::chrono::steady_clock;

struct Options {
    fs::path mesh;
    fs::path output;
    sg::BuildConfig config;
    sg::ImportOptions import;
    bool json = false;
    sg::apps::LogOptions log;
};

/// Logs what the importer skipped and dropped: a user whose mesh lost triangles must hear it.
void log_import_report(const fs::path& path, const sg::ImportReport& report,
                       std::size_t triangles_kept)
{
    spdlog::debug("{}: {} meshes, {} faces, {} triangles read, {} kept, {} vertices",
                  path.string(), report.meshes, report.faces_read, report.triangles_read,
                  triangles_kept, report.vertices);
    for (const std::string& warning : sg::import_warnings(path, report))
        spdlog::warn("{}", warning);
}

/// A freshly built grid that breaks its invariants is a bug in the builder, not a bad input
/// file: report it as an internal error (exit code 3) rather than the FormatError the checker
/// throws for files.
void check_built_grid(const sg::SplitGrid& grid)
{
    try {
        sg::check_invariants(grid);
    } catch (const sg::FormatError& e) {
        throw std::logic_error(std::string("built grid fails its invariants: ") + e.what());
    }
}

/// The limits of the import process (mesh_import.hpp): a hostile mesh file that crashes,
/// hangs or floods Assimp ends as exit code 2 with a message, not as the end of sg-build.
void add_import_flags(CLI::App& app, sg::ImportOptions& import)
{
    sg::apps::add_real_option(app, "--import-time-limit", import.time_limit_seconds, 0.0, 1e6,
                              true,
                              "Seconds the mesh import may take before it is stopped and the "
                              "file refused (exit code 2).");
    app.add_option_function<std::uint64_t>(
           "--import-memory-limit",
           [&import](std::uint64_t mib) { import.memory_limit_bytes = mib << 20; },
           sg::apps::help_text("MiB of memory the mesh import may use before the file is "
                               "refused (exit code 2); 0 means no limit.",
                               sg::apps::count_range(0, std::uint64_t{1} << 30),
                               std::to_string(import.memory_limit_bytes >> 20)))
        ->check(sg::apps::count_in(0, std::uint64_t{1} << 30));
    app.add_flag_callback(
        "--import-in-process",
        [&import] { import.isolation = sg::ImportIsolation::in_process; },
        "Run Assimp inside sg-build instead of a child process: no limits, and a file that "
        "crashes Assimp ends sg-build (for debugging the import)");
}

void build(Options& options)
{
    // Fail on an output that would destroy the input, or that cannot be written, now: not
    // after a long import and build. The temporary file exists from here on.
    sg::apps::refuse_output_over_input(options.output, {options.mesh});
    const std::unique_ptr<sg::OutputFile> output = sg::apps::reserve_output(options.output);
    options.config.threads = sg::apps::threads_to_use(options.config.threads);

    const auto import_start = Clock::now();
    sg::ImportedMesh imported = sg::import_mesh(options.mesh, options.import);
    const double import_seconds = sg::apps::seconds_since(import_start);
    const sg::ImportReport report = imported.report;
    const std::size_t triangles_kept = imported.mesh.triangles.size();
    const std::size_t vertex_count = imported.mesh.vertices.size();
    // The files the mesh pulled in (a glTF's .bin, an OBJ's .mtl) are inputs too.
    sg::apps::refuse_output_over_input(options.output, sg::apps::as_paths(report.opened_files),
                                       options.mesh);
    log_import_report(options.mesh, report, triangles_kept);

    const auto build_start = Clock::now();
    sg::SplitGrid grid = sg::build_split_grid(imported.mesh.view(), options.config,
                                              sg::apps::ProgressLog("building",
                                                                    "triangles placed",
                                                                    build_start));
    const unsigned threads = sg::apps::threads_that_run(options.config.threads);
    const double build_seconds = sg::apps::seconds_since(build_start);
    check_built_grid(grid);
    const sg::GridStats stats = sg::compute_stats(grid);

    const auto write_start = Clock::now();
    const sg::SgContents contents{std::move(imported.mesh), std::move(grid),
                                  options.mesh.filename().string()};
    sg::write_sg_file(*output, contents);
    const double write_seconds = sg::apps::seconds_since(write_start);
    const std::size_t file_bytes = static_cast<std::size_t>(fs::file_size(options.output));
    spdlog::debug("wrote {} ({} bytes)", options.output.string(), file_bytes);

    const std::size_t dropped = report.nonfinite_dropped + report.degenerate_dropped;
    if (options.json) {
        Json j;
        j["schema_version"] = sg::apps::json_schema_version;
        j["splitgrid_version"] = sg::version_string;
        j["input"] = options.mesh.string();
        j["output"] = options.output.string();
        j["import"] = {{"meshes", report.meshes},
                       {"faces_read", report.faces_read},
                       {"triangles_read", report.triangles_read},
                       {"points_skipped", report.points_skipped},
                       {"lines_skipped", report.lines_skipped},
                       {"nonfinite_dropped", report.nonfinite_dropped},
                       {"degenerate_dropped", report.degenerate_dropped},
                       {"triangles_kept", triangles_kept},
                       {"vertices_before_welding", report.vertices_before_welding},
                       {"vertices", vertex_count},
                       {"warnings", report.warnings}};
        j["build_config"] = sg::apps::to_json(options.config);
        j["grid"] = {{"triangle_count", stats.triangle_count},
                     {"node_count", stats.node_count},
                     {"cell_count", stats.cell_count},
                     {"reference_count", stats.reference_count},
                     {"max_depth", stats.max_depth},
                     {"duplication_factor", stats.duplication_factor},
                     {"structure_bytes", stats.structure_bytes},
                     {"structure_bytes_per_triangle", stats.structure_bytes_per_triangle}};
        j["file"] = {{"bytes", file_bytes},
                     {"bytes_per_triangle", sg::per_triangle(file_bytes, triangles_kept)}};
        j["seconds"] = {
            {"import", import_seconds}, {"build", build_seconds}, {"write", write_seconds}};
        j["threads"] = threads;
        std::cout << j.dump(2) << '\n';
        return;
    }
    if (!options.log.shows_summary()) return;
    std::cout << fmt::format(
        "input       {}\n"
        "triangles   {} read, {} dropped ({} non-finite, {} zero-area), {} kept; "
        "{} points and {} lines skipped\n"
        "vertices    {} before welding, {} after (bit-identical positions merged)\n"
        "grid        {} nodes, {} cells, {} references (duplication {:.2f}), max depth {}\n"
        "structure   {} ({:.1f} bytes/triangle)\n"
        "file        {} ({:.1f} bytes/triangle) {}\n"
        "time        import {:.3f} s, build {:.3f} s on {} thread{}, write {:.3f} s\n",
        options.mesh.string(), report.triangles_read, dropped, report.nonfinite_dropped,
        report.degenerate_dropped, triangles_kept, report.points_skipped, report.lines_skipped,
        report.vertices_before_welding, vertex_count, stats.node_count, stats.cell_count,
        stats.reference_count, stats.duplication_factor, stats.max_depth,
        sg::apps::human_bytes(stats.structure_bytes),
        stats.structure_bytes_per_triangle, sg::apps::human_bytes(file_bytes),
        sg::per_triangle(file_bytes, triangles_kept), options.output.string(),
        import_seconds, build_seconds, threads, threads == 1 ? "" : "s", write_seconds);
}

}  // namespace

int main(int argc, char** argv)
{
    Options options;
    CLI::App app{"", "sg-build"};
    sg::apps::describe_tool(
        app,
        "Builds the Split Grid of a mesh and writes mesh and grid to a .sg file.\n"
        "MESH is any file Assimp reads (obj, ply, stl, off, gltf/glb, dae, fbx, 3ds, ...);\n"
        "all its meshes are merged with their node transforms applied.",
        "Resolution of a node with n triangles (the Gaussian resolution function):\n"
        "  N(n) = round(min + (max - min) * (1 - exp(-(n / sigma)^2 / 2)))\n"
        "with min = --resolution-min, max = --resolution-max, sigma = --resolution-sigma,\n"
        "then capped so cells are at least --min-cell-width mean triangle extents wide\n"
        "(docs/SPLIT_GRID.md).\n"
        "On failure or an interrupt no output file is left behind (the file is written\n"
        "atomically: into a temporary file beside it, created before the import).");
    app.add_option("MESH", options.mesh, "Input mesh file")->required();
    sg::apps::add_output_option(app, options.output,
                                "Output .sg file, written atomically; it may not be the mesh "
                                "or a file the mesh refers to (a glTF's .bin, an OBJ's .mtl)");
    app.add_flag("--json", options.json, "Print one JSON object (docs/STATS_JSON.md) instead "
                                         "of the summary");
    sg::apps::add_build_config_flags(app, options.config);
    add_import_flags(app, options.import);
    sg::apps::add_log_flags(app, options.log);
    return sg::apps::run_tool(app, argc, argv, options.log, [&] { build(options); });
}
