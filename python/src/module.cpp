// splitgrid._splitgrid: the compiled part of the splitgrid package (python/splitgrid/__init__.py
// re-exports it). A thin binding: it converts arrays and errors and calls the public C++ API.

#include "bind_grid.hpp"
#include "bind_import.hpp"
#include "errors.hpp"
#include "splitgrid/query.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/version.hpp"

#include <pybind11/pybind11.h>

namespace py = pybind11;

PYBIND11_MODULE(_splitgrid, m)
{
    m.doc() = "The Split Grid ray-tracing acceleration structure (compiled part of splitgrid).";
    m.attr("__version__") = sg::version_string;
    m.attr("INVALID_ID") = py::int_(sg::invalid_triangle);
    m.def(
        "kernel_isa", [] { return std::string(sg::isa_name(sg::kernel_isa())); },
        "The instruction set the query kernels run on: 'scalar', 'sse2', 'avx2' or 'avx512' "
        "(the best the processor has, or the environment variable SG_ISA's choice).");
    sg::python::bind_errors(m);
    sg::python::bind_grid(m);
    sg::python::bind_import(m);
}
