#include "mesh_arrays.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "numpy_arguments.hpp"
#include "splitgrid/error.hpp"

namespace sg::python {
namespace {

void check_triples(const py::array& array, const char* argument, const char* count_name)
{
    if (array.ndim() != 2 || array.shape(1) != 3)
        throw py::value_error(std::string(argument) + ": expected shape (" + count_name +
                              ", 3), got shape " + shape_text(array));
}

template <class T>
void copy_vertices(const py::array& array, std::vector<Vec3f>& out)
{
    const auto values = array.unchecked<T, 2>();
    out.resize(static_cast<std::size_t>(values.shape(0)));
    for (py::ssize_t i = 0; i < values.shape(0); ++i) {
        float xyz[3];
        for (py::ssize_t k = 0; k < 3; ++k) {
            const T value = values(i, k);
            xyz[k] = static_cast<float>(value);
            if (std::isfinite(value) && !std::isfinite(xyz[k]))
                throw py::value_error("vertices[" + std::to_string(i) + ", " + std::to_string(k) +
                                      "] = " + py::str(py::float_(static_cast<double>(value)))
                                                   .cast<std::string>() +
                                      " is outside float32's range");
        }
        out[static_cast<std::size_t>(i)] = {xyz[0], xyz[1], xyz[2]};
    }
}

template <class T>
void copy_triangles(const py::array& array, std::size_t vertex_count, std::vector<Triangle>& out)
{
    const auto values = array.unchecked<T, 2>();
    out.resize(static_cast<std::size_t>(values.shape(0)));
    for (py::ssize_t i = 0; i < values.shape(0); ++i) {
        for (py::ssize_t k = 0; k < 3; ++k) {
            const T value = values(i, k);
            const auto entry = [&] {
                return "triangles[" + std::to_string(i) + ", " + std::to_string(k) +
                       "] = " + std::to_string(value);
            };
            if constexpr (std::is_signed_v<T>) {
                if (value < 0) throw py::value_error(entry() + " is negative");
            }
            if (static_cast<std::uint64_t>(value) >= vertex_count)
                throw py::value_error(entry() + " is not a vertex index: there are " +
                                      std::to_string(vertex_count) + " vertices");
            out[static_cast<std::size_t>(i)].v[static_cast<std::size_t>(k)] =
                static_cast<std::uint32_t>(value);
        }
    }
}

template <class... T>
bool copy_triangles_as(const py::array& array, std::size_t vertex_count,
                       std::vector<Triangle>& out)
{
    return ((py::isinstance<py::array_t<T>>(array) &&
             (copy_triangles<T>(array, vertex_count, out), true)) ||
            ...);
}

}  // namespace

Mesh mesh_from_arrays(const py::handle& vertices, const py::handle& triangles)
{
    Mesh mesh;
    const py::array v = as_array(vertices);
    if (v.dtype().kind() != 'f' || (v.itemsize() != 4 && v.itemsize() != 8))
        throw py::type_error("vertices: dtype " + dtype_text(v) +
                             " is not supported; give float32 or float64");
    check_triples(v, "vertices", "N");
    if (v.itemsize() == 4)
        copy_vertices<float>(converted<float>(v), mesh.vertices);
    else
        copy_vertices<double>(converted<double>(v), mesh.vertices);

    const py::array t = as_array(triangles);
    const char kind = t.dtype().kind();
    if (kind != 'i' && kind != 'u')
        throw py::type_error("triangles: dtype " + dtype_text(t) +
                             " is not supported; give vertex indices of an integer dtype");
    check_triples(t, "triangles", "M");
    if (t.shape(0) == 0) throw py::value_error("triangles: the mesh has no triangles");
    // Integer dtypes of the other byte order are made native first (one copy).
    const py::array native = t.dtype().attr("isnative").cast<bool>()
                                 ? t
                                 : py::array(t.attr("astype")(t.dtype().attr("newbyteorder")("=")));
    const bool copied =
        copy_triangles_as<std::int8_t, std::int16_t, std::int32_t, std::int64_t, std::uint8_t,
                          std::uint16_t, std::uint32_t, std::uint64_t>(native,
                                                                       mesh.vertices.size(),
                                                                       mesh.triangles);
    if (!copied)
        throw py::type_error("triangles: dtype " + dtype_text(t) + " is not supported");
    // The library's check, for what is left: a NaN or infinite vertex that a triangle uses.
    try {
        check_mesh(mesh.view());
    } catch (const InputError& e) {
        throw py::value_error(std::string("vertices: ") + e.what());
    }
    return mesh;
}

}  // namespace sg::python
