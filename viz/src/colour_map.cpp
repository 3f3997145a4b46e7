#include "colour_map.hpp"

#include <algorithm>
#include <cmath>

#include <vtkColorTransferFunction.h>
#include <vtkNew.h>

namespace sg::detail {
namespace {

std::array<Rgb8, heat_colour_count> build_heat_colour_map()
{
    struct ControlPoint {
        double at, r, g, b;
    };
    // sRGB control points, picked by hand for rising CIELAB lightness and distinct hues.
    constexpr ControlPoint points[] = {
        {0.00, 0.08, 0.04, 0.22},
        {0.25, 0.42, 0.08, 0.52},
        {0.50, 0.82, 0.22, 0.36},
        {0.75, 0.98, 0.58, 0.16},
        {1.00, 1.00, 0.96, 0.66},
    };
    vtkNew<vtkColorTransferFunction> function;
    function->SetColorSpaceToLab();
    for (const ControlPoint& p : points) function->AddRGBPoint(p.at, p.r, p.g, p.b);

    std::array<Rgb8, heat_colour_count> map{};
    const auto to_byte = [](double c) {
        return static_cast<std::uint8_t>(std::lround(std::clamp(c, 0.0, 1.0) * 255.0));
    };
    for (int i = 0; i < heat_colour_count; ++i) {
        double rgb[3];
        function->GetColor(static_cast<double>(i) / (heat_colour_count - 1), rgb);
        map[static_cast<std::size_t>(i)] = {to_byte(rgb[0]), to_byte(rgb[1]), to_byte(rgb[2])};
    }
    return map;
}

}  // namespace

const std::array<Rgb8, heat_colour_count>& heat_colour_map()
{
    static const std::array<Rgb8, heat_colour_count> map = build_heat_colour_map();
    return map;
}

Rgb8 heat_colour(double value, double scale_max) noexcept
{
    const double t = std::clamp(value / scale_max, 0.0, 1.0);
    const auto index = static_cast<std::size_t>(std::lround(t * (heat_colour_count - 1)));
    return heat_colour_map()[index];
}

}  // namespace sg::detail
