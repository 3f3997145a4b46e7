// Heat maps read back from PNG: the colour of each pixel against the traversal counters of
// its primary ray and the brute-force hit, and the legend's colour bar against the pixels.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

#include "apps/app_test_support.hpp"
#include "render_test_support.hpp"
#include "splitgrid/traverse.hpp"
#include "splitgrid/viz/render.hpp"

#include <gtest/gtest.h>

namespace sg::test {
namespace {

/// True if the ray meets the box at some t >= 0 (slab test in double, for the oracle).
bool meets_box(const Ray& ray, const Aabb& box)
{
    double t0 = 0.0;
    double t1 = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 3; ++axis) {
        const double o = ray.origin[axis];
        const double d = ray.direction[axis];
        if (d == 0.0) {
            if (o < box.lower[axis] || o > box.upper[axis]) return false;
            continue;
        }
        double near = (box.lower[axis] - o) / d;
        double far = (box.upper[axis] - o) / d;
        if (near > far) std::swap(near, far);
        t0 = std::max(t0, near);
        t1 = std::min(t1, far);
    }
    return t0 <= t1;
}

bool inside_panel(const HeatLegend& legend, int x, int y)
{
    return x >= legend.panel_x && x < legend.panel_x + legend.panel_width &&
           y >= legend.panel_y && y < legend.panel_y + legend.panel_height;
}

class HeatMap : public ::testing::TestWithParam<RenderMode> {
protected:
    void SetUp() override
    {
        scene_ = sphere_floor_scene();
        settings_.mode = GetParam();
        settings_.width = 320;
        settings_.height = 240;
        settings_.camera = frame_box(bounds(scene_.mesh.view()), 320.0f / 240.0f);
        // Move the eye out so that the corners of the image miss the scene's box.
        settings_.camera.eye = settings_.camera.look_at +
                               (settings_.camera.eye - settings_.camera.look_at) * 1.6f;
        settings_.heat_max = 12.0;
        result_ = render(scene_.grid, scene_.mesh.view(), settings_);
        write_image(scratch_ / "heat.png", result_.image);
        image_ = read_png(scratch_ / "heat.png");
    }

    /// The traversal counter the mode shows, for the ray through the centre of (x, y).
    std::uint32_t cost(const PrimaryRays& rays, int x, int y) const
    {
        TraversalCounters counters;
        (void)intersect(scene_.grid, scene_.mesh.view(),
                        rays.ray(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f),
                        &counters);
        return settings_.mode == RenderMode::heat_cells ? counters.cells_visited
                                                        : counters.triangles_tested;
    }

    Scene scene_;
    RenderSettings settings_;
    RenderResult result_;
    ScratchDir scratch_;
    RgbImage image_;
};

TEST_P(HeatMap, LegendBarRisesInLightnessFromZeroToTheTop)
{
    ASSERT_TRUE(result_.legend.has_value());
    const HeatLegend& legend = *result_.legend;
    ASSERT_TRUE(legend.drawn) << "320x240 must hold the legend";
    EXPECT_EQ(legend.scale_max, 12.0);
    EXPECT_FALSE(legend.automatic);
    ASSERT_GE(legend.bar_height, 40);
    double previous = -1.0;
    std::size_t drops = 0;
    for (int row = legend.bar_y + legend.bar_height - 1; row >= legend.bar_y; --row) {
        const Rgb8 c = image_.at(legend.bar_x, row);
        for (int x = legend.bar_x; x < legend.bar_x + legend.bar_width; ++x)
            ASSERT_EQ(image_.at(x, row), c) << "bar row " << row << " is not one colour";
        const double y = luminance(c);
        // 8-bit rounding may wobble neighbouring entries by a hair, never by a visible step.
        if (y < previous - 0.004) ++drops;
        previous = std::max(previous, y);
    }
    EXPECT_EQ(drops, 0u);
    const Rgb8 bottom = image_.at(legend.bar_x, legend.bar_y + legend.bar_height - 1);
    const Rgb8 top = image_.at(legend.bar_x, legend.bar_y);
    EXPECT_GT(luminance(top) - luminance(bottom), 0.5) << "the map spans dark to light";

    // The labels are text: bright pixels beside the bar, where the map itself is not.
    std::size_t bright = 0;
    for (int y = legend.panel_y; y < legend.panel_y + legend.panel_height; ++y)
        for (int x = legend.bar_x + legend.bar_width + 2; x < legend.panel_x + legend.panel_width;
             ++x)
            if (luminance(image_.at(x, y)) > 0.3) ++bright;
    EXPECT_GT(bright, 20u) << "no label text in the legend";
    EXPECT_EQ(legend.labels.front(), "0");
    EXPECT_EQ(legend.labels.back().rfind("12", 0), 0u) << legend.labels.back();
}

TEST_P(HeatMap, PixelColoursFollowTheCostOfTheirPrimaryRay)
{
    const HeatLegend& legend = *result_.legend;
    const Rgb8 zero_colour = image_.at(legend.bar_x, legend.bar_y + legend.bar_height - 1);
    const Rgb8 top_colour = image_.at(legend.bar_x, legend.bar_y);
    const PrimaryRays rays(settings_.camera, settings_.width, settings_.height);
    Aabb padded_box = bounds(scene_.mesh.view());
    const Vec3f pad = (padded_box.upper - padded_box.lower) * 0.01f;
    padded_box.lower = padded_box.lower - pad;
    padded_box.upper = padded_box.upper + pad;

    std::map<std::uint32_t, Rgb8> colour_of_cost;
    std::size_t outside_box = 0;
    std::size_t hits = 0;
    std::size_t wrong = 0;
    std::ostringstream first;
    const auto fail = [&](int x, int y, const std::string& what) {
        if (wrong++ == 0) first << "pixel (" << x << ", " << y << "): " << what;
    };
    for (int y = 0; y < image_.height; ++y)
        for (int x = 0; x < image_.width; ++x) {
            if (inside_panel(legend, x, y)) continue;
            const Rgb8 got = image_.at(x, y);
            const std::uint32_t c = cost(rays, x, y);
            const Ray ray = rays.ray(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
            // Same cost, same colour; cost 0 is the bottom of the bar, the scale's top or more
            // the top of the bar.
            const auto [it, inserted] = colour_of_cost.emplace(c, got);
            if (!inserted && it->second != got) fail(x, y, "two colours for one cost");
            if ((c == 0) != (got == zero_colour)) fail(x, y, "cost 0 iff the bar's bottom colour");
            if (c >= settings_.heat_max && got != top_colour) fail(x, y, "clamped to the top");
            // Independent of the grid: a ray that clearly misses the scene's box does no work
            // (the grid pads its root box by a hair, so grazing rays may visit a cell), and a
            // ray that hits a triangle (brute force) has tested one at least.
            if (!meets_box(ray, padded_box)) {
                ++outside_box;
                if (got != zero_colour) fail(x, y, "misses the box but is not the zero colour");
            }
            if (intersect_brute_force(scene_.mesh.view(), ray).is_hit()) {
                ++hits;
                if (got == zero_colour) fail(x, y, "hits a triangle but shows zero cost");
            }
        }
    EXPECT_EQ(wrong, 0u) << first.str();
    EXPECT_GT(outside_box, 100u) << "premise: the image corners miss the scene's box";
    EXPECT_GT(hits, 1000u);

    // Higher cost, lighter colour (the map's lightness rises), up to the top of the scale.
    ASSERT_GT(colour_of_cost.size(), 5u);
    double previous = -1.0;
    for (const auto& [c, colour] : colour_of_cost) {
        if (c > settings_.heat_max) break;
        EXPECT_GT(luminance(colour), previous - 0.004) << "cost " << c;
        previous = luminance(colour);
    }
}

TEST_P(HeatMap, AutomaticScaleCoversAllButTheBrightestPixels)
{
    RenderSettings settings = settings_;
    settings.heat_max = 0.0;
    const RenderResult result = render(scene_.grid, scene_.mesh.view(), settings);
    const HeatLegend& legend = *result.legend;
    EXPECT_TRUE(legend.automatic);
    std::size_t above = 0;
    double largest = 0.0;
    for (const float v : result.heat_values) {
        largest = std::max(largest, double(v));
        if (v > legend.scale_max) ++above;
    }
    EXPECT_EQ(legend.max_value, largest);
    EXPECT_LE(above, result.heat_values.size() / 200) << "at most 0.5% above the scale";
    EXPECT_NEAR(legend.clamped_fraction,
                static_cast<double>(above) / static_cast<double>(result.heat_values.size()), 1e-12);
    EXPECT_GT(legend.scale_max, 0.0);
}

TEST_P(HeatMap, TooSmallForTheLegendStillColoursEveryPixel)
{
    RenderSettings settings = settings_;
    settings.width = 40;
    settings.height = 30;
    const RenderResult result = render(scene_.grid, scene_.mesh.view(), settings);
    ASSERT_TRUE(result.legend.has_value());
    EXPECT_FALSE(result.legend->drawn);
    EXPECT_EQ(result.heat_values.size(), 40u * 30u);
}

INSTANTIATE_TEST_SUITE_P(Modes, HeatMap,
                         ::testing::Values(RenderMode::heat_cells, RenderMode::heat_triangles),
                         [](const auto& param_info) {
                             return param_info.param == RenderMode::heat_cells ? "cells"
                                                                               : "triangles";
                         });

}  // namespace
}  // namespace sg::test
