#pragma once

#include <cstddef>
#include <string>

#include "splitgrid/build_config.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/mesh_edges.hpp"
#include "splitgrid/stats.hpp"

#include <nlohmann/json.hpp>

/// The JSON documents of docs/STATS_JSON.md, written in one place for every program that
/// prints them: the tools (sg-stats --json, the build_config and grid objects of sg-build,
/// sg-trace and sg-bench) and the Python package (SplitGrid.stats(), build_parameters).
namespace sg {

/// JSON type of every document: keys stay in insertion order, so the output reads in the order
/// docs/STATS_JSON.md lists it.
using Json = nlohmann::ordered_json;

/// The `schema_version` every JSON document carries (docs/STATS_JSON.md). Bumped only when a
/// key is removed or changes meaning; adding keys keeps the version.
inline constexpr int json_schema_version = 1;

/// `value` (bytes, references) divided by `triangles`, or 0 when there are no triangles.
[[nodiscard]] double per_triangle(std::size_t bytes, std::size_t triangles) noexcept;

/// Bytes of a mesh in memory as every structure traces it: 12 per vertex and 12 per triangle.
[[nodiscard]] std::size_t mesh_memory_bytes(const MeshView& mesh) noexcept;

/// BuildConfig as a JSON object, one key per entry of build_config_fields.
[[nodiscard]] Json to_json(const BuildConfig& config);

/// GridStats as a JSON object, one key per field with the field's name (histograms as arrays,
/// cost_model as an object).
[[nodiscard]] Json to_json(const GridStats& stats);

/// EdgeReport as a JSON object: edges, open_edges, nonmanifold_edges, closed (sg-stats and
/// sg-points print it).
[[nodiscard]] Json to_json(const EdgeReport& edges);

/// The file a .sg document describes: the path as the caller named it, and its header.
struct SgFileFacts {
    std::string path;
    SgFileInfo info;
};

/// The document `sg-stats FILE.sg --json` prints: file facts, source name, build_config, mesh,
/// the mesh's edges (`edges`, edge_report of contents.mesh), root_box, grid (`stats`, computed
/// from contents.grid), bytes per triangle and whether the coverage was checked. `file` is
/// null for contents that were never read from a file (a grid built in the Python package):
/// then "file" and "bytes_per_triangle.file" are null.
[[nodiscard]] Json sg_stats_json(const SgContents& contents, const GridStats& stats,
                                 const EdgeReport& edges, const SgFileFacts* file,
                                 bool coverage_checked);

}  // namespace sg
