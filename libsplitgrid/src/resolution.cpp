#include "splitgrid/resolution.hpp"

#include <algorithm>
#include <cmath>

namespace sg {

std::uint32_t node_resolution(const BuildConfig& config, std::size_t triangle_count) noexcept
{
    const double x = static_cast<double>(triangle_count) / config.resolution_sigma;
    const double rise = 1.0 - std::exp(-0.5 * x * x);
    const double lo = config.resolution_min;
    const double hi = config.resolution_max;
    const double n = std::round(lo + (hi - lo) * rise);
    return static_cast<std::uint32_t>(std::clamp(n, lo, hi));
}

}  // namespace sg
