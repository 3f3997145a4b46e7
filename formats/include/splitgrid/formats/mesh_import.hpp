#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "splitgrid/mesh.hpp"

namespace sg {

/// What import_mesh() read, skipped and dropped.
struct ImportReport {
    std::size_t meshes = 0;               ///< meshes in the scene (after instancing)
    std::size_t faces_read = 0;           ///< faces of all kinds Assimp returned
    std::size_t triangles_read = 0;       ///< triangles before cleaning
    std::size_t points_skipped = 0;       ///< point primitives (not triangles)
    std::size_t lines_skipped = 0;        ///< line primitives (not triangles)
    std::size_t nonfinite_dropped = 0;    ///< triangles with a NaN or infinite coordinate
    std::size_t degenerate_dropped = 0;   ///< zero-area triangles
    std::size_t vertices = 0;             ///< vertices kept
    /// Human-readable warnings (one line each), e.g. a face count implausibly small for the
    /// vertex count, which happens with PLY tristrips that Assimp does not read.
    std::vector<std::string> warnings;
};

/// A mesh read from a file, with the report of what was read.
struct ImportedMesh {
    Mesh mesh;
    ImportReport report;
};

/// Reads every mesh of a scene file through Assimp (any format it reads: obj, ply, stl, off,
/// gltf/glb, dae, fbx, 3ds, ...), applies the node transforms, triangulates polygons, skips
/// points and lines, and drops triangles with non-finite corners or zero area (see
/// clean_mesh). Vertices that no kept triangle uses are removed. Assimp writes nothing to
/// stdout or stderr. Throws IoError "<path>: cannot open: <reason>" if the file cannot be
/// opened, InputError "<path>: ..." if Assimp cannot parse it (or the file is a PLY with a
/// header Assimp 5.2 would loop on forever), or "<path>: no triangles (N points, M lines
/// skipped, K degenerate dropped)" if no triangle remains (K counts every dropped triangle).
/// docs/FORMAT.md section 4 lists the Assimp steps used and why.
[[nodiscard]] ImportedMesh import_mesh(const std::filesystem::path& path);

}  // namespace sg
