#include "splitgrid/viz/render.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <mutex>
#include <string>

#include "colour_map.hpp"
#include "heat_legend.hpp"
#include "heat_scale.hpp"
#include "integrators.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/traverse.hpp"

#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace sg {
namespace {

constexpr int tile_side = 16;
constexpr std::uint32_t max_samples_per_pixel = 65536;
constexpr std::uint32_t max_ao_samples = 4096;
constexpr std::uint32_t max_bounces = 64;
constexpr float max_ao_distance = 1e6f;
constexpr double max_heat_max = 1e9;

struct ModeName {
    RenderMode mode;
    std::string_view name;
};
constexpr std::array<ModeName, 5> mode_names{{
    {RenderMode::shaded, "shaded"},
    {RenderMode::ambient_occlusion, "ao"},
    {RenderMode::path, "path"},
    {RenderMode::heat_cells, "heat-cells"},
    {RenderMode::heat_triangles, "heat-triangles"},
}};

/// Sums over primary rays; integers only, so merging per-thread tallies in any order gives
/// the same totals.
struct Tally {
    std::uint64_t primary_rays = 0;
    std::uint64_t secondary_rays = 0;
    std::uint64_t primary_hits = 0;
    std::uint64_t nodes = 0;
    std::uint64_t cells = 0;
    std::uint64_t triangles = 0;
    std::uint32_t nodes_max = 0;
    std::uint32_t cells_max = 0;
    std::uint32_t triangles_max = 0;

    void add(const TraversalCounters& c) noexcept
    {
        ++primary_rays;
        nodes += c.nodes_visited;
        cells += c.cells_visited;
        triangles += c.triangles_tested;
        nodes_max = std::max(nodes_max, c.nodes_visited);
        cells_max = std::max(cells_max, c.cells_visited);
        triangles_max = std::max(triangles_max, c.triangles_tested);
    }
    void merge(const Tally& o) noexcept
    {
        primary_rays += o.primary_rays;
        secondary_rays += o.secondary_rays;
        primary_hits += o.primary_hits;
        nodes += o.nodes;
        cells += o.cells;
        triangles += o.triangles;
        nodes_max = std::max(nodes_max, o.nodes_max);
        cells_max = std::max(cells_max, o.cells_max);
        triangles_max = std::max(triangles_max, o.triangles_max);
    }
};

float srgb_encode(float linear) noexcept
{
    const float c = std::clamp(linear, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

std::uint8_t to_byte(float unit) noexcept
{
    return static_cast<std::uint8_t>(std::lround(std::clamp(unit, 0.0f, 1.0f) * 255.0f));
}

/// Diagonal of the mesh's bounding box, computed in double (the box may span the float range).
float scene_diagonal(const MeshView& mesh) noexcept
{
    const Aabb box = bounds(mesh);
    if (box.is_empty()) return 1.0f;
    double sum = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        const double extent = double(box.upper[axis]) - double(box.lower[axis]);
        sum += extent * extent;
    }
    const double diagonal = std::sqrt(sum);
    return diagonal > 0.0 ? static_cast<float>(std::min(diagonal, 1e30)) : 1.0f;
}

/// Serialises progress reports from the worker threads.
class ProgressReporter {
public:
    ProgressReporter(const RenderProgress& callback, std::uint64_t total)
        : callback_(callback), total_(total)
    {
    }
    void done(std::uint64_t pixels)
    {
        if (!callback_) return;
        const std::lock_guard lock(mutex_);
        done_ += pixels;
        callback_(static_cast<double>(done_) / static_cast<double>(total_));
    }

private:
    const RenderProgress& callback_;
    std::uint64_t total_;
    std::uint64_t done_ = 0;
    std::mutex mutex_;
};

/// Renders one pixel: its colour in the image (not for heat maps) and, for heat maps, its
/// mean cost in `heat`.
struct PixelRenderer {
    const SplitGrid& grid;
    const MeshView& mesh;
    const RenderSettings& settings;
    const PrimaryRays& rays;
    const detail::ShadingContext& context;

    void operator()(int x, int y, RgbImage& image, float* heat, Tally& tally) const noexcept
    {
        const std::uint64_t pixel_index =
            static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(settings.width) +
            static_cast<std::uint64_t>(x);
        Rng rng(settings.seed, pixel_index);
        const std::uint32_t spp = settings.samples_per_pixel;
        float red = 0.0f, green = 0.0f, blue = 0.0f;
        double cost = 0.0;
        const bool heat_map = is_heat_map(settings.mode);
        for (std::uint32_t s = 0; s < spp; ++s) {
            float jx = 0.5f, jy = 0.5f;
            if (spp > 1) {
                jx = rng.next_float();
                jy = rng.next_float();
            }
            const Ray ray = rays.ray(static_cast<float>(x) + jx, static_cast<float>(y) + jy);
            TraversalCounters counters;
            const Hit hit = intersect(grid, mesh, ray, &counters);
            tally.add(counters);
            if (hit.is_hit()) ++tally.primary_hits;
            if (heat_map) {
                cost += settings.mode == RenderMode::heat_cells ? counters.cells_visited
                                                                : counters.triangles_tested;
                continue;
            }
            if (!hit.is_hit()) {
                red += static_cast<float>(render_background.r) / 255.0f;
                green += static_cast<float>(render_background.g) / 255.0f;
                blue += static_cast<float>(render_background.b) / 255.0f;
                continue;
            }
            const detail::SampleResult sample = detail::shade(context, ray, hit, rng);
            tally.secondary_rays += sample.secondary_rays;
            // Path tracing estimates radiance, shown sRGB-encoded; the other modes are
            // visualisations whose values are shown as they are.
            const float shown =
                settings.mode == RenderMode::path ? srgb_encode(sample.value) : sample.value;
            red += shown;
            green += shown;
            blue += shown;
        }
        const float inv = 1.0f / static_cast<float>(spp);
        if (heat_map) {
            heat[pixel_index] = static_cast<float>(cost / spp);
            return;
        }
        image.set(x, y, {to_byte(red * inv), to_byte(green * inv), to_byte(blue * inv)});
    }
};

}  // namespace

std::string_view to_string(RenderMode mode) noexcept
{
    for (const ModeName& m : mode_names)
        if (m.mode == mode) return m.name;
    return "?";
}

std::optional<RenderMode> parse_render_mode(std::string_view name) noexcept
{
    for (const ModeName& m : mode_names)
        if (m.name == name) return m.mode;
    return std::nullopt;
}

const std::vector<RenderMode>& all_render_modes()
{
    static const std::vector<RenderMode> modes = [] {
        std::vector<RenderMode> list;
        for (const ModeName& m : mode_names) list.push_back(m.mode);
        return list;
    }();
    return modes;
}

void validate(const RenderSettings& settings)
{
    const auto out_of_range = [](const char* field, const std::string& value,
                                 const std::string& range) {
        return ConfigError("render settings: " + std::string(field) + " = " + value +
                           " is outside " + range);
    };
    const std::string side_range = "[1, " + std::to_string(max_image_side) + "]";
    if (settings.width < 1 || settings.width > max_image_side)
        throw out_of_range("width", std::to_string(settings.width), side_range);
    if (settings.height < 1 || settings.height > max_image_side)
        throw out_of_range("height", std::to_string(settings.height), side_range);
    if (settings.samples_per_pixel < 1 || settings.samples_per_pixel > max_samples_per_pixel)
        throw out_of_range("samples_per_pixel", std::to_string(settings.samples_per_pixel),
                           "[1, " + std::to_string(max_samples_per_pixel) + "]");
    if (settings.ao_samples < 1 || settings.ao_samples > max_ao_samples)
        throw out_of_range("ao_samples", std::to_string(settings.ao_samples),
                           "[1, " + std::to_string(max_ao_samples) + "]");
    if (!(settings.ao_distance > 0.0f && settings.ao_distance <= max_ao_distance))
        throw out_of_range("ao_distance", std::to_string(settings.ao_distance), "(0, 1e6]");
    if (settings.bounces > max_bounces)
        throw out_of_range("bounces", std::to_string(settings.bounces),
                           "[0, " + std::to_string(max_bounces) + "]");
    if (!(settings.heat_max >= 0.0 && settings.heat_max <= max_heat_max))
        throw out_of_range("heat_max", std::to_string(settings.heat_max), "[0, 1e9]");
    validate(settings.camera);
}

RenderResult render(const SplitGrid& grid, const MeshView& mesh, const RenderSettings& settings,
                    const RenderProgress& progress)
{
    validate(settings);
    const auto start = std::chrono::steady_clock::now();
    const PrimaryRays rays(settings.camera, settings.width, settings.height);
    const detail::ShadingContext context{grid,
                                         mesh,
                                         settings.mode,
                                         detail::key_light_direction(settings.camera),
                                         settings.ao_distance * scene_diagonal(mesh),
                                         settings.ao_samples,
                                         settings.bounces};
    const PixelRenderer pixel{grid, mesh, settings, rays, context};

    RenderResult result;
    result.image = RgbImage(settings.width, settings.height);
    const std::size_t pixel_count =
        static_cast<std::size_t>(settings.width) * static_cast<std::size_t>(settings.height);
    if (is_heat_map(settings.mode)) result.heat_values.assign(pixel_count, 0.0f);

    tbb::combinable<Tally> tallies;
    ProgressReporter reporter(progress, pixel_count);
    tbb::task_arena arena(settings.threads == 0 ? tbb::task_arena::automatic
                                                : static_cast<int>(settings.threads));
    arena.execute([&] {
        tbb::parallel_for(
            tbb::blocked_range2d<int>(0, settings.height, tile_side, 0, settings.width, tile_side),
            [&](const tbb::blocked_range2d<int>& tile) {
                Tally& tally = tallies.local();
                for (int y = tile.rows().begin(); y != tile.rows().end(); ++y)
                    for (int x = tile.cols().begin(); x != tile.cols().end(); ++x)
                        pixel(x, y, result.image, result.heat_values.data(), tally);
                reporter.done(static_cast<std::uint64_t>(tile.rows().size()) *
                              tile.cols().size());
            });
    });

    Tally total;
    tallies.combine_each([&](const Tally& t) { total.merge(t); });
    RenderStats& stats = result.stats;
    stats.primary_rays = total.primary_rays;
    stats.secondary_rays = total.secondary_rays;
    stats.primary_hits = total.primary_hits;
    const double rays_traced = std::max<double>(1.0, static_cast<double>(total.primary_rays));
    stats.nodes_visited_mean = static_cast<double>(total.nodes) / rays_traced;
    stats.cells_visited_mean = static_cast<double>(total.cells) / rays_traced;
    stats.triangles_tested_mean = static_cast<double>(total.triangles) / rays_traced;
    stats.nodes_visited_max = total.nodes_max;
    stats.cells_visited_max = total.cells_max;
    stats.triangles_tested_max = total.triangles_max;
    stats.threads = arena.max_concurrency();

    if (is_heat_map(settings.mode)) {
        HeatLegend legend =
            detail::make_heat_scale(result.heat_values, settings.heat_max, settings.mode);
        const auto* value = result.heat_values.data();
        for (int y = 0; y < settings.height; ++y)
            for (int x = 0; x < settings.width; ++x)
                result.image.set(x, y, detail::heat_colour(*value++, legend.scale_max));
        detail::draw_heat_legend(result.image, legend);
        result.legend = std::move(legend);
    }
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace sg
