/// sg-render: renders the scene of a .sg file through its Split Grid to an image: shaded,
/// ambient occlusion, a diffuse path tracer, or a heat map of the traversal cost per pixel.
/// Prints a summary (or one JSON object with --json) on stdout.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <string>

#include "camera_flags.hpp"
#include "cli_common.hpp"
#include "splitgrid/camera.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/output_file.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/version.hpp"
#include "splitgrid/viz/image.hpp"
#include "splitgrid/viz/library_versions.hpp"
#include "splitgrid/viz/render.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

namespace {

namespace fs = std::filesystem;
using sg::apps::Json;
using Clock = std::chrono::steady_clock;

constexpr std::uint32_t max_threads = 1024;
constexpr std::uint32_t path_default_spp = 16;

struct Options {
    fs::path file;
    fs::path output;
    std::string mode = "shaded";
    sg::RenderSettings settings;
    sg::apps::CameraFlags camera;
    bool json = false;
    sg::apps::LogOptions log;
};

Json legend_json(const sg::HeatLegend& legend)
{
    return {{"title", legend.title},
            {"scale_min", 0.0},
            {"scale_max", legend.scale_max},
            {"automatic", legend.automatic},
            {"max_value", legend.max_value},
            {"clamped_fraction", legend.clamped_fraction},
            {"ticks", legend.ticks},
            {"labels", legend.labels},
            {"drawn", legend.drawn}};
}

void print_json(const Options& options, const std::string& isa, const sg::RenderResult& result,
                const sg::Camera& camera, bool automatic_camera, std::size_t triangles,
                double load_seconds, double write_seconds, std::uintmax_t image_bytes)
{
    const sg::RenderSettings& s = options.settings;
    const sg::RenderStats& stats = result.stats;
    Json j;
    j["schema_version"] = sg::apps::json_schema_version;
    j["splitgrid_version"] = sg::version_string;
    j["file"] = options.file.string();
    j["triangle_count"] = triangles;
    j["image"] = {{"path", options.output.string()},
                  {"format", sg::format_name(*sg::image_format_for(options.output))},
                  {"width", s.width},
                  {"height", s.height},
                  {"bytes", image_bytes}};
    j["mode"] = std::string(sg::to_string(s.mode));
    j["isa"] = isa;
    j["samples_per_pixel"] = s.samples_per_pixel;
    j["seed"] = s.seed;
    j["ao_samples"] = s.ao_samples;
    j["ao_distance"] = s.ao_distance;
    j["bounces"] = s.bounces;
    j["camera"] = sg::apps::camera_json(camera, automatic_camera);
    j["threads"] = stats.threads;
    j["rays"] = {{"primary", stats.primary_rays},
                 {"secondary", stats.secondary_rays},
                 {"total", stats.total_rays()}};
    j["primary"] = {
        {"hit_fraction", stats.primary_hit_fraction()},
        {"nodes_visited_mean", stats.nodes_visited_mean},
        {"nodes_visited_max", stats.nodes_visited_max},
        {"cells_visited_mean", stats.cells_visited_mean},
        {"cells_visited_max", stats.cells_visited_max},
        {"triangles_tested_mean", stats.triangles_tested_mean},
        {"triangles_tested_max", stats.triangles_tested_max}};
    j["heat"] = result.legend ? legend_json(*result.legend) : Json(nullptr);
    j["seconds"] = {{"load", load_seconds}, {"render", stats.seconds}, {"write", write_seconds}};
    j["mrays_per_second"] = stats.mrays_per_second();
    std::cout << j.dump(2) << '\n';
}

void print_summary(const Options& options, const sg::RenderResult& result,
                   const sg::Camera& camera, bool automatic_camera, double load_seconds,
                   double write_seconds, std::uintmax_t image_bytes)
{
    const sg::RenderSettings& s = options.settings;
    const sg::RenderStats& stats = result.stats;
    std::cout << fmt::format(
        "image       {} ({}x{} {}, {}, {})\n"
        "camera      {}{}\n"
        "rays        {} primary ({} per pixel) + {} secondary in {:.3f} s on {} thread{}: "
        "{:.2f} Mrays/s\n"
        "primary     {:.1f}% hit; per ray: cells visited mean {:.1f} max {}, triangles tested "
        "mean {:.1f} max {}, nodes visited mean {:.1f} max {}\n",
        options.output.string(), s.width, s.height, sg::to_string(s.mode),
        sg::format_name(*sg::image_format_for(options.output)), sg::apps::human_bytes(image_bytes),
        sg::apps::camera_as_flags(camera), automatic_camera ? " (automatic framing)" : "",
        stats.primary_rays, s.samples_per_pixel, stats.secondary_rays, stats.seconds,
        stats.threads, stats.threads == 1 ? "" : "s", stats.mrays_per_second(),
        100.0 * stats.primary_hit_fraction(),
        stats.cells_visited_mean, stats.cells_visited_max, stats.triangles_tested_mean,
        stats.triangles_tested_max, stats.nodes_visited_mean, stats.nodes_visited_max);
    if (result.legend) {
        const sg::HeatLegend& legend = *result.legend;
        std::cout << fmt::format(
            "heat scale  0 .. {} {} ({}; largest pixel {:g}, {:.2f}% of pixels above the scale); "
            "legend {}\n",
            legend.scale_max, legend.title, legend.automatic ? "automatic" : "--heat-max",
            legend.max_value, 100.0 * legend.clamped_fraction,
            legend.drawn ? "drawn top right" : "not drawn (image too small)");
    }
    std::cout << fmt::format("time        load {:.3f} s, render {:.3f} s, write {:.3f} s\n",
                             load_seconds, stats.seconds, write_seconds);
}

void render(Options& options)
{
    // Fail on an output that would destroy the input, or that cannot be written, now: not
    // after a long render. The temporary file exists from here on.
    sg::apps::refuse_output_over_input(options.output, {options.file});
    const std::unique_ptr<sg::OutputFile> output = sg::apps::reserve_output(options.output);
    options.settings.threads = sg::apps::threads_to_use(options.settings.threads);
    const std::string isa = sg::apps::kernel_isa_in_use();

    const auto load_start = Clock::now();
    const sg::SgContents contents = sg::read_sg_file(options.file);
    const double load_seconds = sg::apps::seconds_since(load_start);
    const sg::MeshView mesh = contents.mesh.view();
    spdlog::debug("{}: {} triangles, {} nodes", options.file.string(), mesh.triangle_count(),
                  contents.grid.nodes.size());

    bool automatic_camera = false;
    options.settings.camera =
        sg::apps::choose_camera(options.camera, mesh, options.settings.width,
                                options.settings.height, automatic_camera);
    const sg::RenderResult result =
        sg::render(contents.grid, mesh, options.settings,
                   sg::apps::ProgressLog("rendering", "pixels done", Clock::now()));
    if (result.legend && !result.legend->drawn)
        spdlog::warn("{}x{} is too small for the heat legend; its scale: 0 .. {} {}",
                     options.settings.width, options.settings.height, result.legend->scale_max,
                     result.legend->title);

    const auto write_start = Clock::now();
    sg::write_image(*output, result.image);
    const double write_seconds = sg::apps::seconds_since(write_start);
    const std::uintmax_t image_bytes = fs::file_size(options.output);

    if (options.json)
        print_json(options, isa, result, options.settings.camera, automatic_camera,
                   mesh.triangle_count(), load_seconds, write_seconds, image_bytes);
    else if (options.log.shows_summary())
        print_summary(options, result, options.settings.camera, automatic_camera,
                      load_seconds, write_seconds, image_bytes);
}

}  // namespace

int main(int argc, char** argv)
{
    Options options;
    sg::RenderSettings& s = options.settings;
    CLI::App app{"", "sg-render"};
    sg::apps::describe_tool(
        app,
        "Renders the scene of a .sg file through its Split Grid (in parallel; the image does\n"
        "not depend on the thread count) and writes an image through VTK's image writers.",
        "Modes (docs/RENDER.md):\n"
        "  shaded          grey diffuse shading, lit from the eye and by a light fixed to the\n"
        "                  camera; both sides of a triangle are lit\n"
        "  ao              ambient occlusion: share of --ao-samples cosine-distributed rays\n"
        "                  from the first hit that travel --ao-distance unobstructed\n"
        "  path            diffuse path tracer: grey albedo 0.5 under a uniform white sky,\n"
        "                  up to --bounces reflections (the paper's workload: 3), sRGB\n"
        "  heat-cells      cells visited by each pixel's primary ray, with a colour legend\n"
        "  heat-triangles  triangles tested by each pixel's primary ray, with a legend\n"
        "Without --eye and --look-at the camera frames the scene so that it fills the image,\n"
        "seen from above and to the side with --up up (default +y: give --up 0,0,1 for a\n"
        "z-up scene); the summary prints the camera flags it used, to adjust from.\n"
        "The image is written atomically: on failure or an interrupt no output file is left\n"
        "behind.",
        sg::viz::viz_library_versions());
    app.add_option("FILE", options.file, "The .sg file (from sg-build)")->required();
    sg::apps::add_output_option(app, options.output,
                                "Output image, written atomically; the extension picks the "
                                "format: " +
                                    sg::supported_image_extensions() +
                                    " (PNG recommended: lossless)")
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                return sg::image_format_for(text)
                           ? std::string{}
                           : text + ": unsupported image extension (use one of " +
                                 sg::supported_image_extensions() + ")";
            },
            "", ""));
    app.add_option("--mode", options.mode,
                   sg::apps::help_text("What the pixels show (see below).", {}, "shaded"))
        ->check(CLI::IsMember({"shaded", "ao", "path", "heat-cells", "heat-triangles"}));
    const auto side = static_cast<std::uint32_t>(sg::max_image_side);
    sg::apps::add_count_option(app, "--width", s.width, 1, side, "Image width in pixels.");
    sg::apps::add_count_option(app, "--height", s.height, 1, side, "Image height in pixels.");
    CLI::Option* spp = sg::apps::add_count_option(
        app, "--spp", s.samples_per_pixel, 1, 65536,
        "Camera rays per pixel: 1 goes through the pixel centre, more through random points of "
        "the pixel (antialiasing, less noise).",
        fmt::format("1, {} in path mode", path_default_spp));
    sg::apps::add_camera_flags(app, options.camera);
    sg::apps::add_count_option(app, "--threads", s.threads, 0, max_threads,
                               "Worker threads, 0 = all hardware threads; the image is the same "
                               "for every value.");
    sg::apps::add_count_option(app, "--seed", s.seed, 0,
                               std::numeric_limits<std::uint64_t>::max(),
                               "Seed of every random choice (sub-pixel positions, ao and bounce "
                               "directions); the same seed gives the same image.");
    sg::apps::add_count_option(app, "--ao-samples", s.ao_samples, 1, 4096,
                               "ao mode: occlusion rays per camera ray.");
    sg::apps::add_real_option(app, "--ao-distance", s.ao_distance, 0.0, 1e6, true,
                              "ao mode: reach of the occlusion rays as a fraction of the "
                              "diagonal of the scene's box.");
    sg::apps::add_count_option(app, "--bounces", s.bounces, 0, 64,
                               "path mode: diffuse reflections per path.");
    sg::apps::add_real_option(app, "--heat-max", s.heat_max, 0.0, 1e9, false,
                              "Heat maps: value of the top colour, in cells or triangles per "
                              "ray; fix it to compare images. 0 = automatic (the 99.5th "
                              "percentile of the image, rounded up to a tick).");
    app.add_flag("--json", options.json,
                 "Print one JSON object (docs/RENDER.md) instead of the summary");
    sg::apps::add_log_flags(app, options.log);

    app.parse_complete_callback([&] {
        s.mode = *sg::parse_render_mode(options.mode);
        if (s.mode == sg::RenderMode::path && spp->count() == 0)
            s.samples_per_pixel = path_default_spp;
        // A camera given in full is checked before the .sg file is read.
        sg::apps::check_full_camera(options.camera);
    });
    return sg::apps::run_tool(app, argc, argv, options.log, [&] { render(options); });
}
