#pragma once

#include <boost/multiprecision/cpp_int.hpp>

#include <cmath>

namespace sg::test {

/// A finite float as an exact integer: its value times 2^149 (the smallest denormal is
/// 2^-149), for predicates decided in exact arithmetic (Boost.Multiprecision, headers only).
inline boost::multiprecision::cpp_int scaled(float f)
{
    int exponent = 0;
    const float mantissa = std::frexp(f, &exponent);
    boost::multiprecision::cpp_int v = static_cast<long long>(std::ldexp(mantissa, 24));
    const int shift = exponent - 24 + 149;
    if (shift >= 0)
        v <<= shift;
    else
        v >>= -shift;  // only zero bits go: a denormal's mantissa ends in zeros
    return v;
}

}  // namespace sg::test
