#pragma once

#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "splitgrid/build_config.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/formats/stats_json.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/mesh_edges.hpp"

#include <pybind11/pybind11.h>

namespace sg::python {

namespace py = pybind11;

/// What a splitgrid.SplitGrid holds: the mesh, its Split Grid and the source name, exactly what
/// a .sg file holds, and the file's facts when it was read from one. Never changed after it is
/// made, so any number of Python threads may query it at once.
struct GridObject {
    SgContents contents;
    std::optional<SgFileFacts> file;

    [[nodiscard]] MeshView mesh() const noexcept { return contents.mesh.view(); }
    [[nodiscard]] const SplitGrid& grid() const noexcept { return contents.grid; }

    /// The mesh's edge report, computed at the first call (a pass over the mesh that a grid
    /// only ray-traced never needs), then kept. Thread-safe; call without the GIL.
    [[nodiscard]] const EdgeReport& edges() const
    {
        std::call_once(edges_once_, [this] { edges_ = edge_report(mesh()); });
        return edges_;
    }

private:
    mutable std::once_flag edges_once_;
    mutable EdgeReport edges_;
};

/// Issues one splitgrid.OpenMeshWarning when `grid`'s mesh is not closed (some edge is shared
/// by an odd number of triangles): inside and outside by parity are then not defined
/// everywhere. `query` names the query in the message. Needs the GIL.
void warn_if_open(const GridObject& grid, const char* query);

/// The build parameters of splitgrid.build(): `preset` (build_preset_names), then every entry
/// of `params` by its build_config_fields name (a switch takes a bool, a count a whole number,
/// a real any real number), then `threads`; checked with the library's messages
/// (set_build_config_field, validate). Throws TypeError for an unknown name or a value of the
/// wrong type, ValueError for one out of range.
[[nodiscard]] BuildConfig build_config_from(const std::string& preset, const py::object& threads,
                                            const py::kwargs& params);

/// Builds the Split Grid of `mesh` with the GIL released, checks its invariants and keeps both.
/// Ctrl-C stops the build (KeyboardInterrupt) at its next progress report.
[[nodiscard]] std::unique_ptr<GridObject> build_grid(Mesh mesh, const BuildConfig& config,
                                                     std::string source_name);

/// Reads a .sg file with every check of read_sg_file, with the GIL released.
[[nodiscard]] std::unique_ptr<GridObject> load_grid(const std::filesystem::path& path);

/// The document of `sg-stats --json` (docs/STATS_JSON.md) for `grid`, as a Python dict.
[[nodiscard]] py::dict grid_stats(const GridObject& grid);

/// A JSON document as the equal Python object (dicts, lists, numbers, strings, None).
[[nodiscard]] py::object to_python(const Json& json);

}  // namespace sg::python
