#pragma once

#include "splitgrid/mesh.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace sg::python {

namespace py = pybind11;

/// The `vertices` and `triangles` arguments as the library's mesh, copied once (the grid keeps
/// its own mesh, which SplitGrid.vertices and .triangles show without copying again).
/// vertices: (N, 3) float32 or float64; float64 is rounded to float32, and a finite value
/// outside float32's range is refused rather than made infinite. triangles: (M, 3) of any
/// integer dtype, every index in [0, N). Throws TypeError for a dtype, ValueError for a shape,
/// an index out of range, a NaN or infinite vertex that a triangle uses (check_mesh's message)
/// or an empty mesh, each naming the argument (and the entry: "triangles[4, 2] = -1 is
/// negative").
[[nodiscard]] Mesh mesh_from_arrays(const py::handle& vertices, const py::handle& triangles);

/// A read-only (N, 3) numpy view of `values` (float32 or uint32 triples) that keeps `owner`
/// alive: no copy.
template <class T, class Triple>
[[nodiscard]] py::array_t<T> triple_view(const std::vector<Triple>& values, const py::handle& owner)
{
    static_assert(sizeof(Triple) == 3 * sizeof(T), "a view needs three packed values per record");
    const auto n = static_cast<py::ssize_t>(values.size());
    const auto row = static_cast<py::ssize_t>(sizeof(Triple));
    const auto column = static_cast<py::ssize_t>(sizeof(T));
    py::array_t<T> view({n, py::ssize_t{3}}, {row, column},
                        reinterpret_cast<const T*>(values.data()), owner);
    py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return view;
}

}  // namespace sg::python
