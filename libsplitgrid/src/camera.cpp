#include "splitgrid/camera.hpp"

#include <cmath>
#include <algorithm>
#include <limits>
#include <numbers>

#include "splitgrid/error.hpp"

namespace sg {

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
