#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "splitgrid/vec3.hpp"

namespace sg {

/// Small, fast, seedable random numbers for ray generation (PCG-XSH-RR 64/32, O'Neill 2014).
/// Each pixel, path or test case seeds its own stream, so results do not depend on how the
/// work is split over threads.
class Rng {
public:
    explicit constexpr Rng(std::uint64_t seed, std::uint64_t stream = 0) noexcept
        : increment_((stream << 1u) | 1u)
    {
        next_u32();
        state_ += seed;
        next_u32();
    }

    constexpr std::uint32_t next_u32() noexcept
    {
        const std::uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + increment_;
        const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
        const auto rotation = static_cast<std::uint32_t>(old >> 59u);
        return (xorshifted >> rotation) | (xorshifted << ((32u - rotation) & 31u));
    }

    /// Uniform in [0, 1): the top 24 bits, so every value is exactly representable.
    constexpr float next_float() noexcept
    {
        return static_cast<float>(next_u32() >> 8u) * 0x1.0p-24f;
    }

private:
    std::uint64_t state_ = 0;
    std::uint64_t increment_;
};

/// Two unit vectors t, b that complete the unit vector n to a right-handed orthonormal
/// basis (t, b, n), without a branch on a chosen axis and without a singularity
/// (Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 2017).
inline void orthonormal_basis(Vec3f n, Vec3f& t, Vec3f& b) noexcept
{
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float c = n.x * n.y * a;
    t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
}

/// A direction on the hemisphere around the unit normal n, with density cos(theta)/pi
/// (the importance sampling of a diffuse surface), from two uniform numbers in [0, 1).
inline Vec3f cosine_hemisphere(Vec3f n, float u1, float u2) noexcept
{
    const float r = std::sqrt(u1);
    const float phi = 2.0f * std::numbers::pi_v<float> * u2;
    Vec3f t;
    Vec3f b;
    orthonormal_basis(n, t, b);
    const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
    return normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * z);
}

/// A direction uniformly distributed on the unit sphere.
inline Vec3f uniform_sphere(float u1, float u2) noexcept
{
    const float z = 1.0f - 2.0f * u1;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = 2.0f * std::numbers::pi_v<float> * u2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace sg
