#include "heat_scale.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <string>

namespace sg::detail {
namespace {

/// Intervals the tick step aims at: about four labelled intervals fit a bar a third of the
/// image tall with room for the labels.
constexpr double target_intervals = 4.0;
/// Share of pixels allowed above an automatic scale (the 99.5th percentile).
constexpr double automatic_percentile = 0.995;

/// The smallest of 1, 2, 5 times a power of ten that is at least `raw` (> 0).
double nice_step(double raw)
{
    const double power = std::pow(10.0, std::floor(std::log10(raw)));
    for (const double m : {1.0, 2.0, 5.0, 10.0})
        if (m * power >= raw * (1.0 - 1e-12)) return m * power;
    return 10.0 * power;
}

std::string format_number(double value, int decimals)
{
    std::array<char, 64> text{};
    const auto result =
        decimals >= 0
            ? std::to_chars(text.data(), text.data() + text.size(), value,
                            std::chars_format::fixed, decimals)
            : std::to_chars(text.data(), text.data() + text.size(), value);
    return std::string(text.data(), result.ptr);
}

}  // namespace

HeatLegend make_heat_scale(const std::vector<float>& values, double heat_max, RenderMode mode)
{
    HeatLegend legend;
    legend.title = mode == RenderMode::heat_cells ? "cells visited per ray"
                                                  : "triangles tested per ray";
    for (const float v : values) legend.max_value = std::max(legend.max_value, double(v));

    legend.automatic = !(heat_max > 0.0);
    double step = 1.0;
    if (legend.automatic) {
        double top = 0.0;
        if (!values.empty()) {
            std::vector<float> sorted = values;
            const auto rank = static_cast<std::size_t>(
                std::floor(automatic_percentile * static_cast<double>(sorted.size() - 1)));
            std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(rank),
                             sorted.end());
            top = sorted[rank];
        }
        if (!(top > 0.0)) top = 1.0;
        step = nice_step(top / target_intervals);
        legend.scale_max = std::ceil(top / step - 1e-9) * step;
    } else {
        legend.scale_max = heat_max;
        step = nice_step(heat_max / target_intervals);
    }

    std::size_t clamped = 0;
    for (const float v : values)
        if (double(v) > legend.scale_max) ++clamped;
    legend.clamped_fraction =
        values.empty() ? 0.0 : static_cast<double>(clamped) / static_cast<double>(values.size());

    // Ticks at multiples of the step, and the top of the scale itself; a multiple closer
    // than a third of a step to the top is dropped so that the labels do not overlap.
    const int decimals = step >= 1.0 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
    for (int k = 0; k * step < legend.scale_max - step / 3.0; ++k) {
        legend.ticks.push_back(k * step);
        legend.labels.push_back(format_number(k * step, decimals));
    }
    legend.ticks.push_back(legend.scale_max);
    const double steps_to_top = legend.scale_max / step;
    const bool top_on_step = std::fabs(steps_to_top - std::round(steps_to_top)) < 1e-9;
    std::string top_label = format_number(legend.scale_max, top_on_step ? decimals : -1);
    legend.labels.push_back(clamped != 0 ? top_label + "+" : top_label);
    return legend;
}

}  // namespace sg::detail
