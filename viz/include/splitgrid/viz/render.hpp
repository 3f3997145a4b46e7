#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "splitgrid/camera.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/viz/image.hpp"

namespace sg {

/// What a rendered pixel shows. docs/RENDER.md describes each mode with pictures.
enum class RenderMode {
    /// Grey diffuse shading of the first hit, lit from the eye (a headlight) and by a key
    /// light fixed to the camera; both sides of a triangle are lit. One closest-hit ray per
    /// sample. Formula: see shaded_lighting.
    shaded,
    /// Ambient occlusion: the share of `ao_samples` cosine-distributed occlusion rays from the
    /// first hit that travel `ao_distance` without hitting anything (1 = open, 0 = enclosed),
    /// shown linearly. One closest-hit ray and ao_samples occluded() rays per sample.
    ambient_occlusion,
    /// Diffuse path tracing: grey Lambertian surfaces of albedo path_albedo under a uniform
    /// white sky (radiance sky_radiance in every direction), up to `bounces` reflections,
    /// cosine-weighted bounce directions, no light source other than the sky. A path that
    /// needs more than `bounces` reflections to reach the sky contributes nothing. Shown
    /// sRGB-encoded, clamped to 1. Up to bounces + 1 closest-hit rays per sample.
    path,
    /// Cells visited (TraversalCounters::cells_visited) by the primary ray, mean over the
    /// pixel's samples, through the heat colour map, with a legend.
    heat_cells,
    /// Triangles tested (TraversalCounters::triangles_tested) by the primary ray, as above.
    heat_triangles,
};

/// The mode's command-line name: "shaded", "ao", "path", "heat-cells", "heat-triangles".
[[nodiscard]] std::string_view to_string(RenderMode mode) noexcept;
/// The mode with that command-line name, or nothing.
[[nodiscard]] std::optional<RenderMode> parse_render_mode(std::string_view name) noexcept;
/// Every mode, in the order above.
[[nodiscard]] const std::vector<RenderMode>& all_render_modes();
[[nodiscard]] constexpr bool is_heat_map(RenderMode mode) noexcept
{
    return mode == RenderMode::heat_cells || mode == RenderMode::heat_triangles;
}

/// Colour of pixels whose primary rays all miss, in the shaded, ao and path modes: a dark
/// slate blue that no grey surface value can take, so "background" is decidable per pixel.
/// Pixels whose samples partly hit blend it with the surface linearly.
inline constexpr Rgb8 render_background{48, 56, 72};

/// Grey albedo of every surface in path mode.
inline constexpr float path_albedo = 0.5f;
/// Radiance of the uniform sky in path mode. Under it, a surface that sees only sky has
/// radiance exactly path_albedo * sky_radiance, whatever the sample count.
inline constexpr float sky_radiance = 1.0f;

/// The shaded mode's lighting. With d the unit direction of the primary ray, n the unit
/// geometric normal of the hit triangle ((v1 - v0) x (v2 - v0), normalised) turned to face
/// the viewer (negated when n . d > 0), and the camera basis f = normalize(look_at - eye),
/// r = normalize(f x up), u = r x f, the key light comes from
/// L = normalize(key_up * u - key_left * r - key_back * f) (above, left and behind the
/// viewer), and a sample's grey value is
///     ambient + headlight * (n . -d) + key * max(0, n . L),
/// written to 8 bits as round(255 * value). The weights add up to 1.
struct ShadedLighting {
    float ambient = 0.12f;
    float headlight = 0.58f;
    float key = 0.30f;
    float key_up = 0.7f;
    float key_left = 0.4f;
    float key_back = 0.6f;
};
inline constexpr ShadedLighting shaded_lighting{};

/// Everything a render needs besides the scene. Defaults are sg-render's defaults.
struct RenderSettings {
    RenderMode mode = RenderMode::shaded;
    int width = 800;   ///< pixels, [1, max_image_side]
    int height = 600;  ///< pixels, [1, max_image_side]
    /// Camera rays per pixel, [1, 65536]. With 1 the ray goes through the pixel centre;
    /// with more, through uniformly random points of the pixel.
    std::uint32_t samples_per_pixel = 1;
    /// See sg::frame_box for a camera that sees the whole scene.
    Camera camera;
    /// Seeds every random choice (sub-pixel positions, ao and bounce directions). Each
    /// pixel draws from its own stream (seed, pixel index), so an image depends only on the
    /// settings and the scene, never on the thread count.
    std::uint64_t seed = 1;
    /// Worker threads, 0 = all hardware threads.
    std::uint32_t threads = 0;
    /// Occlusion rays per camera ray in ao mode, [1, 4096].
    std::uint32_t ao_samples = 16;
    /// Reach of the occlusion rays in ao mode, as a fraction of the diagonal of the scene's
    /// bounding box, (0, 1e6]: 0.1 makes occlusion local (creases, contacts); 1 or more
    /// measures whether anything at all is in the way.
    float ao_distance = 0.1f;
    /// Diffuse reflections per path in path mode, [0, 64]; 3 is the paper's workload.
    std::uint32_t bounces = 3;
    /// Top of the heat maps' colour scale, in cells or triangles per ray: 0 chooses it from
    /// the image (see HeatLegend); a fixed value makes images comparable. [0, 1e9].
    double heat_max = 0.0;
};

/// Largest width or height render() accepts (a 16384 x 16384 image needs 768 MiB).
inline constexpr int max_image_side = 16384;

/// Throws ConfigError naming the field, its value and the valid range, or the camera's fault.
void validate(const RenderSettings& settings);

/// Traversal work and ray counts of one render. Means and maxima are over primary rays.
struct RenderStats {
    double seconds = 0.0;                 ///< wall time of render(), legend included
    std::uint64_t primary_rays = 0;       ///< camera rays: width * height * spp
    std::uint64_t secondary_rays = 0;     ///< occlusion and bounce rays
    std::uint64_t primary_hits = 0;       ///< camera rays that hit a triangle
    double nodes_visited_mean = 0.0;
    double cells_visited_mean = 0.0;
    double triangles_tested_mean = 0.0;
    std::uint32_t nodes_visited_max = 0;
    std::uint32_t cells_visited_max = 0;
    std::uint32_t triangles_tested_max = 0;
    int threads = 0;                      ///< threads the render ran on

    [[nodiscard]] std::uint64_t total_rays() const noexcept
    {
        return primary_rays + secondary_rays;
    }
    /// Share of camera rays that hit a triangle, in [0, 1].
    [[nodiscard]] double primary_hit_fraction() const noexcept
    {
        return primary_rays == 0 ? 0.0
                                 : static_cast<double>(primary_hits) /
                                       static_cast<double>(primary_rays);
    }
    /// Millions of rays (primary and secondary) per second of render time.
    [[nodiscard]] double mrays_per_second() const noexcept
    {
        return seconds > 0.0 ? static_cast<double>(total_rays()) / seconds * 1e-6 : 0.0;
    }
};

/// The colour scale of a heat map and where its legend went.
/// Values map linearly from [0, scale_max] onto the colour map (dark violet through red and
/// orange to pale yellow, interpolated in CIELAB so that lightness rises steadily); values
/// above scale_max take the top colour. With heat_max 0 the scale ends at the 99.5th
/// percentile of the pixels' values rounded up to a tick step (1, 2 or 5 times a power of
/// ten), so a few extreme pixels do not wash the rest of the image into one colour.
struct HeatLegend {
    std::string title;                ///< e.g. "cells visited per primary ray"
    double scale_max = 1.0;           ///< value of the top colour
    bool automatic = true;            ///< scale_max was chosen from the image
    double max_value = 0.0;           ///< largest pixel value in the image
    double clamped_fraction = 0.0;    ///< share of pixels above scale_max
    std::vector<double> ticks;        ///< labelled values, 0 first and scale_max last
    std::vector<std::string> labels;  ///< their labels; the last reads "N+" when clamped
    /// False when the image is too small for the legend (then only these fields describe it).
    bool drawn = false;
    /// The colour bar in image pixels (top-left origin), when drawn: the row `bar_y` shows
    /// scale_max, the row `bar_y + bar_height - 1` shows 0, every column of a row the same
    /// colour. Tick labels are to its right, the title above, all on a dark panel.
    int bar_x = 0;
    int bar_y = 0;
    int bar_width = 0;
    int bar_height = 0;
    /// The whole legend panel (bar, labels, title), which covers the picture beneath it.
    int panel_x = 0;
    int panel_y = 0;
    int panel_width = 0;
    int panel_height = 0;
};

/// A rendered image with what it cost.
struct RenderResult {
    RgbImage image;
    RenderStats stats;
    std::optional<HeatLegend> legend;  ///< heat maps only
    /// Heat maps only: each pixel's value (row-major from the top-left, the mean over its
    /// samples of the cells visited or triangles tested by its primary rays).
    std::vector<float> heat_values;
};

/// Called with the fraction of pixels done, in [0, 1], from worker threads, never
/// concurrently; often (once per 16 x 16 tile), so a caller that prints should throttle.
using RenderProgress = std::function<void(double fraction_done)>;

/// Renders `mesh` through `grid` (built for that mesh) as `settings` say, in parallel over
/// 16 x 16 pixel tiles with oneTBB. The image is a pure function of the scene and the
/// settings except `threads`. Throws ConfigError for invalid settings (see validate).
/// Cost: width * height * spp camera rays, times (1 + ao_samples) in ao mode and up to
/// (1 + bounces) in path mode.
[[nodiscard]] RenderResult render(const SplitGrid& grid, const MeshView& mesh,
                                  const RenderSettings& settings,
                                  const RenderProgress& progress = {});

}  // namespace sg
