#pragma once

#include <cmath>
#include <cstddef>
#include <type_traits>

namespace sg {

/// Three packed single-precision floats: a point or a direction in scene space.
/// 12 bytes, no padding, so an array of Vec3f is the vertex array stored in a .sg file.
struct Vec3f {
    float x = 0.0f;
    float y = 0.0f;
    float z = 0.0f;

    [[nodiscard]] constexpr float operator[](int axis) const noexcept
    {
        return axis == 0 ? x : (axis == 1 ? y : z);
    }
    [[nodiscard]] constexpr float& operator[](int axis) noexcept
    {
        return axis == 0 ? x : (axis == 1 ? y : z);
    }
    friend constexpr bool operator==(const Vec3f&, const Vec3f&) = default;
};
static_assert(sizeof(Vec3f) == 12 && alignof(Vec3f) == 4,
              "Vec3f must be three packed floats: it is written to .sg files as is");
static_assert(std::is_trivially_copyable_v<Vec3f>, "Vec3f is stored as raw bytes");

[[nodiscard]] constexpr Vec3f operator+(Vec3f a, Vec3f b) noexcept
{
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
[[nodiscard]] constexpr Vec3f operator-(Vec3f a, Vec3f b) noexcept
{
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
[[nodiscard]] constexpr Vec3f operator*(Vec3f a, float s) noexcept
{
    return {a.x * s, a.y * s, a.z * s};
}
[[nodiscard]] constexpr Vec3f operator*(float s, Vec3f a) noexcept { return a * s; }
[[nodiscard]] constexpr float dot(Vec3f a, Vec3f b) noexcept
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
[[nodiscard]] constexpr Vec3f cross(Vec3f a, Vec3f b) noexcept
{
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
[[nodiscard]] inline float length(Vec3f a) noexcept { return std::sqrt(dot(a, a)); }
[[nodiscard]] inline Vec3f normalize(Vec3f a) noexcept
{
    const float len = length(a);
    return len > 0.0f ? a * (1.0f / len) : a;
}
[[nodiscard]] inline bool is_finite(Vec3f a) noexcept
{
    return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

/// Double-precision point, used where the builder and the checker need headroom
/// (clipping, overlap tests), never stored.
struct Vec3d {
    double x = 0.0;
    double y = 0.0;
    double z = 0.0;

    constexpr Vec3d() = default;
    constexpr Vec3d(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
    constexpr explicit Vec3d(Vec3f v) : x(v.x), y(v.y), z(v.z) {}

    [[nodiscard]] constexpr double operator[](int axis) const noexcept
    {
        return axis == 0 ? x : (axis == 1 ? y : z);
    }
    [[nodiscard]] constexpr double& operator[](int axis) noexcept
    {
        return axis == 0 ? x : (axis == 1 ? y : z);
    }
};

[[nodiscard]] constexpr Vec3d operator-(Vec3d a, Vec3d b) noexcept
{
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
[[nodiscard]] constexpr double dot(Vec3d a, Vec3d b) noexcept
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
[[nodiscard]] constexpr Vec3d cross(Vec3d a, Vec3d b) noexcept
{
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// Component Axis of v (a Vec3f or Vec3d, const or not), chosen at compile time: operator[]
/// chooses by a branch, which loops over many points pay for at each access.
template <int Axis, class V>
[[nodiscard]] constexpr auto& component(V& v) noexcept
{
    static_assert(Axis >= 0 && Axis < 3);
    if constexpr (Axis == 0) return v.x;
    else if constexpr (Axis == 1) return v.y;
    else return v.z;
}

}  // namespace sg
