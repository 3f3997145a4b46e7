#pragma once

#include <string>
#include <utility>
#include <vector>

#include "point_queries.hpp"
#include "sampling_grid.hpp"
#include "splitgrid/formats/library_versions.hpp"
#include "splitgrid/formats/output_file.hpp"

/// The output of sg-points --grid: the answers on the grid as VTK image data (.vti) for
/// ParaView, written through viz/ where the tool is built with VTK (grid_field_vtk.cpp), and
/// refused where it is not (grid_field_without_vtk.cpp).
namespace sg::apps {

/// Facts about the field, written as field data beside the arrays.
struct GridFieldFacts {
    std::vector<std::pair<std::string, std::string>> texts;
    std::vector<std::pair<std::string, double>> numbers;
};

/// Empty where --grid can be answered; else why not, as one line for the refusal.
[[nodiscard]] std::string why_no_grid_field();

/// The libraries that write the field, for --version: VTK where the tool is built with it.
[[nodiscard]] std::vector<LibraryVersion> grid_field_libraries();

/// Writes `answers` (of `query`, in the grid's point order) as VTK image data placed where
/// the grid's points lie, into `output`, and commits it. The point-data arrays, the active
/// scalars first: "occupancy"; "distance"; "signed_distance"; for the closest point query
/// "distance", "closest_point" (3 components, NaN where there is no answer) and "triangle_id"
/// (Int64, -1 where there is none).
void write_grid_field(OutputFile& output, const SamplingGrid& grid, PointQuery query,
                      const PointAnswers& answers, const GridFieldFacts& facts);

}  // namespace sg::apps
