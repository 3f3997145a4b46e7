#pragma once

#include "grid_object.hpp"

#include <pybind11/pybind11.h>

namespace sg::python {

namespace py = pybind11;

/// Adds the point queries to the SplitGrid class, under Open3D's RaycastingScene names and
/// shapes: compute_closest_points, compute_distance, compute_signed_distance and
/// compute_occupancy.
void bind_point_queries(py::class_<GridObject>& grid_class);

}  // namespace sg::python
