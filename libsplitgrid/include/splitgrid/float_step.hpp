#pragma once

#include <bit>
#include <cstdint>
#include <limits>

namespace sg {

/// The float next to f towards -infinity: std::nextafter(f, -infinity) for every f, inline.
/// The builders round every clipped bound outward with it, where libm's nextafterf would be
/// an out-of-line call each time. Zero is recognised by its bits, so a floating-point mode
/// that flushes denormals to zero cannot mistake a denormal for it.
[[nodiscard]] inline float next_float_down(float f) noexcept
{
    const auto bits = std::bit_cast<std::uint32_t>(f);
    const std::uint32_t magnitude = bits & 0x7FFFFFFFu;
    if (magnitude > 0x7F800000u || bits == 0xFF800000u) return f;  // NaN, -infinity
    if (magnitude == 0) return -std::numeric_limits<float>::denorm_min();
    return std::bit_cast<float>((bits >> 31) == 0 ? bits - 1 : bits + 1);
}

/// The float next to f towards +infinity: std::nextafter(f, +infinity) for every f, inline.
[[nodiscard]] inline float next_float_up(float f) noexcept
{
    const auto bits = std::bit_cast<std::uint32_t>(f);
    const std::uint32_t magnitude = bits & 0x7FFFFFFFu;
    if (magnitude > 0x7F800000u || bits == 0x7F800000u) return f;  // NaN, +infinity
    if (magnitude == 0) return std::numeric_limits<float>::denorm_min();
    return std::bit_cast<float>((bits >> 31) == 0 ? bits + 1 : bits - 1);
}

/// The largest float not above x (x not NaN). The conversion rounds to nearest, so a float on
/// the wrong side of x is one step away (an infinity where x lies beyond the largest float,
/// which steps back to it).
///
/// Without a branch: whether the conversion landed on the wrong side is a coin toss for
/// clipped coordinates, which the builders round six at a time. The step is one unit of the
/// bits, down for a positive f (+infinity included) and up for a negative one; a zero never
/// needs it here (x < 0 converts to -0 at worst, whose step gives -denorm_min).
[[nodiscard]] inline float float_not_above(double x) noexcept
{
    const float f = static_cast<float>(x);
    const auto bits = std::bit_cast<std::uint32_t>(f);
    const std::uint32_t down = (bits >> 31) != 0 ? 1u : 0xFFFFFFFFu;
    const std::uint32_t step = static_cast<double>(f) > x ? down : 0u;
    return std::bit_cast<float>(bits + step);
}

/// The smallest float not below x (x not NaN), without a branch as float_not_above.
[[nodiscard]] inline float float_not_below(double x) noexcept
{
    const float f = static_cast<float>(x);
    const auto bits = std::bit_cast<std::uint32_t>(f);
    const std::uint32_t up = (bits >> 31) != 0 ? 0xFFFFFFFFu : 1u;
    const std::uint32_t step = static_cast<double>(f) < x ? up : 0u;
    return std::bit_cast<float>(bits + step);
}

}  // namespace sg
