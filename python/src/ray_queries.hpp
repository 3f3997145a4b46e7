#pragma once

#include "grid_object.hpp"

#include <pybind11/pybind11.h>

namespace sg::python {

namespace py = pybind11;

/// Adds the ray queries to the SplitGrid class, under Open3D's RaycastingScene names and
/// shapes: cast_rays (closest hit), test_occlusions (any hit), count_intersections and
/// list_intersections (every hit).
void bind_ray_queries(py::class_<GridObject>& grid_class);

}  // namespace sg::python
