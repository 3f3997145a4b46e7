#pragma once

#include <vector>

#include "splitgrid/viz/render.hpp"

namespace sg::detail {

/// The colour scale of a heat map over the pixel values `values` (HeatLegend documents the
/// automatic choice): title, scale_max, ticks and labels, max_value and clamped_fraction.
/// `heat_max` > 0 fixes the top of the scale. The legend's geometry is left to
/// draw_heat_legend. Cost: one selection over a copy of the values.
[[nodiscard]] HeatLegend make_heat_scale(const std::vector<float>& values, double heat_max,
                                         RenderMode mode);

}  // namespace sg::detail
