#include "splitgrid/camera.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "splitgrid/error.hpp"

namespace sg {
namespace {

// Framing works in double: a scene may span nearly the whole float range.
Vec3d to_double(Vec3f v) { return Vec3d(v); }
Vec3f to_float(const Vec3d& v)
{
    return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}
Vec3d scaled(const Vec3d& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
Vec3d plus(const Vec3d& a, const Vec3d& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3d unit(const Vec3d& a) { return scaled(a, 1.0 / std::sqrt(dot(a, a))); }

/// The eye's direction from the scene when +y is up (a three-quarter view from above).
constexpr Vec3d y_up_view{1.0, 0.6, 1.4};

/// Share of the image's half-width (or half-height) that frame_mesh fills.
constexpr double frame_fill = 0.95;

}  // namespace

void validate(const Camera& camera)
{
    if (!is_finite(camera.eye) || !is_finite(camera.look_at) || !is_finite(camera.up)) {
        throw ConfigError("camera: eye, look-at and up must be finite");
    }
    const Vec3f view = camera.look_at - camera.eye;
    if (!(dot(view, view) > 0.0f)) {
        throw ConfigError("camera: eye and look-at must differ");
    }
    const Vec3f side = cross(normalize(view), normalize(camera.up));
    if (!(dot(side, side) > 1e-12f)) {
        throw ConfigError("camera: up must not be zero or parallel to the view direction");
    }
    if (!(camera.fov_y_degrees > 0.0f && camera.fov_y_degrees < 180.0f)) {
        throw ConfigError("camera: the field of view must lie strictly between 0 and 180 degrees");
    }
}

Camera frame_box(const Aabb& box, float aspect, float fov_y_degrees)
{
    Aabb frame = box;
    if (frame.is_empty()) frame = Aabb{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}};
    // Centre and radius in double: the box may span nearly the whole float range.
    const double cx = 0.5 * (double(frame.lower.x) + frame.upper.x);
    const double cy = 0.5 * (double(frame.lower.y) + frame.upper.y);
    const double cz = 0.5 * (double(frame.lower.z) + frame.upper.z);
    const double dx = double(frame.upper.x) - frame.lower.x;
    const double dy = double(frame.upper.y) - frame.lower.y;
    const double dz = double(frame.upper.z) - frame.lower.z;
    double radius = 0.5 * std::sqrt(dx * dx + dy * dy + dz * dz);
    if (!(radius > 0.0)) radius = std::max(1.0, std::fabs(cx) + std::fabs(cy) + std::fabs(cz)) * 1e-3;

    const double half_fov_y = 0.5 * double(fov_y_degrees) * std::numbers::pi / 180.0;
    const double half_fov_x = std::atan(std::tan(half_fov_y) * double(aspect > 0.0f ? aspect : 1.0f));
    const double half_fov = std::min(half_fov_y, half_fov_x);
    // A sphere of radius r fills a cone of half-angle a when seen from distance r / sin(a);
    // 5% more leaves a margin around the silhouette.
    const double distance = 1.05 * radius / std::sin(half_fov);

    const Vec3f direction = normalize(Vec3f{1.0f, 0.6f, 1.4f});
    Camera camera;
    camera.look_at = {float(cx), float(cy), float(cz)};
    camera.eye = {float(cx + distance * direction.x), float(cy + distance * direction.y),
                  float(cz + distance * direction.z)};
    camera.up = {0.0f, 1.0f, 0.0f};
    camera.fov_y_degrees = fov_y_degrees;
    return camera;
}

Vec3f framing_direction(Vec3f up)
{
    if (!is_finite(up) || !(dot(up, up) > 0.0f))
        throw ConfigError("camera: up must be finite and not zero");
    const Vec3d u = unit(to_double(up));
    const Vec3d v = unit(y_up_view);
    // Rodrigues' rotation about k = y x u, |k| = sin(angle), written without normalising k:
    // R v = v cos + k x v + k (k . v) / (1 + cos). At u = -y the axis is undefined: the half
    // turn about x is taken, which keeps x and flips y and z.
    const double cosine = u[1];
    if (1.0 + cosine < 1e-9) return to_float({v[0], -v[1], -v[2]});
    const Vec3d k{u[2], 0.0, -u[0]};
    return to_float(unit(plus(plus(scaled(v, cosine), cross(k, v)),
                              scaled(k, dot(k, v) / (1.0 + cosine)))));
}

Camera frame_mesh(const MeshView& mesh, float aspect, float fov_y_degrees, Vec3f up)
{
    if (!(fov_y_degrees > 0.0f && fov_y_degrees < 180.0f))
        throw ConfigError("camera: the field of view must lie strictly between 0 and 180 degrees");
    const Vec3d forward = scaled(to_double(framing_direction(up)), -1.0);
    const Vec3d right = unit(cross(forward, to_double(up)));
    const Vec3d image_up = cross(right, forward);

    Aabb box = bounds(mesh);
    const bool has_triangles = !box.is_empty();
    if (!has_triangles) box = Aabb{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}};
    const Vec3d lower = to_double(box.lower);
    const Vec3d upper = to_double(box.upper);
    const Vec3d centre = scaled(plus(lower, upper), 0.5);

    // Half-extents of the filled part of the image plane at distance 1.
    const double safe_aspect = std::isfinite(aspect) && aspect > 0.0f ? double(aspect) : 1.0;
    const double half_y =
        frame_fill * std::tan(0.5 * double(fov_y_degrees) * std::numbers::pi / 180.0);
    const double half_x = half_y * safe_aspect;

    // A point at (X, Y, Z) in the basis (right, image_up, forward) around `centre` seen from
    // the eye centre + a right + b image_up - D forward lies in the filled part when
    // |X - a| <= half_x (Z + D) and |Y - b| <= half_y (Z + D). For the x constraints alone the
    // smallest D is max(x_plus - a / half_x, x_minus + a / half_x) with x_plus = max(X / half_x
    // - Z), x_minus = max(-X / half_x - Z); it is least, (x_plus + x_minus) / 2, where both
    // are equal: the outline is centred and touches both sides. Likewise for y; the larger
    // of the two distances frames the scene, so its axis is filled and the other fits.
    double x_plus = -std::numeric_limits<double>::infinity();
    double x_minus = x_plus, y_plus = x_plus, y_minus = x_plus, nearest = x_plus;
    const auto add = [&](const Vec3d& p) {
        const Vec3d d{p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]};
        const double x = dot(d, right), y = dot(d, image_up), z = dot(d, forward);
        x_plus = std::max(x_plus, x / half_x - z);
        x_minus = std::max(x_minus, -x / half_x - z);
        y_plus = std::max(y_plus, y / half_y - z);
        y_minus = std::max(y_minus, -y / half_y - z);
        nearest = std::max(nearest, -z);
    };
    if (has_triangles) {
        for (const Triangle& t : mesh.triangles)
            for (const std::uint32_t i : t.v) add(to_double(mesh.vertices[i]));
    } else {
        for (int corner = 0; corner < 8; ++corner)
            add({(corner & 1) ? upper[0] : lower[0], (corner & 2) ? upper[1] : lower[1],
                 (corner & 4) ? upper[2] : lower[2]});
    }
    const double a = 0.5 * (x_plus - x_minus) * half_x;
    const double b = 0.5 * (y_plus - y_minus) * half_y;
    double distance = std::max(0.5 * (x_plus + x_minus), 0.5 * (y_plus + y_minus));
    // Keep every point in front of the eye even for a scene of one point.
    const Vec3d diagonal{upper[0] - lower[0], upper[1] - lower[1], upper[2] - lower[2]};
    double size = std::sqrt(dot(diagonal, diagonal));
    if (!(size > 0.0))
        size = std::max(1.0, std::fabs(centre[0]) + std::fabs(centre[1]) + std::fabs(centre[2])) *
               1e-3;
    distance = std::max(distance, nearest + 1e-3 * size);

    const Vec3d look_at = plus(centre, plus(scaled(right, a), scaled(image_up, b)));
    Camera camera;
    camera.look_at = to_float(look_at);
    camera.eye = to_float(plus(look_at, scaled(forward, -distance)));
    camera.up = up;
    camera.fov_y_degrees = fov_y_degrees;
    return camera;
}

PrimaryRays::PrimaryRays(const Camera& camera, int width, int height)
    : width_(width), height_(height)
{
    validate(camera);
    if (width <= 0 || height <= 0) throw ConfigError("camera: image width and height must be positive");
    eye_ = camera.eye;
    forward_ = normalize(camera.look_at - camera.eye);
    const Vec3f right = normalize(cross(forward_, camera.up));
    const Vec3f up = cross(right, forward_);
    const float half_height =
        std::tan(0.5f * camera.fov_y_degrees * std::numbers::pi_v<float> / 180.0f);
    const float half_width = half_height * static_cast<float>(width) / static_cast<float>(height);
    right_ = right * half_width;
    down_ = up * -half_height;
}

Ray PrimaryRays::ray(float x, float y) const noexcept
{
    const float sx = 2.0f * x / static_cast<float>(width_) - 1.0f;
    const float sy = 2.0f * y / static_cast<float>(height_) - 1.0f;
    return {eye_, normalize(forward_ + right_ * sx + down_ * sy), 0.0f,
            std::numeric_limits<float>::infinity()};
}

}  // namespace sg
