#include "heat_legend.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "colour_map.hpp"

#include <vtkFreeTypeTools.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkStdString.h>
#include <vtkTextProperty.h>

namespace sg::detail {
namespace {

constexpr Rgb8 panel_colour{18, 18, 24};
constexpr float panel_opacity = 0.8f;
constexpr Rgb8 text_colour{240, 240, 240};
constexpr Rgb8 frame_colour{200, 200, 200};

/// A string rasterised by FreeType: coverage per pixel, rows from the top.
struct TextBitmap {
    int width = 0;
    int height = 0;
    std::vector<float> coverage;
};

TextBitmap rasterise(const std::string& text, int font_pixels)
{
    vtkNew<vtkTextProperty> property;
    property->SetFontFamilyToArial();
    property->SetFontSize(font_pixels);  // points at 72 dpi: one point per pixel
    property->SetColor(1.0, 1.0, 1.0);
    property->BoldOn();  // thin strokes vanish at small sizes over a busy picture
    property->SetJustificationToLeft();
    property->SetVerticalJustificationToBottom();
    vtkFreeTypeTools* freetype = vtkFreeTypeTools::GetInstance();
    // Power-of-two padding is for OpenGL textures; the legend wants the tight box.
    freetype->ScaleToPowerTwoOff();
    vtkNew<vtkImageData> rendered;
    int text_size[2] = {0, 0};
    TextBitmap bitmap;
    if (!freetype->RenderString(property.Get(), vtkStdString(text), 72, rendered.Get(),
                                text_size))
        return bitmap;
    int extent[6];
    rendered->GetExtent(extent);
    const int columns = extent[1] - extent[0] + 1;
    const int rows = extent[3] - extent[2] + 1;
    if (columns <= 0 || rows <= 0 || rendered->GetNumberOfScalarComponents() != 4) return bitmap;
    bitmap.width = std::min(columns, text_size[0]);
    bitmap.height = std::min(rows, text_size[1]);
    bitmap.coverage.resize(static_cast<std::size_t>(bitmap.width) *
                           static_cast<std::size_t>(bitmap.height));
    // The alpha channel carries the glyph coverage; VTK's rows start at the bottom.
    for (int y = 0; y < bitmap.height; ++y)
        for (int x = 0; x < bitmap.width; ++x) {
            const auto* pixel = static_cast<const unsigned char*>(
                rendered->GetScalarPointer(extent[0] + x, extent[2] + bitmap.height - 1 - y, 0));
            bitmap.coverage[static_cast<std::size_t>(y) * static_cast<std::size_t>(bitmap.width) +
                            static_cast<std::size_t>(x)] = static_cast<float>(pixel[3]) / 255.0f;
        }
    return bitmap;
}

std::uint8_t mix(std::uint8_t under, std::uint8_t over, float opacity)
{
    const float mixed =
        static_cast<float>(under) * (1.0f - opacity) + static_cast<float>(over) * opacity;
    return static_cast<std::uint8_t>(std::lround(mixed));
}

void blend(RgbImage& image, int x, int y, Rgb8 colour, float opacity)
{
    if (x < 0 || y < 0 || x >= image.width || y >= image.height || opacity <= 0.0f) return;
    const Rgb8 under = image.at(x, y);
    image.set(x, y, {mix(under.r, colour.r, opacity), mix(under.g, colour.g, opacity),
                     mix(under.b, colour.b, opacity)});
}

void fill(RgbImage& image, int x0, int y0, int width, int height, Rgb8 colour, float opacity)
{
    for (int y = y0; y < y0 + height; ++y)
        for (int x = x0; x < x0 + width; ++x) blend(image, x, y, colour, opacity);
}

void draw_text(RgbImage& image, const TextBitmap& text, int x0, int y0)
{
    for (int y = 0; y < text.height; ++y)
        for (int x = 0; x < text.width; ++x)
            blend(image, x0 + x, y0 + y, text_colour,
                  text.coverage[static_cast<std::size_t>(y) * static_cast<std::size_t>(text.width) +
                                static_cast<std::size_t>(x)]);
}

}  // namespace

void draw_heat_legend(RgbImage& image, HeatLegend& legend)
{
    legend.drawn = false;
    // Sizes follow the image height, so the legend reads the same at every resolution.
    const int font = std::clamp(static_cast<int>(std::lround(image.height / 40.0)), 9, 40);
    const int pad = std::max(4, font / 2);
    const int margin = font;
    const int bar_width = font;
    const int tick_length = std::max(3, font / 3);
    const int bar_height = std::max(2, static_cast<int>(std::lround(image.height * 0.4)));

    const TextBitmap title = rasterise(legend.title, font);
    std::vector<TextBitmap> labels;
    int label_width = 0;
    int label_height = 0;
    for (const std::string& label : legend.labels) {
        labels.push_back(rasterise(label, font));
        label_width = std::max(label_width, labels.back().width);
        label_height = std::max(label_height, labels.back().height);
    }
    if (title.width == 0 || label_width == 0) return;  // FreeType failed: no legend

    const int column_width = bar_width + tick_length + pad + label_width;
    const int panel_width = pad + std::max(title.width, column_width) + pad;
    // Labels are centred on their ticks, so half a label sticks out above and below the bar.
    const int panel_height =
        pad + title.height + pad + label_height / 2 + bar_height + label_height / 2 + pad;
    const int panel_x = image.width - margin - panel_width;
    const int panel_y = margin;
    if (panel_x < 0 || panel_width > image.width / 2 || panel_y + panel_height > image.height)
        return;

    fill(image, panel_x, panel_y, panel_width, panel_height, panel_colour, panel_opacity);
    draw_text(image, title, panel_x + pad, panel_y + pad);

    const int bar_x = panel_x + pad;
    const int bar_y = panel_y + pad + title.height + pad + label_height / 2;
    for (int row = 0; row < bar_height; ++row) {
        const double value =
            legend.scale_max * (1.0 - static_cast<double>(row) / (bar_height - 1));
        fill(image, bar_x, bar_y + row, bar_width, 1, heat_colour(value, legend.scale_max), 1.0f);
    }
    // A one-pixel frame around (not on) the bar, so the bar's own pixels are pure colour map.
    fill(image, bar_x - 1, bar_y - 1, bar_width + 2, 1, frame_colour, 1.0f);
    fill(image, bar_x - 1, bar_y + bar_height, bar_width + 2, 1, frame_colour, 1.0f);
    fill(image, bar_x - 1, bar_y, 1, bar_height, frame_colour, 1.0f);
    fill(image, bar_x + bar_width, bar_y, 1, bar_height, frame_colour, 1.0f);

    const auto tick_row = [&](std::size_t i) {
        const double t = std::clamp(legend.ticks[i] / legend.scale_max, 0.0, 1.0);
        return bar_y + static_cast<int>(std::lround((1.0 - t) * (bar_height - 1)));
    };
    // On a short bar the labels would overlap: the first and last are always drawn, the ones
    // between only where they keep a label's height from their neighbours.
    const std::size_t last = legend.ticks.size() - 1;
    int previous_row = -label_height;
    for (std::size_t i = 0; i <= last; ++i) {
        const int row = tick_row(i);
        const bool crowded = std::abs(row - previous_row) < label_height ||
                             std::abs(tick_row(last) - row) < label_height;
        if (i != 0 && i != last && crowded) continue;
        fill(image, bar_x + bar_width, row, tick_length, 1, frame_colour, 1.0f);
        draw_text(image, labels[i], bar_x + bar_width + tick_length + pad,
                  row - labels[i].height / 2);
        previous_row = row;
    }

    legend.drawn = true;
    legend.bar_x = bar_x;
    legend.bar_y = bar_y;
    legend.bar_width = bar_width;
    legend.bar_height = bar_height;
    legend.panel_x = panel_x;
    legend.panel_y = panel_y;
    legend.panel_width = panel_width;
    legend.panel_height = panel_height;
}

}  // namespace sg::detail
