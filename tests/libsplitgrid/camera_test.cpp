#include <gtest/gtest.h>

#include <algorithm>
#include <array>
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

// Image coordinates of p in [-1, 1] x [-1, 1] when inside the image, computed in double from
// the camera's definition (camera.hpp), not with PrimaryRays.
struct ImagePoint {
    double x = 0.0;
    double y = 0.0;
    double depth = 0.0;
};
ImagePoint project(const Camera& camera, float aspect, Vec3f p)
{
    const auto d3 = [](Vec3f v) { return std::array<double, 3>{v.x, v.y, v.z}; };
    const auto sub = [](std::array<double, 3> a, std::array<double, 3> b) {
        return std::array<double, 3>{a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    };
    const auto dot3 = [](std::array<double, 3> a, std::array<double, 3> b) {
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    };
    const auto cross3 = [](std::array<double, 3> a, std::array<double, 3> b) {
        return std::array<double, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                     a[0] * b[1] - a[1] * b[0]};
    };
    const auto unit3 = [&](std::array<double, 3> a) {
        const double n = std::sqrt(dot3(a, a));
        return std::array<double, 3>{a[0] / n, a[1] / n, a[2] / n};
    };
    const auto f = unit3(sub(d3(camera.look_at), d3(camera.eye)));
    const auto r = unit3(cross3(f, d3(camera.up)));
    const auto u = cross3(r, f);
    const auto q = sub(d3(p), d3(camera.eye));
    const double half_y = std::tan(0.5 * camera.fov_y_degrees * std::numbers::pi / 180.0);
    const double depth = dot3(q, f);
    return {dot3(q, r) / depth / (half_y * aspect), dot3(q, u) / depth / half_y, depth};
}

/// How far the mesh's outline reaches towards the image edges: the smaller of its two
/// extents on the better-filled axis, as a share of the half-image (1 = touches the edge on
/// both sides). Fails the test if a corner is outside the image or behind the eye.
double fill_of(const Camera& camera, float aspect, const Mesh& mesh)
{
    double x_lo = 1e30, x_hi = -1e30, y_lo = 1e30, y_hi = -1e30;
    for (const Vec3f& p : mesh.vertices) {
        const ImagePoint q = project(camera, aspect, p);
        EXPECT_GT(q.depth, 0.0);
        EXPECT_LE(std::abs(q.x), 1.0);
        EXPECT_LE(std::abs(q.y), 1.0);
        x_lo = std::min(x_lo, q.x);
        x_hi = std::max(x_hi, q.x);
        y_lo = std::min(y_lo, q.y);
        y_hi = std::max(y_hi, q.y);
    }
    return std::max(std::min(-x_lo, x_hi), std::min(-y_lo, y_hi));
}

/// Elevation of the eye above the plane perpendicular to `up`, seen from look_at, in degrees.
double elevation_degrees(const Camera& camera, Vec3f up)
{
    return 90.0 - angle_degrees(camera.eye - camera.look_at, up);
}

TEST(Camera, FramedMeshFillsTheImageForEveryAspectAndUp)
{
    // A long bar and a small sphere off to one side: a scene whose bounding sphere is much
    // larger than its outline, which frame_box (sg-bench's camera) leaves mostly empty.
    Mesh mesh = test::uv_sphere({6.0f, 1.0f, 0.5f}, 0.7f, 8, 12);
    test::append(mesh, test::random_triangles(4, 300, {{-10, 0, -0.5f}, {10, 0.8f, 0.5f}}, 0.5f));
    for (const float aspect : {0.5f, 1.0f, 4.0f / 3.0f, 3.0f}) {
        for (const Vec3f up : {Vec3f{0, 1, 0}, Vec3f{0, 0, 1}, Vec3f{0, -1, 0}, Vec3f{1, 0, 0},
                               Vec3f{0.3f, -0.2f, 0.9f}}) {
            SCOPED_TRACE(testing::Message() << "aspect " << aspect << " up " << up.x << ","
                                            << up.y << "," << up.z);
            const Camera camera = frame_mesh(mesh.view(), aspect, 40.0f, up);
            EXPECT_NO_THROW(validate(camera));
            const double fill = fill_of(camera, aspect, mesh);
            EXPECT_GT(fill, 0.94) << "the outline must reach the image edges on both sides";
            EXPECT_LT(fill, 0.96) << "and keep a 5% margin";
        }
        const Camera old = frame_box(bounds(mesh.view()), aspect, 40.0f);
        EXPECT_LT(fill_of(old, aspect, mesh), 0.8) << "premise: the sphere framing wastes room";
    }
}

TEST(Camera, FramingLooksFromTheSameElevationAboveTheGroundOfEveryUp)
{
    const Mesh mesh = test::uv_sphere({1.0f, 2.0f, 3.0f}, 1.0f, 10, 10);
    // (1, 0.6, 1.4) is 19.27 degrees above the y = 0 plane.
    const double expected = std::asin(0.6 / std::sqrt(1.0 + 0.36 + 1.96)) * 180.0 /
                            std::numbers::pi;
    for (const Vec3f up : {Vec3f{0, 1, 0}, Vec3f{0, 0, 1}, Vec3f{0, -1, 0}, Vec3f{-1, 0, 0},
                           Vec3f{1, 0.6f, 1.4f}, Vec3f{0, 0, 5}}) {
        SCOPED_TRACE(testing::Message() << "up " << up.x << "," << up.y << "," << up.z);
        const Camera camera = frame_mesh(mesh.view(), 1.0f, 45.0f, up);
        EXPECT_EQ(camera.up, up) << "the image's up is the given up";
        EXPECT_NEAR(elevation_degrees(camera, up), expected, 0.01);
    }
    // With z up, the rotation taking +y to +z takes (1, 0.6, 1.4) to (1, -1.4, 0.6).
    // (Compared by components: acos is too coarse near 0 for a float vector.)
    const auto expect_direction = [](Vec3f actual, Vec3f expected_direction) {
        const Vec3f e = normalize(expected_direction);
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(actual[a], e[a], 1e-6f) << "axis " << a;
    };
    expect_direction(framing_direction({0, 0, 1}), {1.0f, -1.4f, 0.6f});
    // With +y up it is frame_box's direction, so the default view keeps its angle.
    expect_direction(framing_direction({0, 1, 0}), {1.0f, 0.6f, 1.4f});
    // With -y up, the half turn about x.
    expect_direction(framing_direction({0, -1, 0}), {1.0f, -0.6f, -1.4f});
}

TEST(Camera, FramingRefusesAnUpItCannotUse)
{
    const Mesh mesh = test::uv_sphere({0, 0, 0}, 1.0f, 6, 6);
    EXPECT_THROW((void)frame_mesh(mesh.view(), 1.0f, 45.0f, {0, 0, 0}), ConfigError);
    EXPECT_THROW((void)frame_mesh(mesh.view(), 1.0f, 45.0f, {NAN, 1, 0}), ConfigError);
    EXPECT_THROW((void)frame_mesh(mesh.view(), 1.0f, 180.0f, {0, 1, 0}), ConfigError);
    // No triangles: the unit cube is framed.
    const Camera empty = frame_mesh(MeshView{}, 1.0f, 45.0f, {0, 1, 0});
    EXPECT_NO_THROW(validate(empty));
    EXPECT_LT(length(empty.look_at - Vec3f{0.5f, 0.5f, 0.5f}), 0.5f);
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
