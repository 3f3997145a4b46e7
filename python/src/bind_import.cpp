#include "bind_import.hpp"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>

#include "errors.hpp"
#include "splitgrid/formats/mesh_import.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl/filesystem.h>

namespace sg::python {
namespace {

constexpr const char* import_mesh_doc = R"doc(Reads a mesh file exactly as sg-build reads it.

Assimp reads any format it knows (obj, ply, stl, off, gltf/glb, dae, fbx, 3ds,
...) in a child process with a time and memory limit, so a file that crashes or
hangs Assimp becomes an exception; all meshes of the scene are merged with
their node transforms, polygons triangulated, points and lines skipped,
triangles with non-finite corners or zero area dropped, and vertices with
bit-identical positions welded. build() on the result with sg-build's
parameters makes exactly the grid sg-build makes.

Parameters
----------
path : str or os.PathLike

Returns
-------
vertices : numpy.ndarray, float32, shape (N, 3)
triangles : numpy.ndarray, uint32, shape (M, 3)

Warns
-----
MeshImportWarning
    One per finding sg-build warns about: skipped points and lines, dropped
    triangles, a face count implausibly small for the vertex count.

Raises
------
OSError
    The file cannot be opened.
ValueError
    Assimp cannot read the file, it has no triangles, or the import crashed or
    exceeded its limits; the message names the file.
)doc";

}  // namespace

void bind_import(py::module_& m)
{
    m.def(
        "import_mesh",
        [](const std::filesystem::path& path) {
            auto mesh = std::make_unique<Mesh>();
            std::vector<std::string> warnings;
            {
                const py::gil_scoped_release release;
                ImportedMesh imported = import_mesh(path);
                warnings = import_warnings(path, imported.report);
                *mesh = std::move(imported.mesh);
            }
            for (const std::string& warning : warnings) warn_mesh_import(warning);
            // Both arrays share one owner: the mesh is handed over, not copied.
            Mesh* owned = mesh.release();
            const py::capsule owner(owned, [](void* p) { delete static_cast<Mesh*>(p); });
            const auto n = static_cast<py::ssize_t>(owned->vertices.size());
            const auto m_count = static_cast<py::ssize_t>(owned->triangles.size());
            py::array_t<float> vertices({n, py::ssize_t{3}},
                                        reinterpret_cast<const float*>(owned->vertices.data()),
                                        owner);
            py::array_t<std::uint32_t> triangles(
                {m_count, py::ssize_t{3}},
                reinterpret_cast<const std::uint32_t*>(owned->triangles.data()), owner);
            return py::make_tuple(vertices, triangles);
        },
        py::arg("path"), import_mesh_doc);
}

}  // namespace sg::python
