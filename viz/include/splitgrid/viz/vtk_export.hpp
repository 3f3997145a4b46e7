#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "splitgrid/error.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/split_grid.hpp"

/// Export of a Split Grid as VTK XML files for ParaView (docs/VIZ.md describes every file and
/// array). This header includes no VTK header: VTK stays private to splitgrid_viz.
namespace sg::viz {

/// Which blocks of the multiblock data set to write. Each block is one file.
struct ExportParts {
    /// "cells": one hexahedron per cell of every selected node (inner and leaf cells; empty
    /// cells only with ExportOptions::empty_cells), as an unstructured grid.
    bool cells = true;
    /// "planes": the two bounding planes (lo and hi) of every selected node, as quads spanning
    /// the node's box, as poly data.
    bool planes = true;
    /// "leaves": the leaf cells of the selection again, alone, so a user can hide the inner
    /// levels by hiding "cells".
    bool leaves = true;
    /// "mesh": the whole triangle mesh with the per-triangle reference_count, as poly data.
    bool mesh = true;

    friend constexpr bool operator==(const ExportParts&, const ExportParts&) = default;
};

/// Default cap on exported primitives (hexahedra in "cells" and "leaves" plus quads in
/// "planes"; the mesh is not counted, it is the input). One million primitives are about
/// 20 to 40 MB of compressed files and already more than a wireframe can show readably; a
/// structure over it is usually explored with a depth limit or one subtree at a time.
inline constexpr std::uint64_t default_primitive_limit = 1'000'000;

/// What to export and where.
///
/// Depths count inner nodes from the root of the whole structure (the root node has depth 0),
/// as sg-build --max-depth and sg-stats do; a cell has the depth of the node it belongs to,
/// so a node's cells and its bounding planes share a depth. The limits apply to nodes: a node
/// is selected if its depth lies in [min_depth, max_depth] and (with `subtree`) it lies in
/// that subtree; a selected node contributes its planes and its cells.
struct ExportOptions {
    ExportParts parts;
    std::uint32_t min_depth = 0;
    std::uint32_t max_depth = std::numeric_limits<std::uint32_t>::max();
    /// Only this node (an index into SplitGrid::nodes, the node_id array of the export) and
    /// the nodes below it. Depths stay counted from the root of the whole structure.
    std::optional<std::uint32_t> subtree;
    /// Also write empty cells (kind 0) into "cells".
    bool empty_cells = false;
    /// Refuse (ExportLimitError) a selection of more primitives than this; 0 means no limit.
    std::uint64_t primitive_limit = default_primitive_limit;
    /// Replace an existing, non-empty output folder if it holds an earlier export (a .vtm file
    /// at its top level). Any other non-empty folder is never replaced.
    bool replace_existing = false;
    /// Base name of the .vtm file and of the folder of block files beside it. Letters,
    /// digits, '_', '-' and '.', not starting with '.'; at most 100 characters.
    std::string name = "splitgrid";
};

/// Facts about the structure that the grid itself does not hold, written as field data.
struct ExportMetadata {
    /// Name of the mesh file the structure was built from (SgContents::source_name).
    std::string source_name;
    /// Name of the structure file the grid was read from, e.g. "dragon.sg" (may be empty).
    std::string structure_name;
};

/// Sizes of a selection, known before anything is written.
struct ExportCounts {
    std::uint64_t cells = 0;           ///< hexahedra in "cells" (0 if the part is off)
    std::uint64_t planes = 0;          ///< quads in "planes" (2 per selected node)
    std::uint64_t leaves = 0;          ///< hexahedra in "leaves"
    std::uint64_t mesh_triangles = 0;  ///< triangles in "mesh"
    std::uint64_t selected_nodes = 0;  ///< nodes whose planes and cells are selected
    /// primitives_by_max_depth[d]: primitives the same selection would hold with max_depth = d
    /// (for d from 0 to the deepest selected node), so a tool can suggest a depth limit.
    std::vector<std::uint64_t> primitives_by_max_depth;

    /// cells + planes + leaves: what ExportOptions::primitive_limit caps.
    [[nodiscard]] std::uint64_t primitives() const noexcept { return cells + planes + leaves; }
};

/// One file of a finished export.
struct ExportedFile {
    std::filesystem::path path;  ///< under the output folder
    std::uint64_t bytes = 0;
};

/// What export_vtk() wrote.
struct ExportSummary {
    ExportCounts counts;
    std::filesystem::path vtm_path;   ///< the multiblock file to open in ParaView
    std::vector<ExportedFile> files;  ///< every file written, the .vtm first
    std::uint64_t total_bytes = 0;
};

/// The selection holds more primitives than ExportOptions::primitive_limit. Nothing was
/// written. Carries the counts so that a tool can suggest a depth limit.
class ExportLimitError : public ConfigError {
public:
    ExportLimitError(const std::string& message, ExportCounts counts, std::uint64_t limit)
        : ConfigError(message), counts_(std::move(counts)), limit_(limit)
    {
    }
    [[nodiscard]] const ExportCounts& counts() const noexcept { return counts_; }
    [[nodiscard]] std::uint64_t limit() const noexcept { return limit_; }

private:
    ExportCounts counts_;
    std::uint64_t limit_;
};

/// A valid ExportOptions::name made from a file name: its stem ("dragon" for
/// "scans/dragon.sg") with every other character than letters, digits, '_', '-' and '.'
/// replaced by '_', leading dots dropped, cut to 100 characters; "splitgrid" if nothing is
/// left.
[[nodiscard]] std::string export_name_for(const std::filesystem::path& file);

/// Counts what export_vtk() would write for `options`, without writing. Throws ConfigError
/// for options that cannot be met (min_depth > max_depth, a subtree node that does not
/// exist, a bad name). Cost: one walk over the selected nodes' cells.
/// Precondition: check_invariants(grid) passes; mesh has grid.triangle_count triangles.
[[nodiscard]] ExportCounts count_export(const SplitGrid& grid, const MeshView& mesh,
                                        const ExportOptions& options);

/// Writes the selected blocks as one multiblock data set into the folder `out_dir`:
///   out_dir/<name>.vtm              the multiblock file (blocks "cells", "planes", "leaves",
///                                   "mesh", in this order, those selected)
///   out_dir/<name>/<name>_<i>.vtu   block i, "cells" and "leaves" (unstructured grids)
///   out_dir/<name>/<name>_<i>.vtp   block i, "planes" and "mesh" (poly data)
/// through VTK's XML writers: appended raw binary, zlib compressed, 64-bit block headers.
/// A selected block that holds nothing (no planes in a grid without nodes, say) is left out,
/// so <i> counts the blocks that are written.
///
/// The output is atomic: everything is written into a new hidden folder beside `out_dir`
/// (".<folder name>.sg-export-<pid>-<random>"), flushed to disk, and renamed to `out_dir` only when
/// complete; on any failure it is removed and `out_dir` is untouched. `out_dir` may be absent
/// or an empty folder; an existing non-empty folder is replaced only with
/// ExportOptions::replace_existing and only if it holds an earlier export (then the swap is
/// one atomic rename where the file system supports it). The parent folder must exist.
///
/// Throws ExportLimitError (nothing written) when the selection is over the limit,
/// ConfigError for impossible options, IoError when a file cannot be written or `out_dir` is
/// not usable. The library prints nothing: VTK's messages end up in the exception's text.
/// Memory: about 200 bytes per exported primitive plus the mesh, while the blocks are built.
/// Precondition: check_invariants(grid) passes; mesh has grid.triangle_count triangles.
[[nodiscard]] ExportSummary export_vtk(const SplitGrid& grid, const MeshView& mesh,
                                       const ExportOptions& options,
                                       const ExportMetadata& metadata,
                                       const std::filesystem::path& out_dir);

namespace detail {
class StagedFolder;
}

/// The output folder of an export, reserved before the work: the constructor checks
/// `out_dir` as export_vtk() does (replace_existing as ExportOptions::replace_existing) and
/// creates the hidden staging folder beside it at once, so that a folder that cannot be
/// written is found before a large .sg file is read. It also removes the staging folders of
/// `out_dir` that killed runs left behind (stale_removed() lists them). Until the export is
/// committed the staging folder is removed on destruction and on an interrupt. Throws
/// IoError naming the path.
class ExportFolder {
public:
    ExportFolder(const std::filesystem::path& out_dir, bool replace_existing);
    ~ExportFolder();
    ExportFolder(const ExportFolder&) = delete;
    ExportFolder& operator=(const ExportFolder&) = delete;

    [[nodiscard]] const std::filesystem::path& path() const noexcept { return out_dir_; }
    [[nodiscard]] bool replace_existing() const noexcept { return replace_existing_; }
    /// Staging folders of killed runs removed by the constructor.
    [[nodiscard]] const std::vector<std::filesystem::path>& stale_removed() const noexcept;
    /// The staging folder (for export_vtk).
    [[nodiscard]] detail::StagedFolder& staged() noexcept { return *staged_; }

private:
    std::filesystem::path out_dir_;
    bool replace_existing_;
    std::unique_ptr<detail::StagedFolder> staged_;
};

/// export_vtk() into a folder reserved earlier, which it commits.
/// ExportOptions::replace_existing must equal the folder's replace_existing() (ConfigError).
[[nodiscard]] ExportSummary export_vtk(const SplitGrid& grid, const MeshView& mesh,
                                       const ExportOptions& options,
                                       const ExportMetadata& metadata, ExportFolder& folder);

}  // namespace sg::viz
