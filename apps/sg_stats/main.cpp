/// sg-stats: reads a .sg file (with every check of read_sg_file) and prints its header,
/// build parameters and the statistics of its Split Grid, as text or as JSON
/// (docs/STATS_JSON.md).

#include <cstddef>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/formats/stats_json.hpp"
#include "splitgrid/mesh_edges.hpp"
#include "splitgrid/stats.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

namespace {

namespace fs = std::filesystem;

struct Options {
    fs::path file;
    bool json = false;
    bool coverage = false;
    sg::apps::LogOptions log;
};

/// Everything sg-stats reports, gathered once for both output forms.
struct Report {
    sg::SgFileInfo info;
    sg::SgContents contents;
    sg::GridStats stats;
    sg::EdgeReport edges;
    std::size_t mesh_bytes = 0;
};

/// "2:5 4:10 64:1" for a power-of-two histogram: bin k is labelled by its lower bound 2^k,
/// empty bins are left out.
std::string histogram_text(const std::vector<std::size_t>& bins)
{
    std::string text;
    for (std::size_t k = 0; k < bins.size(); ++k) {
        if (bins[k] == 0) continue;
        if (!text.empty()) text += ' ';
        text += fmt::format("{}:{}", std::size_t{1} << k, bins[k]);
    }
    return text.empty() ? "-" : text;
}

void print_json(const Options& options, const Report& r)
{
    const sg::SgFileFacts file{options.file.string(), r.info};
    std::cout << sg::sg_stats_json(r.contents, r.stats, r.edges, &file, options.coverage).dump(2)
              << '\n';
}

void print_text(const Options& options, const Report& r)
{
    const sg::GridStats& s = r.stats;
    const std::size_t triangles = r.contents.mesh.triangles.size();
    const auto bytes_per_triangle = [&](std::size_t bytes) {
        return sg::per_triangle(bytes, triangles);
    };
    const std::size_t file_bytes = static_cast<std::size_t>(r.info.file_bytes);

    std::string out;
    out += fmt::format("file            {} (format version {}, {}, {} bytes)\n",
                       options.file.string(), r.info.format_version,
                       sg::apps::human_bytes(file_bytes), file_bytes);
    for (const sg::SgSectionInfo& section : r.info.sections)
        out += fmt::format("  section {:4}  {:>12} bytes  {:>10} records  at offset {}\n",
                           section.name, section.bytes, section.count, section.offset);
    out += fmt::format("source          {}\n", r.contents.source_name);
    out += fmt::format("build config    {}\n", sg::apps::to_text(r.contents.grid.config));

    out += fmt::format("\nmesh            {} vertices stored, {} triangles\n",
                       r.contents.mesh.vertices.size(), triangles);
    out += fmt::format("edges           {} ({} open: shared by an odd number of triangles; {} "
                       "non-manifold: by more than two): {}\n",
                       r.edges.edges, r.edges.open_edges, r.edges.nonmanifold_edges,
                       r.edges.is_closed() ? "closed" : "not closed");
    out += fmt::format("grid            {} nodes, {} cells ({} empty, {} leaf, {} inner)\n",
                       s.node_count, s.cell_count, s.empty_cells, s.leaf_cells, s.inner_cells);
    out += fmt::format("references      {} to {} distinct triangles (duplication factor {:.3f})\n",
                       s.reference_count, s.referenced_triangles, s.duplication_factor);
    out += fmt::format("depth           max {}, mean leaf depth {:.2f}\n", s.max_depth,
                       s.mean_leaf_depth);

    out += "\nresolution per depth (histogram b:count = nodes with a resolution in [b, 2b))\n";
    out += "  depth   nodes   mean res  histogram\n";
    for (std::size_t d = 0; d < s.nodes_per_depth.size(); ++d) {
        const double mean = d < s.mean_resolution_per_depth.size()
                                ? s.mean_resolution_per_depth[d]
                                : 0.0;
        const std::string hist = d < s.resolution_histogram.size()
                                     ? histogram_text(s.resolution_histogram[d])
                                     : std::string("-");
        out += fmt::format("  {:>5} {:>7} {:>10.2f}  {}\n", d, s.nodes_per_depth[d], mean, hist);
    }

    out += fmt::format("\nleaves          {} (empty cell fraction {:.3f})\n", s.leaf_cells,
                       s.empty_cell_fraction);
    out += fmt::format("triangles/leaf  min {}, mean {:.2f}, max {}\n", s.leaf_size_min,
                       s.leaf_size_mean, s.leaf_size_max);
    out += fmt::format("  histogram     {}  (b:count = leaves with [b, 2b) triangles)\n",
                       histogram_text(s.leaf_size_histogram));

    out += "\nmemory\n";
    out += fmt::format("  nodes         {:>12} bytes\n", s.node_bytes);
    out += fmt::format("  cells         {:>12} bytes\n", s.cell_bytes);
    out += fmt::format("  references    {:>12} bytes\n", s.reference_bytes);
    out += fmt::format("  structure     {:>12} bytes  {:8.2f} bytes/triangle\n", s.structure_bytes,
                       bytes_per_triangle(s.structure_bytes));
    out += fmt::format("  mesh          {:>12} bytes  {:8.2f} bytes/triangle\n", r.mesh_bytes,
                       bytes_per_triangle(r.mesh_bytes));
    out += fmt::format("  struct + mesh {:>12} bytes  {:8.2f} bytes/triangle\n",
                       s.structure_bytes + r.mesh_bytes,
                       bytes_per_triangle(s.structure_bytes + r.mesh_bytes));
    out += fmt::format("  file          {:>12} bytes  {:8.2f} bytes/triangle\n", file_bytes,
                       bytes_per_triangle(file_bytes));

    out += fmt::format("\nexpected cost   {:.3f} (SAH model: node {:g}, cell {:g}, triangle {:g})\n",
                       s.sah_cost, s.cost_model.node_cost, s.cost_model.cell_cost,
                       s.cost_model.triangle_cost);
    if (options.coverage) out += "coverage        checked: every triangle is in every cell it overlaps\n";
    std::cout << out;
}

void stats(const Options& options)
{
    sg::SgReadOptions read_options;
    read_options.check_coverage = options.coverage;
    Report report;
    // The full read comes first: it checks everything, so a bad file is refused with the
    // reader's precise message before the header is looked at again.
    report.contents = sg::read_sg_file(options.file, read_options);
    report.info = sg::read_sg_info(options.file);
    report.stats = sg::compute_stats(report.contents.grid);
    report.edges = sg::edge_report(report.contents.mesh.view());
    report.mesh_bytes = sg::mesh_memory_bytes(report.contents.mesh.view());
    spdlog::debug("{}: read and checked{}", options.file.string(),
                  options.coverage ? " (with coverage)" : "");
    if (options.json)
        print_json(options, report);
    else
        print_text(options, report);
}

}  // namespace

int main(int argc, char** argv)
{
    Options options;
    CLI::App app{"", "sg-stats"};
    sg::apps::describe_tool(
        app,
        "Prints the header, build parameters and statistics of a .sg file: the mesh's edges\n"
        "(open: shared by an odd number of triangles; non-manifold: by more than two; a mesh\n"
        "without open edges is closed, and sg-points' inside/outside is exact on it), totals,\n"
        "depth, resolution per depth, leaf sizes, duplication factor, memory and bytes per\n"
        "triangle, and the expected traversal cost.",
        "Expected traversal cost (surface-area model, for a random ray hitting the root box):\n"
        "    sum over inner nodes   P(box)  * node_cost\n"
        "  + sum over inner nodes   P(slab) * cell_cost * (1 + (N - 1) * 2 A / SA(slab))\n"
        "  + sum over leaf cells    P(cell) * triangle_cost * references\n"
        "P(X) = SA(X) / SA(root box); slab = node box narrowed to [lo, hi]; N = resolution;\n"
        "A = area of one cell plane inside the slab. All three costs are 1.\n"
        "The JSON output is documented in docs/STATS_JSON.md (schema_version 1).");
    app.add_option("FILE", options.file, "The .sg file")->required();
    app.add_flag("--json", options.json, "Print one JSON object instead of text");
    app.add_flag("--coverage", options.coverage,
                 "Also check that every triangle is referenced by every cell it overlaps "
                 "(slow on large meshes)");
    sg::apps::add_log_flags(app, options.log);
    return sg::apps::run_tool(app, argc, argv, options.log, [&] { stats(options); });
}
