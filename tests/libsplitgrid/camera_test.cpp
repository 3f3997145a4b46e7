#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "splitgrid/camera.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/ray_offset.hpp"
#include "splitgrid/sampling.hpp"
#include "splitgrid/traverse.hpp"
#include "support/random_scene.hpp"

namespace sg {
namespace {

// Angle between two directions, in degrees, computed in double.
double angle_degrees(Vec3f a, Vec3f b)
{
    const double d = (double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z) /
                     (std::sqrt(double(dot(a, a))) * std::sqrt(double(dot(b, b))));
    return std::acos(std::clamp(d, -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

TEST(Camera, FramedBoxFitsTheFieldOfViewForEveryAspect)
{
    const Aabb box{{-3.0f, 10.0f, 100.0f}, {5.0f, 11.0f, 140.0f}};
    for (const float aspect : {0.5f, 1.0f, 4.0f / 3.0f, 3.0f}) {
        const Camera camera = frame_box(box, aspect, 40.0f);
        const Vec3f forward = camera.look_at - camera.eye;
        const double half_y = 20.0;
        const double half_x = std::atan(std::tan(half_y * std::numbers::pi / 180.0) * aspect) *
                              180.0 / std::numbers::pi;
        for (int corner = 0; corner < 8; ++corner) {
            const Vec3f p{(corner & 1) ? box.upper.x : box.lower.x,
                          (corner & 2) ? box.upper.y : box.lower.y,
                          (corner & 4) ? box.upper.z : box.lower.z};
            // Inside the cone of the narrower half-angle is inside the image.
            EXPECT_LT(angle_degrees(forward, p - camera.eye), std::min(half_x, half_y))
                << "aspect " << aspect << " corner " << corner;
        }
    }
}

TEST(Camera, CentreAndCornerRaysPointWhereTheFieldOfViewSays)
{
    const Camera camera{{0.0f, 0.0f, 10.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 60.0f};
    const PrimaryRays rays(camera, 200, 100);
    const Ray centre = rays.ray(100.0f, 50.0f);
    EXPECT_NEAR(centre.direction.z, -1.0f, 1e-6f);
    // Top edge, middle column: 30 degrees above the axis, and "up" is +y.
    const Ray top = rays.ray(100.0f, 0.0f);
    EXPECT_NEAR(angle_degrees(top.direction, {0.0f, 0.0f, -1.0f}), 30.0, 1e-4);
    EXPECT_GT(top.direction.y, 0.0f);
    // Right edge, middle row: x grows to the right when looking down -z with +y up.
    const Ray right = rays.ray(200.0f, 50.0f);
    EXPECT_GT(right.direction.x, 0.0f);
}

TEST(Camera, RefusesCamerasThatCannotFormAnImage)
{
    EXPECT_THROW(validate(Camera{{0, 0, 0}, {0, 0, 0}, {0, 1, 0}, 45}), ConfigError);
    EXPECT_THROW(validate(Camera{{0, 0, 1}, {0, 0, 0}, {0, 0, 1}, 45}), ConfigError);
    EXPECT_THROW(validate(Camera{{0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 180}), ConfigError);
    EXPECT_THROW(validate(Camera{{0, 0, NAN}, {0, 0, 0}, {0, 1, 0}, 45}), ConfigError);
    EXPECT_THROW(PrimaryRays(Camera{}, 0, 10), ConfigError);
}

TEST(Sampling, CosineHemisphereStaysOnTheNormalsSideAndIsUnit)
{
    Rng rng(7);
    for (int i = 0; i < 10000; ++i) {
        const Vec3f n = uniform_sphere(rng.next_float(), rng.next_float());
        const Vec3f d = cosine_hemisphere(n, rng.next_float(), rng.next_float());
        EXPECT_NEAR(length(d), 1.0f, 1e-5f);
        EXPECT_GE(dot(d, n), -1e-6f);
    }
}

TEST(Sampling, CosineHemisphereHasTheCosineMean)
{
    // E[cos theta] under density cos/pi is 2/3.
    Rng rng(11);
    const Vec3f n = normalize(Vec3f{0.3f, -0.4f, 0.8f});
    double sum = 0.0;
    constexpr int count = 200000;
    for (int i = 0; i < count; ++i) sum += dot(cosine_hemisphere(n, rng.next_float(), rng.next_float()), n);
    EXPECT_NEAR(sum / count, 2.0 / 3.0, 0.005);
}

TEST(RayOffset, SpawnedRaysNeverHitTheirSourceTriangle)
{
    // A closed sphere far from the origin: every secondary ray leaves its hit point either
    // outwards or inwards; neither may report its own triangle again (brute-force oracle).
    Mesh sphere = test::uv_sphere({148376.0f, 1234.0f, -223423.0f}, 50.0f, 64, 32);
    const MeshView mesh = sphere.view();
    Rng rng(3);
    int spawned = 0;
    for (int i = 0; i < 8000; ++i) {
        const Vec3f target = sphere.vertices[rng.next_u32() % sphere.vertices.size()];
        const Vec3f origin = target + uniform_sphere(rng.next_float(), rng.next_float()) * 200.0f;
        const Hit hit = intersect_brute_force(mesh, {origin, target - origin});
        if (!hit.is_hit()) continue;
        const SurfacePoint at = surface_point(mesh, hit);
        const Vec3f d = uniform_sphere(rng.next_float(), rng.next_float());
        const Hit again = intersect_brute_force(mesh, spawn_ray(at, d));
        ++spawned;
        EXPECT_NE(again.triangle, hit.triangle) << "ray " << i;
    }
    EXPECT_GT(spawned, 6000);
}

}  // namespace
}  // namespace sg
