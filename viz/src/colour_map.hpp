#pragma once

#include <array>

#include "splitgrid/viz/image.hpp"

namespace sg::detail {

/// Entries of the heat colour map.
inline constexpr int heat_colour_count = 256;

/// The heat maps' colour map, lowest value first: dark violet, purple, red, orange, pale
/// yellow. Built once (thread-safe) by VTK's vtkColorTransferFunction interpolating five
/// control points in CIELAB; their lightness L* rises from about 6 to 96, so lightness
/// rises along the whole map and the map reads in grey print too.
[[nodiscard]] const std::array<Rgb8, heat_colour_count>& heat_colour_map();

/// The colour of `value` on the scale [0, scale_max] (clamped at both ends).
/// Precondition: scale_max > 0.
[[nodiscard]] Rgb8 heat_colour(double value, double scale_max) noexcept;

}  // namespace sg::detail
