#include "splitgrid/formats/stats_json.hpp"

#include <variant>

#include "splitgrid/version.hpp"

namespace sg {
namespace {

Json vec_json(Vec3f v) { return Json::array({v.x, v.y, v.z}); }

}  // namespace

double per_triangle(std::size_t bytes, std::size_t triangles) noexcept
{
    return triangles == 0 ? 0.0 : static_cast<double>(bytes) / static_cast<double>(triangles);
}

std::size_t mesh_memory_bytes(const MeshView& mesh) noexcept
{
    return mesh.vertices.size() * sizeof(Vec3f) + mesh.triangles.size() * sizeof(Triangle);
}

Json to_json(const BuildConfig& config)
{
    Json j;
    for (const BuildConfigField& field : build_config_fields)
        std::visit([&](auto member) { j[std::string(field.name)] = config.*member; },
                   field.member);
    return j;
}

Json to_json(const GridStats& stats)
{
    Json j;
    j["triangle_count"] = stats.triangle_count;
    j["node_count"] = stats.node_count;
    j["cell_count"] = stats.cell_count;
    j["empty_cells"] = stats.empty_cells;
    j["leaf_cells"] = stats.leaf_cells;
    j["inner_cells"] = stats.inner_cells;
    j["reference_count"] = stats.reference_count;
    j["referenced_triangles"] = stats.referenced_triangles;
    j["max_depth"] = stats.max_depth;
    j["mean_leaf_depth"] = stats.mean_leaf_depth;
    j["nodes_per_depth"] = stats.nodes_per_depth;
    j["mean_resolution_per_depth"] = stats.mean_resolution_per_depth;
    j["resolution_histogram"] = stats.resolution_histogram;
    j["leaf_size_min"] = stats.leaf_size_min;
    j["leaf_size_max"] = stats.leaf_size_max;
    j["leaf_size_mean"] = stats.leaf_size_mean;
    j["leaf_size_histogram"] = stats.leaf_size_histogram;
    j["empty_cell_fraction"] = stats.empty_cell_fraction;
    j["duplication_factor"] = stats.duplication_factor;
    j["node_bytes"] = stats.node_bytes;
    j["cell_bytes"] = stats.cell_bytes;
    j["reference_bytes"] = stats.reference_bytes;
    j["structure_bytes"] = stats.structure_bytes;
    j["structure_bytes_per_triangle"] = stats.structure_bytes_per_triangle;
    j["sah_cost"] = stats.sah_cost;
    j["cost_model"] = {{"node_cost", stats.cost_model.node_cost},
                       {"cell_cost", stats.cost_model.cell_cost},
                       {"triangle_cost", stats.cost_model.triangle_cost}};
    return j;
}

Json to_json(const EdgeReport& edges)
{
    Json j;
    j["edges"] = edges.edges;
    j["open_edges"] = edges.open_edges;
    j["nonmanifold_edges"] = edges.nonmanifold_edges;
    j["closed"] = edges.is_closed();
    return j;
}

Json sg_stats_json(const SgContents& contents, const GridStats& stats, const EdgeReport& edges,
                   const SgFileFacts* file, bool coverage_checked)
{
    const std::size_t triangles = contents.mesh.triangles.size();
    const std::size_t mesh = mesh_memory_bytes(contents.mesh.view());
    Json j;
    j["schema_version"] = json_schema_version;
    j["splitgrid_version"] = version_string;
    if (file != nullptr) {
        Json sections = Json::array();
        for (const SgSectionInfo& section : file->info.sections)
            sections.push_back({{"name", section.name},
                                {"offset", section.offset},
                                {"bytes", section.bytes},
                                {"count", section.count},
                                {"crc32", section.crc32}});
        j["file"] = {{"path", file->path},
                     {"format_version", file->info.format_version},
                     {"bytes", file->info.file_bytes},
                     {"sections", sections}};
    } else {
        j["file"] = nullptr;
    }
    j["source_name"] = contents.source_name;
    j["build_config"] = to_json(contents.grid.config);
    j["mesh"] = {{"vertex_count", contents.mesh.vertices.size()},
                 {"triangle_count", triangles},
                 {"bytes", mesh}};
    j["edges"] = to_json(edges);
    j["root_box"] = {{"lower", vec_json(contents.grid.root_box.lower)},
                     {"upper", vec_json(contents.grid.root_box.upper)}};
    j["grid"] = to_json(stats);
    Json file_per_triangle = nullptr;
    if (file != nullptr)
        file_per_triangle = per_triangle(static_cast<std::size_t>(file->info.file_bytes),
                                         triangles);
    j["bytes_per_triangle"] = {{"structure", per_triangle(stats.structure_bytes, triangles)},
                               {"structure_and_mesh",
                                per_triangle(stats.structure_bytes + mesh, triangles)},
                               {"file", file_per_triangle}};
    j["coverage_checked"] = coverage_checked;
    return j;
}

}  // namespace sg
