#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

/// Fields sampled on a regular grid of points (sg-points --grid), written as VTK image data
/// (.vti) for ParaView. This header includes no VTK header: VTK stays private to splitgrid_viz.
namespace sg {

class OutputFile;

namespace viz {

/// Where the samples lie: point (i, j, k) at origin + (i * spacing[0], j * spacing[1],
/// k * spacing[2]), computed in double as VTK computes it, i (x) fastest, then j, then k: the
/// order of VTK image data, so value n of an array belongs to point
/// i + dimensions[0] * (j + dimensions[1] * k).
struct ImageGeometry {
    std::array<std::uint32_t, 3> dimensions{1, 1, 1};  ///< points per axis, each >= 1
    std::array<double, 3> origin{0.0, 0.0, 0.0};      ///< point (0, 0, 0); finite
    std::array<double, 3> spacing{1.0, 1.0, 1.0};     ///< between neighbours; finite, > 0

    /// dimensions[0] * dimensions[1] * dimensions[2].
    [[nodiscard]] std::uint64_t point_count() const noexcept
    {
        return std::uint64_t{dimensions[0]} * dimensions[1] * dimensions[2];
    }
};

/// A float32 point-data array: `components` values per point, point_count * components in
/// all (+infinity and NaN are written as they are).
struct FloatPointArray {
    std::string name;
    std::span<const float> values;
    int components = 1;
};

/// Triangle ids, one per point (0xFFFFFFFF for none), written as an Int64 point-data array
/// with -1 for none: ParaView then colours and thresholds real ids without a 4-billion
/// outlier.
struct IdPointArray {
    std::string name;
    std::span<const std::uint32_t> values;
};

/// What write_image_field writes: the geometry, the point data and facts about the field's
/// origin, written as one-tuple field data (ParaView's Information panel shows them).
struct ImageField {
    ImageGeometry geometry;
    /// The first is the active scalars, which ParaView colours by and contours at once.
    std::vector<FloatPointArray> floats;
    std::vector<IdPointArray> ids;
    std::vector<std::pair<std::string, std::string>> text_facts;
    std::vector<std::pair<std::string, double>> number_facts;
};

/// Writes `field` as VTK XML image data (vtkXMLImageDataWriter: appended raw binary, zlib
/// compressed, 64-bit block headers, like the export of vtk_export.hpp) to the temporary file
/// of `output`, then commits it, so the target is either the old file or the whole new one.
/// The float arrays are handed to VTK without a copy. Throws ConfigError naming the target for a
/// geometry outside its ranges, no float array, or an array whose length does not match the
/// point count; IoError if the write fails.
void write_image_field(OutputFile& output, const ImageField& field);

}  // namespace viz
}  // namespace sg
