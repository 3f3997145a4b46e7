// The ao and path modes against what physics says for scenes with a known answer: inside a
// closed sphere nothing is open and no sky is seen (black); a lone floor seen from above is
// fully open and lit by the whole sky (ao white, path exactly albedo times sky radiance).
// Also: the image depends on the seed but not on the thread count.

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>

#include "apps/app_test_support.hpp"
#include "render_test_support.hpp"
#include "splitgrid/viz/render.hpp"

#include <gtest/gtest.h>

namespace sg::test {
namespace {

/// The value of every pixel of `image`, if all are the same grey, or -1.
int uniform_grey(const RgbImage& image)
{
    const Rgb8 first = image.at(0, 0);
    if (first.r != first.g || first.g != first.b) return -1;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            if (image.at(x, y) != first) return -1;
    return first.r;
}

/// Renders, writes a PNG and reads it back with VTK's reader.
RgbImage render_and_read_back(const Scene& scene, const RenderSettings& settings,
                              const std::string& name)
{
    const RenderResult result = render(scene.grid, scene.mesh.view(), settings);
    ScratchDir scratch;
    write_image(scratch / (name + ".png"), result.image);
    return read_png(scratch / (name + ".png"));
}

class InsideClosedSphere : public ::testing::Test {
protected:
    void SetUp() override
    {
        scene_.mesh = uv_sphere({0.0f, 0.0f, 0.0f}, 1.0f, 24, 48);
        scene_.grid = build_checked(scene_.mesh);
        settings_.width = 48;
        settings_.height = 36;
        settings_.camera =
            Camera{{0.1f, 0.05f, 0.0f}, {0.0f, 0.2f, -1.0f}, {0.0f, 1.0f, 0.0f}, 90.0f};
    }
    Scene scene_;
    RenderSettings settings_;
};

TEST_F(InsideClosedSphere, AmbientOcclusionIsFullyOccluded)
{
    settings_.mode = RenderMode::ambient_occlusion;
    settings_.ao_samples = 8;
    settings_.ao_distance = 1.0f;  // the diagonal of the box, longer than any chord
    EXPECT_EQ(uniform_grey(render_and_read_back(scene_, settings_, "ao")), 0);
}

TEST_F(InsideClosedSphere, ShortAmbientOcclusionRaysSeeNothing)
{
    // Control: rays shorter than the distance to the far wall find every direction open,
    // so the black above comes from real occlusion.
    settings_.mode = RenderMode::ambient_occlusion;
    settings_.ao_samples = 8;
    settings_.ao_distance = 1e-6f;
    EXPECT_EQ(uniform_grey(render_and_read_back(scene_, settings_, "ao_short")), 255);
}

TEST_F(InsideClosedSphere, PathTracingReceivesNoSkyLight)
{
    settings_.mode = RenderMode::path;
    settings_.samples_per_pixel = 4;
    EXPECT_EQ(uniform_grey(render_and_read_back(scene_, settings_, "path")), 0);
}

class FloorFromAbove : public ::testing::Test {
protected:
    void SetUp() override
    {
        scene_.mesh = axis_plane(1, 0.0f, 8);  // y = 0, x and z in [0, 8]
        scene_.grid = build_checked(scene_.mesh);
        settings_.width = 40;
        settings_.height = 30;
        // From 5 units above the centre, a 40-degree view stays well inside the floor.
        settings_.camera =
            Camera{{4.0f, 5.0f, 4.0f}, {4.0f, 0.0f, 4.0f}, {0.0f, 0.0f, -1.0f}, 40.0f};
    }
    Scene scene_;
    RenderSettings settings_;
};

TEST_F(FloorFromAbove, AmbientOcclusionIsFullyOpen)
{
    settings_.mode = RenderMode::ambient_occlusion;
    settings_.ao_samples = 8;
    settings_.ao_distance = 10.0f;
    EXPECT_EQ(uniform_grey(render_and_read_back(scene_, settings_, "ao")), 255);
}

TEST_F(FloorFromAbove, PathTracingGivesAlbedoTimesSky)
{
    // Every bounce ray escapes to the uniform sky, so each sample is exactly albedo * sky.
    const double linear = double(path_albedo) * double(sky_radiance);
    const double srgb = linear <= 0.0031308 ? 12.92 * linear
                                            : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
    const int expected = static_cast<int>(std::lround(srgb * 255.0));
    settings_.mode = RenderMode::path;
    for (const std::uint32_t bounces : {1u, 3u}) {
        settings_.bounces = bounces;
        const int grey = uniform_grey(render_and_read_back(scene_, settings_, "path"));
        EXPECT_NEAR(grey, expected, 1) << bounces << " bounces";
    }
}

TEST_F(FloorFromAbove, PathTracingWithoutBouncesIsBlack)
{
    // No reflection allowed: a surface cannot send sky light to the eye.
    settings_.mode = RenderMode::path;
    settings_.bounces = 0;
    EXPECT_EQ(uniform_grey(render_and_read_back(scene_, settings_, "path0")), 0);
}

TEST(RenderModes, OcclusionAndBouncesShadeBetweenTheExtremes)
{
    // Sphere on a floor: the floor near the sphere is partly occluded, the open floor and
    // the sphere's top see the sky; ao and path must produce both and values in between.
    const Scene scene = sphere_floor_scene();
    for (const RenderMode mode : {RenderMode::ambient_occlusion, RenderMode::path}) {
        RenderSettings settings;
        settings.mode = mode;
        settings.width = 80;
        settings.height = 60;
        settings.ao_distance = 0.2f;
        settings.samples_per_pixel = 2;
        settings.camera = frame_box(bounds(scene.mesh.view()), 80.0f / 60.0f);
        const RgbImage image = render_and_read_back(scene, settings, "mix");
        int darkest = 255;
        int brightest = 0;
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) {
                const Rgb8 c = image.at(x, y);
                if (c == render_background) continue;
                darkest = std::min<int>(darkest, c.r);
                brightest = std::max<int>(brightest, c.r);
            }
        EXPECT_LT(darkest, brightest - 60) << to_string(mode);
    }
}

TEST(RenderModes, ImageDependsOnSeedButNotOnThreadCount)
{
    const Scene scene = sphere_floor_scene();
    for (const RenderMode mode : all_render_modes()) {
        SCOPED_TRACE(std::string(to_string(mode)));
        RenderSettings settings;
        settings.mode = mode;
        settings.width = 70;  // not a multiple of the tile size
        settings.height = 45;
        settings.samples_per_pixel = 3;
        settings.ao_samples = 4;
        settings.camera = frame_box(bounds(scene.mesh.view()), 70.0f / 45.0f);
        settings.threads = 1;
        const RenderResult one = render(scene.grid, scene.mesh.view(), settings);
        settings.threads = 2;
        const RenderResult two = render(scene.grid, scene.mesh.view(), settings);
        EXPECT_EQ(one.image, two.image);
        EXPECT_EQ(one.heat_values, two.heat_values);
        EXPECT_EQ(one.stats.total_rays(), two.stats.total_rays());
        EXPECT_EQ(one.stats.cells_visited_max, two.stats.cells_visited_max);

        ScratchDir scratch;
        write_image(scratch / "one.png", one.image);
        write_image(scratch / "two.png", two.image);
        EXPECT_EQ(read_text(scratch / "one.png"), read_text(scratch / "two.png"));

        settings.seed = 2;
        const RenderResult reseeded = render(scene.grid, scene.mesh.view(), settings);
        // Every mode jitters its camera rays when spp > 1, so a new seed moves them.
        EXPECT_NE(reseeded.image, two.image);
    }
}

TEST(RenderModes, RaysAreCountedPerMode)
{
    const Scene scene = sphere_floor_scene();
    RenderSettings settings;
    settings.width = 32;
    settings.height = 24;
    settings.camera = frame_box(bounds(scene.mesh.view()), 32.0f / 24.0f);
    settings.mode = RenderMode::ambient_occlusion;
    settings.ao_samples = 5;
    const RenderStats ao = render(scene.grid, scene.mesh.view(), settings).stats;
    EXPECT_EQ(ao.primary_rays, 32u * 24u);
    EXPECT_EQ(ao.secondary_rays, ao.primary_hits * 5u);
    settings.mode = RenderMode::path;
    settings.bounces = 3;
    const RenderStats path = render(scene.grid, scene.mesh.view(), settings).stats;
    EXPECT_GE(path.secondary_rays, path.primary_hits);
    EXPECT_LE(path.secondary_rays, path.primary_hits * 3u);
}

TEST(RenderModes, InvalidSettingsAreRefused)
{
    const Scene scene = sphere_floor_scene();
    RenderSettings good;
    good.width = 8;
    good.height = 8;
    good.camera = frame_box(bounds(scene.mesh.view()), 1.0f);
    EXPECT_NO_THROW((void)render(scene.grid, scene.mesh.view(), good));
    const auto refused = [&](auto change) {
        RenderSettings s = good;
        change(s);
        EXPECT_THROW((void)render(scene.grid, scene.mesh.view(), s), ConfigError);
    };
    refused([](RenderSettings& s) { s.width = 0; });
    refused([](RenderSettings& s) { s.height = max_image_side + 1; });
    refused([](RenderSettings& s) { s.samples_per_pixel = 0; });
    refused([](RenderSettings& s) { s.ao_samples = 0; });
    refused([](RenderSettings& s) { s.ao_distance = 0.0f; });
    refused([](RenderSettings& s) { s.ao_distance = std::nanf(""); });
    refused([](RenderSettings& s) { s.bounces = 65; });
    refused([](RenderSettings& s) { s.heat_max = -1.0; });
    refused([](RenderSettings& s) { s.camera.look_at = s.camera.eye; });
    refused([](RenderSettings& s) { s.camera.fov_y_degrees = 180.0f; });
}

}  // namespace
}  // namespace sg::test
