#pragma once

#include <pybind11/pybind11.h>

namespace sg::python {

namespace py = pybind11;

/// The SplitGrid class with its queries, and the functions that make one: build() and load().
void bind_grid(py::module_& m);

}  // namespace sg::python
