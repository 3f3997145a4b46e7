/// sg-export: reads a .sg file and writes its Split Grid (cells, bounding planes, leaves) and
/// mesh as VTK files that ParaView opens as one multiblock data set (docs/VIZ.md).

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/version.hpp"
#include "splitgrid/viz/library_versions.hpp"
#include "splitgrid/viz/vtk_export.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using sg::apps::Json;

struct Options {
    fs::path file;
    fs::path output;
    std::vector<std::string> parts{"cells", "planes", "leaves", "mesh"};
    std::uint32_t min_depth = 0;
    std::uint32_t max_depth = std::numeric_limits<std::uint32_t>::max();
    std::uint32_t subtree = 0;
    bool has_subtree = false;
    bool empty_cells = false;
    std::uint64_t limit = sg::viz::default_primitive_limit;
    bool force = false;
    bool json = false;
    sg::apps::LogOptions log;
};

sg::viz::ExportOptions export_options(const Options& options)
{
    sg::viz::ExportOptions o;
    o.parts = {false, false, false, false};
    for (const std::string& part : options.parts) {
        if (part == "cells") o.parts.cells = true;
        if (part == "planes") o.parts.planes = true;
        if (part == "leaves") o.parts.leaves = true;
        if (part == "mesh") o.parts.mesh = true;
    }
    o.min_depth = options.min_depth;
    o.max_depth = options.max_depth;
    if (options.has_subtree) o.subtree = options.subtree;
    o.empty_cells = options.empty_cells;
    o.primitive_limit = options.limit;
    o.replace_existing = options.force;
    o.name = sg::viz::export_name_for(options.file);
    return o;
}

/// The refusal of a selection over the limit, as a usage error (exit code 1) that says how
/// to narrow it: the deepest --max-depth that fits, or the --limit that would let it through.
[[noreturn]] void refuse_over_limit(const Options& options, const sg::viz::ExportLimitError& e)
{
    const std::vector<std::uint64_t>& by_depth = e.counts().primitives_by_max_depth;
    std::string narrow;
    for (std::size_t d = by_depth.size(); d-- > options.min_depth;)
        if (by_depth[d] <= e.limit()) {
            narrow = fmt::format("export fewer levels with --max-depth {} ({} primitives) or ",
                                 d, by_depth[d]);
            break;
        }
    if (narrow.empty() && !by_depth.empty())
        narrow = fmt::format("even the shallowest depth holds {} primitives; export one subtree "
                             "with --subtree NODE or ",
                             by_depth[std::min<std::size_t>(options.min_depth, by_depth.size() - 1)]);
    throw CLI::ValidationError(fmt::format("{}: {}; {}raise the limit with --limit {} (0: no limit)",
                                           options.file.string(), e.what(), narrow,
                                           e.counts().primitives()));
}

void print_summary(const Options& options, const sg::viz::ExportSummary& s, double read_seconds,
                   double export_seconds)
{
    const sg::viz::ExportCounts& c = s.counts;
    if (options.json) {
        Json files = Json::array();
        for (const sg::viz::ExportedFile& file : s.files)
            files.push_back({{"path", file.path.string()}, {"bytes", file.bytes}});
        Json j;
        j["schema_version"] = sg::apps::json_schema_version;
        j["splitgrid_version"] = sg::version_string;
        j["input"] = options.file.string();
        j["output"] = options.output.string();
        j["vtm"] = s.vtm_path.string();
        j["counts"] = {{"cells", c.cells},
                       {"planes", c.planes},
                       {"leaves", c.leaves},
                       {"mesh_triangles", c.mesh_triangles},
                       {"selected_nodes", c.selected_nodes},
                       {"primitives", c.primitives()}};
        j["files"] = files;
        j["total_bytes"] = s.total_bytes;
        j["seconds"] = {{"read", read_seconds}, {"export", export_seconds}};
        std::cout << j.dump(2) << '\n';
        return;
    }
    if (!options.log.shows_summary()) return;
    std::cout << fmt::format(
        "input       {}\n"
        "selection   {} nodes: {} cells, {} planes, {} leaves; mesh {} triangles\n"
        "output      {} ({} in {} files)\n"
        "time        read {:.3f} s, export {:.3f} s\n"
        "open with   paraview {}\n",
        options.file.string(), c.selected_nodes, c.cells, c.planes, c.leaves, c.mesh_triangles,
        s.vtm_path.string(), sg::apps::human_bytes(s.total_bytes), s.files.size(), read_seconds,
        export_seconds, s.vtm_path.string());
}

void export_file(const Options& options)
{
    // An export that would replace its own input, or a folder that cannot be written, is
    // refused before the .sg file is read; the staging folder exists from here on.
    sg::apps::refuse_folder_over_input(options.output, {options.file});
    sg::viz::ExportFolder folder(options.output, options.force);
    sg::apps::report_stale_removed(folder.stale_removed());

    const auto read_start = Clock::now();
    const sg::SgContents contents = sg::read_sg_file(options.file);
    const double read_seconds = sg::apps::seconds_since(read_start);

    const sg::viz::ExportMetadata metadata{contents.source_name,
                                           options.file.filename().string()};
    const auto export_start = Clock::now();
    sg::viz::ExportSummary summary;
    try {
        summary = sg::viz::export_vtk(contents.grid, contents.mesh.view(),
                                      export_options(options), metadata, folder);
    } catch (const sg::viz::ExportLimitError& e) {
        refuse_over_limit(options, e);
    }
    const double export_seconds = sg::apps::seconds_since(export_start);
    if (summary.counts.primitives() == 0 && summary.counts.mesh_triangles == 0)
        spdlog::warn("the selection is empty: the export holds no cells, planes or triangles");
    print_summary(options, summary, read_seconds, export_seconds);
}

}  // namespace

int main(int argc, char** argv)
{
    Options options;
    CLI::App app{"", "sg-export"};
    sg::apps::describe_tool(
        app,
        "Writes the Split Grid of a .sg file and its mesh as VTK files for ParaView:\n"
        "  DIR/NAME.vtm             the file to open: a multiblock data set whose blocks\n"
        "                           are named cells, planes, leaves and mesh\n"
        "  DIR/NAME/NAME_<i>.vtu    cells and leaves: one hexahedron per cell\n"
        "  DIR/NAME/NAME_<i>.vtp    planes (two quads per node) and mesh (the triangles)\n"
        "NAME is the .sg file's name without .sg. Every file is VTK XML with appended raw\n"
        "binary data, zlib compressed, 64-bit headers.",
        "Cell arrays (docs/VIZ.md has the details):\n"
        "  cells, leaves  depth (active scalars: the depth of the cell's node, root = 0),\n"
        "                 node_id, cell_index (position along the node's axis), axis\n"
        "                 (0 x, 1 y, 2 z), kind (0 empty, 1 leaf, 2 inner), triangle_count\n"
        "                 (references in the leaf or in the inner cell's subtree),\n"
        "                 cost_share (the cell's share of the expected traversal cost of\n"
        "                 sg-stats: its leaf's triangle tests, or its whole subtree)\n"
        "  planes         depth, node_id, side (0 lo, 1 hi), axis, cut_fraction (share of\n"
        "                 the node's extent on its axis that the plane cuts away)\n"
        "  mesh           reference_count (how many leaves reference the triangle)\n"
        "Field data on every block: source_name, structure_name, build_* (build\n"
        "parameters), grid_* (totals of the whole structure), export_* (the selection).\n"
        "\n"
        "DIR is created; it must not exist or be empty. --force replaces a DIR that holds an\n"
        "earlier export (a .vtm file); any other folder is left alone. The export is written\n"
        "into a hidden folder beside DIR and renamed to DIR when complete, so a failure leaves\n"
        "no partial export.\n"
        "Over the limit (default 1,000,000 hexahedra and quads) nothing is written and the\n"
        "tool exits with code 1, naming the --max-depth that would fit. On an interrupt the\n"
        "hidden folder is removed; one left by a killed run is removed by the next run.",
        sg::viz::viz_library_versions());
    app.add_option("FILE", options.file, "The .sg file (from sg-build)")->required()->type_name("");
    sg::apps::add_output_option(app, options.output,
                                "Output folder DIR (created; see below for an existing folder)",
                                true, "DIR");
    app.add_option("--parts", options.parts,
                   sg::apps::help_text("Comma-separated blocks to write, from cells, planes, "
                                       "leaves, mesh.",
                                       {}, "cells,planes,leaves,mesh"))
        ->delimiter(',')
        ->type_name("LIST")
        ->check(CLI::IsMember({"cells", "planes", "leaves", "mesh"}));
    sg::apps::add_count_option(app, "--min-depth", options.min_depth, 0, sg::max_supported_depth,
                               "Export only nodes at this depth or deeper (the root node is "
                               "depth 0; a cell has its node's depth).")
        ->type_name("D");
    sg::apps::add_count_option(app, "--max-depth", options.max_depth, 0, sg::max_supported_depth,
                               "Export only nodes at this depth or shallower.", "no limit")
        ->type_name("D");
    sg::apps::add_count_option(app, "--subtree", options.subtree, 0,
                               std::numeric_limits<std::uint32_t>::max(),
                               "Export only node NODE and the nodes below it (NODE is a node_id "
                               "as shown in ParaView). Depths still count from the root.",
                               "the whole structure")
        ->type_name("NODE")
        ->each([&options](const std::string&) { options.has_subtree = true; });
    app.add_flag("--empty-cells", options.empty_cells,
                 "Also write empty cells (kind 0) into the cells block");
    sg::apps::add_count_option(app, "--limit", options.limit, 0,
                               std::numeric_limits<std::uint64_t>::max(),
                               "Most hexahedra and quads (cells + planes + leaves; the mesh is "
                               "not counted) to write; 0 means no limit. More is slow to open "
                               "and unreadable as a wireframe.")
        ->type_name("N");
    app.add_flag("--force", options.force,
                 "Replace DIR if it exists and holds an earlier export (a .vtm file), unless it "
                 "holds FILE");
    app.add_flag("--json", options.json, "Print one JSON object (docs/VIZ.md) instead of the "
                                         "summary");
    sg::apps::add_log_flags(app, options.log);
    app.parse_complete_callback([&options] {
        if (options.min_depth > options.max_depth)
            throw CLI::ValidationError(fmt::format("--min-depth {} is above --max-depth {}",
                                                   options.min_depth, options.max_depth));
    });
    return sg::apps::run_tool(app, argc, argv, options.log, [&] { export_file(options); });
}
