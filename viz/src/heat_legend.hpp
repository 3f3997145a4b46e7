#pragma once

#include "splitgrid/viz/image.hpp"
#include "splitgrid/viz/render.hpp"

namespace sg::detail {

/// Draws the legend of `legend` (scale, ticks, labels, title: see make_heat_scale) into the
/// top-right corner of `image`: a dark panel holding the title, the colour bar with the
/// scale's top at the top, tick marks and labels. Text is rasterised by VTK's FreeType
/// module (vtkFreeTypeTools, fonts built into VTK, no display needed), at a size that
/// follows the image height. Sets legend.drawn and the bar and panel rectangles; an image
/// too small to hold the panel is left untouched (drawn = false).
void draw_heat_legend(RgbImage& image, HeatLegend& legend);

}  // namespace sg::detail
