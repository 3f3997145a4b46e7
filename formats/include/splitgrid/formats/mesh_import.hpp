#pragma once

#include <cstddef>
#include <cstdint>
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
    /// Vertices of the kept triangles as the file's meshes gave them, before welding: Assimp
    /// gives OBJ and STL files one vertex per triangle corner, and other formats one per
    /// distinct (position, normal, texture coordinate, ...) combination.
    std::size_t vertices_before_welding = 0;
    std::size_t vertices = 0;             ///< vertices kept: distinct positions after welding
    /// Human-readable warnings (one line each), e.g. a face count implausibly small for the
    /// vertex count, which happens with PLY tristrips that Assimp does not read.
    std::vector<std::string> warnings;
    /// Every file the importer opened, as it named them: the mesh file and the files it
    /// refers to (a glTF's .bin buffers, an OBJ's .mtl). The tools refuse to write over any
    /// of them.
    std::vector<std::string> opened_files;
};

/// A mesh read from a file, with the report of what was read.
struct ImportedMesh {
    Mesh mesh;
    ImportReport report;
};

/// Where Assimp runs. Assimp 5.2 (Debian 12) aborts the whole process on some malformed files
/// (an internal assertion, e.g. on a truncated ASCII PLY), and may loop or exhaust memory on
/// others; no exception reaches the caller in those cases.
enum class ImportIsolation {
    /// Assimp runs in a forked child process with an address-space and a CPU-time limit; the
    /// mesh comes back through a pipe. A crash, abort, timeout or memory exhaustion of the
    /// child becomes an InputError naming the file and the reason. Costs a fork and one copy
    /// of the mesh through the pipe (docs/HARDENING.md, "13. Hostile mesh files", has the
    /// figure).
    child_process,
    /// Assimp runs in the calling process: no fork, but a hostile file can take the process
    /// down. For trusted files, or callers that cannot fork (see ImportOptions).
    in_process,
};

/// Limits of one import. The defaults suit meshes up to about 10^7 triangles on a machine
/// with 8 GiB or more; a tool that imports untrusted files may lower them.
struct ImportOptions {
    ImportIsolation isolation = ImportIsolation::child_process;
    /// Wall-clock seconds the child may take (its CPU time is limited to the same figure).
    /// Range (0, 1e6]. Assimp reads a scan of a million triangles in seconds
    /// (docs/notebook/build.md, "The mesh import in a child process: what the isolation
    /// costs"), so 300 s leaves room for 10^7-triangle scenes on a slow machine.
    double time_limit_seconds = 300.0;
    /// Address space the child may add to what it inherits from the parent, in bytes;
    /// 0 means no limit. A whole sg-build peaks at a few hundred bytes per triangle
    /// (docs/notebook/build.md, "The mesh import in a child process: what the isolation
    /// costs"), so the default 16 GiB holds 10^7-triangle scenes with room to spare. Under
    /// AddressSanitizer the limit does not bind as it should (ASan reserves its heap address
    /// space at start-up), and hitting it aborts the child (a crash message).
    std::uint64_t memory_limit_bytes = std::uint64_t{16} << 30;
};

/// Reads every mesh of a scene file through Assimp (any format it reads: obj, ply, stl, off,
/// gltf/glb, dae, fbx, 3ds, ...), applies the node transforms, triangulates polygons, skips
/// points and lines, drops triangles with non-finite corners or zero area (see clean_mesh),
/// then welds the vertices with bit-identical positions (weld_identical_vertices), which
/// also removes the vertices no kept triangle uses. Triangle ids are the order of the faces
/// in the file's meshes, whatever the welding does. Assimp writes nothing to
/// stdout or stderr. Throws IoError "<path>: cannot open: <reason>" if the file cannot be
/// opened, InputError "<path>: ..." if Assimp cannot parse it (or the file is a PLY with a
/// header Assimp 5.2 would loop on forever), or "<path>: no triangles (N points, M lines
/// skipped, K degenerate dropped)" if no triangle remains (K counts every dropped triangle).
/// With ImportIsolation::child_process (the default) also InputError "<path>: importer
/// crashed (signal N, <name>)[: <its last message>]", "<path>: import exceeded the time limit
/// of S s" and "<path>: import exceeded the memory limit of M MiB"; ConfigError for limits
/// out of range; IoError if no child process can be started.
/// Forking from a process with other threads is safe here (the child runs only this import
/// and never returns into the caller's code), but a library whose state other threads hold
/// locked at the fork would be unusable in the child: Assimp holds none.
/// docs/FORMAT.md section 4 lists the Assimp steps used and why.
[[nodiscard]] ImportedMesh import_mesh(const std::filesystem::path& path,
                                       const ImportOptions& options = {});

/// What a user of import_mesh() should be told about `path`'s import, one line each, as sg-build
/// logs them and the Python package raises them as warnings: the report's own warnings, then
/// the point and line primitives skipped, the triangles with non-finite corners and the
/// zero-area triangles dropped (each line only when its count is not zero).
[[nodiscard]] std::vector<std::string> import_warnings(const std::filesystem::path& path,
                                                       const ImportReport& report);

}  // namespace sg
