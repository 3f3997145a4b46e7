#pragma once

#include <cstdint>
#include <vector>

#include "hierarchy.hpp"
#include "selection.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/viz/vtk_export.hpp"

#include <vtkDataObject.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

/// Builders of the VTK data sets of the export, one per block (docs/VIZ.md lists every array).
namespace sg::viz::detail {

/// Which cells a cell block holds.
enum class CellBlockKind {
    all_exported,  ///< "cells": every exported cell of the selected nodes
    leaves_only,   ///< "leaves": only the leaf cells among them
};

/// Hexahedra, each with its own 8 points in VTK's corner order, with the cell-data arrays
/// depth (active scalars), node_id, cell_index, axis, kind, triangle_count and cost_share.
/// `count` is the number of cells the selection holds (from the counting pass; checked).
[[nodiscard]] vtkSmartPointer<vtkUnstructuredGrid>
make_cell_block(const SplitGrid& grid, const Hierarchy& hierarchy,
                const std::vector<std::uint32_t>& nodes, const Selection& selection,
                CellBlockKind kind, std::uint64_t count);

/// Two quads per node (lo and hi plane, each with its own 4 points), with the cell-data
/// arrays depth (active scalars), node_id, side, axis and cut_fraction.
[[nodiscard]] vtkSmartPointer<vtkPolyData>
make_plane_block(const SplitGrid& grid, const Hierarchy& hierarchy,
                 const std::vector<std::uint32_t>& nodes);

/// The mesh as triangles over its shared vertices (cell i is triangle i), with the cell-data
/// array reference_count (active scalars): how many leaves of the whole grid reference it.
[[nodiscard]] vtkSmartPointer<vtkPolyData> make_mesh_block(const SplitGrid& grid,
                                                           const MeshView& mesh);

/// Everything written as field data on every block: source and structure names, the build
/// parameters, totals of the whole grid and the selection that made the export.
struct FieldFacts {
    const SplitGrid* grid = nullptr;
    const ExportMetadata* metadata = nullptr;
    const ExportOptions* options = nullptr;
    double expected_cost = 0.0;
};

/// Adds the field-data arrays of `facts` to `block` (one tuple each).
void add_field_data(vtkDataObject& block, const FieldFacts& facts);

}  // namespace sg::viz::detail
