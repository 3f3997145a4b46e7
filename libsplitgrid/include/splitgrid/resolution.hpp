#pragma once

#include <cstdint>

#include "splitgrid/build_config.hpp"

namespace sg {

/// Resolution (number of cells) of a node holding `triangle_count` triangles:
///   N(n) = round(min + (max - min) * (1 - exp(-(n / sigma)^2 / 2)))
/// clamped to [resolution_min, resolution_max]. The only place the formula lives.
[[nodiscard]] std::uint32_t node_resolution(const BuildConfig& config,
                                            std::size_t triangle_count) noexcept;

}  // namespace sg
