#include "errors.hpp"

#include <exception>

#include "splitgrid/error.hpp"

namespace sg::python {
namespace {

// The classes are owned by the module (its attributes), so they live as long as it does; the
// pointers here are borrowed. No static py::object: its destructor would run after the
// interpreter has finalised.
PyObject* format_error = nullptr;
PyObject* invalid_ray_warning = nullptr;
PyObject* mesh_import_warning = nullptr;
PyObject* open_mesh_warning = nullptr;

PyObject* new_class(py::module_& m, const char* name, PyObject* base, const char* doc)
{
    const std::string qualified = std::string("splitgrid.") + name;
    PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, base, nullptr);
    if (cls == nullptr) throw py::error_already_set();
    m.add_object(name, py::reinterpret_steal<py::object>(cls));
    return cls;
}

void warn(PyObject* category, const std::string& message)
{
    if (PyErr_WarnEx(category, message.c_str(), 1) != 0) throw py::error_already_set();
}

}  // namespace

void bind_errors(py::module_& m)
{
    format_error = new_class(
        m, "FormatError", PyExc_ValueError,
        "A .sg file whose bytes do not follow the format: bad magic, truncation, checksum "
        "mismatch, an index out of range. The message names the file and, where known, the "
        "byte offset. A ValueError.");
    invalid_ray_warning = new_class(
        m, "InvalidRayWarning", PyExc_UserWarning,
        "Some rays of a query were invalid (NaN or infinite origin or direction, zero "
        "direction, NaN or infinite tnear, NaN tfar, or tnear > tfar) and were answered as "
        "misses. The message counts them and names the first.");
    mesh_import_warning = new_class(
        m, "MeshImportWarning", PyExc_UserWarning,
        "import_mesh() skipped or dropped part of a file (points, lines, zero-area or "
        "non-finite triangles), or the file looks misread. One warning per finding, as "
        "sg-build logs them.");
    open_mesh_warning = new_class(
        m, "OpenMeshWarning", PyExc_UserWarning,
        "compute_occupancy() or compute_signed_distance() on a mesh that is not closed: some "
        "edge is shared by an odd number of triangles, so inside and outside by parity are not "
        "defined everywhere. The message counts the open and non-manifold edges; "
        "SplitGrid.stats()['edges'] has them too.");

    py::register_exception_translator([](std::exception_ptr error) {
        try {
            if (error) std::rethrow_exception(error);
        } catch (const FormatError& e) {
            PyErr_SetString(format_error, e.what());
        } catch (const IoError& e) {
            PyErr_SetString(PyExc_OSError, e.what());
        } catch (const InputError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        } catch (const ConfigError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        }
    });
}

void warn_invalid_rays(const std::string& message) { warn(invalid_ray_warning, message); }

void warn_mesh_import(const std::string& message) { warn(mesh_import_warning, message); }

void warn_open_mesh(const std::string& message) { warn(open_mesh_warning, message); }

}  // namespace sg::python
