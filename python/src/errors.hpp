#pragma once

#include <string>

#include <pybind11/pybind11.h>

namespace sg::python {

namespace py = pybind11;

/// Registers the package's exception and warning classes on `m` and the translation of the
/// library's exceptions, messages unchanged:
/// - sg::FormatError -> splitgrid.FormatError, a ValueError (a damaged or truncated .sg file);
/// - sg::InputError, sg::ConfigError -> ValueError (unusable mesh or rays, a parameter out of
///   range);
/// - sg::IoError -> OSError (a missing or unreadable file);
/// - splitgrid.InvalidRayWarning, splitgrid.MeshImportWarning and splitgrid.OpenMeshWarning,
///   all UserWarnings.
void bind_errors(py::module_& m);

/// Issues `message` as a splitgrid.InvalidRayWarning. Throws py::error_already_set when the
/// warning filters turn it into an exception. Needs the GIL.
void warn_invalid_rays(const std::string& message);

/// Issues `message` as a splitgrid.MeshImportWarning, like warn_invalid_rays.
void warn_mesh_import(const std::string& message);

/// Issues `message` as a splitgrid.OpenMeshWarning, like warn_invalid_rays.
void warn_open_mesh(const std::string& message);

}  // namespace sg::python
