// Mesh import through Assimp (with opened_files.cpp and library_versions.cpp, the only
// files of the project that include Assimp).

#include "mesh_import_assimp.hpp"

#include <cstdint>
#include <exception>
#include <limits>
#include <new>
#include <string>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "assimp_guards.hpp"
#include "opened_files.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/vertex_weld.hpp"

namespace sg {
namespace {

/// Post-processing applied after the file is read:
/// - Triangulate: polygons become triangles; points and lines stay as 1- and 2-index faces,
///   which we count as skipped.
/// - PreTransformVertices: bakes every node transform (and instancing) into the vertices,
///   so the mesh is in scene space.
/// - SortByPType: one primitive type per mesh, so mPrimitiveTypes is meaningful.
/// JoinIdenticalVertices is deliberately off: it merges positions within four units in the
/// last place (so it moves vertices) and keeps corners apart whose normals or texture
/// coordinates differ; weld_identical_vertices() merges exactly the bit-identical positions
/// instead. FindDegenerates is off too: it would turn zero-area triangles into lines or
/// points (or delete them) without telling us, and clean_mesh counts them instead.
constexpr unsigned post_processing =
    aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType;

/// The warning heuristic: a real surface mesh has about two triangles per vertex, so fewer
/// than one triangle per this many vertices means most of the file was not read.
constexpr std::size_t vertices_per_triangle_warning = 8;
constexpr std::size_t warning_min_vertices = 1000;

/// Assimp's error strings sometimes span lines; messages of the toolkit are one line.
std::string one_line(std::string text)
{
    for (char& c : text)
        if (c == '\n' || c == '\r') c = ' ';
    while (!text.empty() && text.back() == ' ') text.pop_back();
    return text.empty() ? std::string("Assimp gave no reason") : text;
}

/// Appends the triangles of one mesh, counting the faces of other kinds.
void append_mesh(const aiMesh& in, Mesh& out, ImportReport& report)
{
    const auto base = static_cast<std::uint32_t>(out.vertices.size());
    bool has_triangles = false;
    for (unsigned f = 0; f < in.mNumFaces; ++f) {
        const aiFace& face = in.mFaces[f];
        switch (face.mNumIndices) {
        case 1: ++report.points_skipped; break;
        case 2: ++report.lines_skipped; break;
        case 3:
            out.triangles.push_back(Triangle{{base + face.mIndices[0], base + face.mIndices[1],
                                              base + face.mIndices[2]}});
            has_triangles = true;
            break;
        default:
            // aiProcess_Triangulate leaves no polygons; a face with 0 indices would be a
            // loader bug. Neither is a triangle.
            break;
        }
    }
    report.faces_read += in.mNumFaces;
    // Vertices of point and line meshes would only be dropped again by compaction.
    if (!has_triangles) return;
    out.vertices.reserve(out.vertices.size() + in.mNumVertices);
    for (unsigned v = 0; v < in.mNumVertices; ++v) {
        const aiVector3D& p = in.mVertices[v];
        out.vertices.push_back(
            Vec3f{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
    }
}

/// Rethrows Assimp's std::bad_alloc, which it would otherwise report as a parse error: running
/// out of memory is a limit of the machine or of the import process, not a fault of the file.
void rethrow_out_of_memory(const Assimp::Importer& importer)
{
    const std::exception_ptr& error = importer.GetException();
    if (!error) return;
    try {
        std::rethrow_exception(error);
    } catch (const std::bad_alloc&) {
        throw;
    } catch (...) {
        // Any other exception is described by GetErrorString().
    }
}

}  // namespace

namespace detail {

ImportedMesh import_mesh_in_process(const std::filesystem::path& path)
{
    // Also turns "does not exist" and "permission denied" into IoError with the system's
    // reason: Assimp would report them as parse failures.
    detail::refuse_known_assimp_hangs(path);
    const std::string name = path.string();

    // No Assimp::DefaultLogger is created, so Assimp logs to its silent NullLogger and
    // writes nothing to stdout or stderr.
    Assimp::Importer importer;
    const std::vector<std::string>& opened_files = detail::record_opened_files(importer);
    // ValidateDataStructure runs on the raw scene, before the other steps: they trust the
    // indices, and a hostile file must be refused rather than crash them.
    const aiScene* scene = importer.ReadFile(name, aiProcess_ValidateDataStructure);
    if (scene == nullptr) rethrow_out_of_memory(importer);
    if (scene == nullptr) throw InputError(name + ": " + one_line(importer.GetErrorString()));

    // Counted before post-processing, which drops vertices no face uses: a file whose faces
    // Assimp cannot read (PLY tristrips) shows up as many vertices and few triangles.
    std::size_t vertices_in_file = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m)
        vertices_in_file += scene->mMeshes[m]->mNumVertices;

    scene = importer.ApplyPostProcessing(post_processing);
    if (scene == nullptr) rethrow_out_of_memory(importer);
    if (scene == nullptr) throw InputError(name + ": " + one_line(importer.GetErrorString()));

    ImportedMesh result;
    ImportReport& report = result.report;
    report.meshes = scene->mNumMeshes;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh& mesh = *scene->mMeshes[m];
        if (result.mesh.vertices.size() + mesh.mNumVertices >
            std::numeric_limits<std::uint32_t>::max())
            throw InputError(name + ": more than 2^32 - 1 vertices, the limit of 32-bit indices");
        append_mesh(mesh, result.mesh, report);
    }
    report.triangles_read = result.mesh.triangles.size();
    // Triangle ids are 32-bit and 0xFFFFFFFF means "no hit" (ray.hpp).
    if (report.triangles_read >= std::numeric_limits<std::uint32_t>::max())
        throw InputError(name + ": more than 2^32 - 2 triangles, the limit of 32-bit ids");
    importer.FreeScene();
    report.opened_files = opened_files;

    const CleanReport cleaned = clean_mesh(result.mesh);
    report.nonfinite_dropped = cleaned.nonfinite_triangles;
    report.degenerate_dropped = cleaned.degenerate_triangles;
    if (cleaned.bad_index_triangles > 0)
        report.warnings.push_back(std::to_string(cleaned.bad_index_triangles) +
                                  " triangles with a vertex index out of range were dropped");
    // After clean_mesh, so which triangles are dropped does not depend on the welding (it
    // changes no position), and no non-finite vertex is left to weld.
    const WeldReport welded = weld_identical_vertices(result.mesh);
    report.vertices_before_welding = welded.vertices_before;
    report.vertices = welded.vertices_after;

    const std::size_t triangles = result.mesh.triangles.size();
    if (triangles == 0)
        throw InputError(name + ": no triangles (" + std::to_string(report.points_skipped) +
                         " points, " + std::to_string(report.lines_skipped) + " lines skipped, " +
                         std::to_string(cleaned.dropped()) + " degenerate dropped)");
    if (vertices_in_file > warning_min_vertices &&
        triangles * vertices_per_triangle_warning < vertices_in_file)
        report.warnings.push_back(
            "only " + std::to_string(triangles) + " triangles for " +
            std::to_string(vertices_in_file) +
            " vertices: the file may use an element Assimp does not read (for example PLY "
            "tristrips)");
    return result;
}

}  // namespace detail
}  // namespace sg
