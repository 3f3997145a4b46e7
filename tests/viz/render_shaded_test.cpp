// The shaded mode against an independent oracle: for every pixel of a PNG read back with
// VTK's reader, the brute-force closest hit of the pixel's centre ray (over all triangles,
// no grid) decides background or surface, and the documented lighting formula, evaluated
// here on the brute-force hit, gives the grey value.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <vector>

#include "apps/app_test_support.hpp"
#include "render_test_support.hpp"
#include "splitgrid/camera.hpp"
#include "splitgrid/ray_triangle.hpp"
#include "splitgrid/traverse.hpp"
#include "splitgrid/viz/render.hpp"

#include <gtest/gtest.h>

namespace sg::test {
namespace {

/// The shaded mode's formula (render.hpp, ShadedLighting), written out again from the
/// documentation for one triangle.
int expected_grey(const MeshView& mesh, std::uint32_t triangle, const Ray& ray,
                  const Camera& camera)
{
    const Vec3f a = mesh.vertex(triangle, 0);
    const Vec3f b = mesh.vertex(triangle, 1);
    const Vec3f c = mesh.vertex(triangle, 2);
    Vec3f n = normalize(cross(b - a, c - a));
    const Vec3f d = normalize(ray.direction);
    if (dot(n, d) > 0.0f) n = n * -1.0f;
    const Vec3f f = normalize(camera.look_at - camera.eye);
    const Vec3f r = normalize(cross(f, camera.up));
    const Vec3f u = cross(r, f);
    const Vec3f light = normalize(u * 0.7f - r * 0.4f - f * 0.6f);
    const double value = 0.12 + 0.58 * std::max(0.0f, -dot(n, d)) +
                         0.30 * std::max(0.0f, dot(n, light));
    return static_cast<int>(std::lround(std::clamp(value, 0.0, 1.0) * 255.0));
}

/// Every triangle the ray hits at exactly distance t (usually one; two where the ray meets
/// a shared edge, and then either may be the closest hit).
std::vector<std::uint32_t> triangles_at(const MeshView& mesh, const Ray& ray, float t)
{
    std::vector<std::uint32_t> found;
    const WatertightRay w(ray);
    for (std::uint32_t i = 0; i < mesh.triangle_count(); ++i) {
        float ti = 0.0f, u = 0.0f, v = 0.0f;
        if (intersect_triangle(w, mesh.vertex(i, 0), mesh.vertex(i, 1), mesh.vertex(i, 2),
                               ray.t_min, ray.t_max, ti, u, v) &&
            ti == t)
            found.push_back(i);
    }
    return found;
}

TEST(RenderShaded, EveryPixelMatchesBruteForceHitAndLightingFormula)
{
    const Scene scene = sphere_floor_scene();
    const MeshView mesh = scene.mesh.view();
    RenderSettings settings;
    settings.width = 160;
    settings.height = 120;
    // Closer than the automatic framing and from higher up, so the floor fills much of the view.
    settings.camera = Camera{{10.0f, 8.0f, 12.0f}, {4.0f, 1.0f, 4.0f}, {0.0f, 1.0f, 0.0f}, 45.0f};
    const RenderResult result = render(scene.grid, mesh, settings);

    ScratchDir scratch;
    write_image(scratch / "shaded.png", result.image);
    const RgbImage image = read_png(scratch / "shaded.png");
    ASSERT_EQ(image.width, 160);
    ASSERT_EQ(image.height, 120);

    const PrimaryRays rays(settings.camera, settings.width, settings.height);
    std::size_t hits = 0;
    std::size_t wrong = 0;
    std::ostringstream first;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const Ray ray = rays.ray(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
            const Hit expected = intersect_brute_force(mesh, ray);
            const Rgb8 got = image.at(x, y);
            bool ok = false;
            if (!expected.is_hit()) {
                ok = got == render_background;
            } else {
                ++hits;
                for (const std::uint32_t triangle : triangles_at(mesh, ray, expected.t)) {
                    const int grey = expected_grey(mesh, triangle, ray, settings.camera);
                    ok = ok || (got.r == got.g && got.g == got.b && std::abs(got.r - grey) <= 1);
                }
            }
            if (!ok && wrong++ == 0)
                first << "pixel (" << x << ", " << y << "): got " << int(got.r) << ","
                      << int(got.g) << "," << int(got.b) << ", brute force "
                      << (expected.is_hit() ? "hits triangle " : "misses")
                      << (expected.is_hit() ? std::to_string(expected.triangle) : "");
        }
    EXPECT_EQ(wrong, 0u) << first.str();
    // Premise: the view shows plenty of both surface and background.
    EXPECT_GT(hits, image.rgb.size() / 3 / 5);
    EXPECT_LT(hits, image.rgb.size() / 3 * 9 / 10);
    EXPECT_EQ(result.stats.primary_rays, 160u * 120u);
    EXPECT_EQ(result.stats.primary_hits, hits);
}

TEST(RenderShaded, SpanningSeveralSamplesBlendsSurfaceAndBackground)
{
    // Background is a fixed non-grey colour; with 16 samples a silhouette pixel mixes it
    // with grey, so some pixels must be neither pure background nor pure grey.
    const Scene scene = sphere_floor_scene();
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.samples_per_pixel = 16;
    settings.camera = frame_box(bounds(scene.mesh.view()), 64.0f / 48.0f);
    const RgbImage image = render(scene.grid, scene.mesh.view(), settings).image;
    std::size_t blended = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const Rgb8 c = image.at(x, y);
            if (c != render_background && !(c.r == c.g && c.g == c.b)) ++blended;
        }
    EXPECT_GT(blended, 10u);
}

}  // namespace
}  // namespace sg::test
