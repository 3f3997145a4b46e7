#pragma once

#include <pybind11/pybind11.h>

namespace sg::python {

namespace py = pybind11;

/// import_mesh(): a mesh file as numpy arrays, read the way sg-build reads it.
void bind_import(py::module_& m);

}  // namespace sg::python
