#include "bind_grid.hpp"

#include <filesystem>
#include <string>

#include "grid_object.hpp"
#include "mesh_arrays.hpp"
#include "point_queries.hpp"
#include "ray_queries.hpp"
#include "splitgrid/formats/stats_json.hpp"

#include <pybind11/stl/filesystem.h>

namespace sg::python {
namespace {

constexpr const char* class_doc = R"doc(A triangle mesh with its Split Grid, ready for ray queries.

Made by splitgrid.build() from numpy arrays or splitgrid.load() from a .sg file;
saved with save(). It never changes once made: any number of threads may query
it at once, and the arrays it returns stay valid as long as they are referenced.
)doc";

constexpr const char* build_doc = R"doc(Builds the Split Grid of a triangle mesh.

Parameters
----------
vertices : array_like, float32 or float64, shape (N, 3)
    Vertex positions. float64 is rounded to float32 (the precision of the
    structure and its ray tests); a finite value beyond float32's range is an
    error.
triangles : array_like, any integer dtype, shape (M, 3)
    Vertex indices of each triangle, in [0, N). Triangle ids in query results
    are rows of this array.
preset : {"default", "poster"}, optional
    "default" is the fastest Split Grid of the library; "poster" the
    construction of the Eurographics 2014 poster (no bounding nodes, no cost
    test). Parameters given with it override it, as sg-build's flags do.
threads : int or None, optional
    oneTBB threads for the build: None or 0 for all hardware threads. The
    result is the same for every thread count.
source_name : str, optional
    Name of the mesh's source file, stored in .sg files (sg-build stores the
    mesh file's name).
**params
    Build parameters under the names of sg-build's flags with "_" for "-":
    resolution_min, resolution_max, resolution_sigma, leaf_size, max_depth,
    no_progress_fraction, min_cell_width (numbers) and stop_by_cost,
    bounding_planes, bounding_nodes, clip_triangles (bools). Ranges and
    defaults: `sg-build --help` and docs/PYTHON.md.

Returns
-------
SplitGrid

Raises
------
TypeError
    A dtype that is not supported, an unknown parameter name, or a parameter of
    the wrong type.
ValueError
    A wrong shape, a triangle index out of range or negative, a NaN or
    infinite vertex used by a triangle, an empty mesh, or a parameter out of
    range (the library's message, as sg-build prints it).

Notes
-----
The GIL is released during the build; Ctrl-C stops it with KeyboardInterrupt.
)doc";

constexpr const char* load_doc = R"doc(Reads a .sg file (written by sg-build or SplitGrid.save).

Every check of the library's reader applies: magic, version, record sizes,
section table, counts against the file size, checksums, every index and the
grid's invariants.

Parameters
----------
path : str or os.PathLike

Returns
-------
SplitGrid

Raises
------
OSError
    The file is missing or cannot be read.
FormatError
    The file is damaged or truncated (a ValueError); the message names the file
    and, where known, the byte offset.
)doc";

constexpr const char* save_doc = R"doc(Writes the mesh and its grid to a .sg file, atomically.

The bytes go to a temporary file in the same folder, renamed over `path` only
when complete. A file read with load() and saved again is byte-identical.

Parameters
----------
path : str or os.PathLike

Raises
------
OSError
    The file cannot be written.
)doc";

constexpr const char* stats_doc =
    R"doc(Statistics of the grid: what `sg-stats FILE.sg --json` prints.

Returns
-------
dict
    Keys of docs/STATS_JSON.md: schema_version, splitgrid_version, file (None
    for a grid not read from a file), source_name, build_config, mesh,
    root_box, grid (depth, resolutions, leaves, references, memory, expected
    cost), bytes_per_triangle, coverage_checked.
)doc";

}  // namespace

void bind_grid(py::module_& m)
{
    py::class_<GridObject> grid_class(m, "SplitGrid", class_doc);
    grid_class
        .def("save",
             [](const GridObject& grid, const std::filesystem::path& path) {
                 const py::gil_scoped_release release;
                 write_sg_file(path, grid.contents);
             },
             py::arg("path"), save_doc)
        .def("stats", &grid_stats, stats_doc)
        .def_property_readonly(
            "vertices",
            [](const py::object& self) {
                return triple_view<float>(self.cast<const GridObject&>().contents.mesh.vertices,
                                          self);
            },
            "float32 (N, 3): the vertex positions, a read-only view (no copy).")
        .def_property_readonly(
            "triangles",
            [](const py::object& self) {
                return triple_view<std::uint32_t>(
                    self.cast<const GridObject&>().contents.mesh.triangles, self);
            },
            "uint32 (M, 3): the vertex indices of each triangle, a read-only view (no copy). "
            "Triangle ids of query results are its rows.")
        .def_property_readonly(
            "build_parameters",
            [](const GridObject& grid) { return to_python(to_json(grid.grid().config)); },
            "dict: the build parameters the grid was built with (build_config of "
            "docs/STATS_JSON.md; threads is always 0: the grid does not depend on it).")
        .def_property_readonly(
            "source_name", [](const GridObject& grid) { return grid.contents.source_name; },
            "str: the name of the mesh's source file, as stored in .sg files.")
        .def("__len__", [](const GridObject& grid) { return grid.contents.mesh.triangles.size(); },
             "Number of triangles.")
        .def("__repr__", [](const GridObject& grid) {
            return "<splitgrid.SplitGrid: " + std::to_string(grid.contents.mesh.triangles.size()) +
                   " triangles, " + std::to_string(grid.contents.mesh.vertices.size()) +
                   " vertices, " + std::to_string(grid.grid().memory_bytes()) +
                   " structure bytes>";
        });
    bind_ray_queries(grid_class);
    bind_point_queries(grid_class);

    m.def(
        "build",
        [](const py::object& vertices, const py::object& triangles, const std::string& preset,
           const py::object& threads, std::string source_name, const py::kwargs& params) {
            const BuildConfig config = build_config_from(preset, threads, params);
            return build_grid(mesh_from_arrays(vertices, triangles), config,
                              std::move(source_name));
        },
        py::arg("vertices"), py::arg("triangles"), py::kw_only(), py::arg("preset") = "default",
        py::arg("threads") = py::none(), py::arg("source_name") = "", build_doc);
    m.def("load", &load_grid, py::arg("path"), load_doc);
}

}  // namespace sg::python
