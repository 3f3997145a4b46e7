/// sg-rays: writes a ray file (docs/FORMAT.md) without writing code: the primary rays of a
/// camera framed as sg-render frames it, random rays in a scene's box, or rays read from a
/// text or CSV file. Prints a summary (or one JSON object with --json) on stdout.

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "camera_flags.hpp"
#include "cli_common.hpp"
#include "output_paths.hpp"
#include "splitgrid/camera.hpp"
#include "splitgrid/formats/output_file.hpp"
#include "splitgrid/formats/ray_file.hpp"
#include "splitgrid/formats/ray_text.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/ray_generation.hpp"
#include "splitgrid/version.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

namespace {

namespace fs = std::filesystem;
using sg::apps::Json;

/// Largest image side of the camera mode: a 16384 x 16384 image is 268M rays, an 8 GiB file.
constexpr std::uint32_t max_side = 16384;
constexpr std::uint32_t max_random_rays = 1'000'000'000;

struct Options {
    fs::path input;  ///< the .sg file (camera, random) or the text file (text)
    fs::path output;
    // camera
    std::uint32_t width = 800;   // sg-render's default image size
    std::uint32_t height = 600;
    sg::apps::CameraFlags camera;
    // random
    std::uint32_t count = 1'000'000;
    std::uint64_t seed = 1;
    bool json = false;
    sg::apps::LogOptions log;
};

/// What a mode made, for the summary and the JSON.
struct Made {
    std::string mode;
    std::vector<sg::Ray> rays;
    std::string details;  ///< one line for the summary
    Json json;            ///< the mode's own JSON keys
};

Made camera_rays(const Options& options)
{
    const sg::SgContents contents = sg::read_sg_file(options.input);
    const auto width = static_cast<int>(options.width);
    const auto height = static_cast<int>(options.height);
    bool automatic = false;
    const sg::Camera camera =
        sg::apps::choose_camera(options.camera, contents.mesh.view(), width, height, automatic);
    Made made{"camera", sg::pixel_centre_rays(sg::PrimaryRays(camera, width, height)), {}, {}};
    made.details = fmt::format("{}x{} pixels, ray y * {} + x through the centre of pixel (x, y); "
                               "camera {}{}",
                               width, height, width, sg::apps::camera_as_flags(camera),
                               automatic ? " (automatic framing)" : "");
    made.json = {{"width", width}, {"height", height},
                 {"camera", sg::apps::camera_json(camera, automatic)}};
    return made;
}

Made random_rays(const Options& options)
{
    const sg::SgContents contents = sg::read_sg_file(options.input);
    const sg::Aabb box = sg::bounds(contents.mesh.view());
    Made made{"random", sg::random_rays_in_box(box, options.count, options.seed), {}, {}};
    made.details = fmt::format("origins uniform in the box ({},{},{}) .. ({},{},{}), directions "
                               "uniform on the sphere, seed {}",
                               box.lower.x, box.lower.y, box.lower.z, box.upper.x, box.upper.y,
                               box.upper.z, options.seed);
    made.json = {{"seed", options.seed},
                 {"box", {{"lower", {box.lower.x, box.lower.y, box.lower.z}},
                          {"upper", {box.upper.x, box.upper.y, box.upper.z}}}}};
    return made;
}

Made text_rays(const Options& options)
{
    Made made{"text", sg::read_ray_text(options.input), {}, Json::object()};
    made.details = "read from " + options.input.string();
    return made;
}

void write_rays(const Options& options, Made (*make)(const Options&))
{
    // An output that would destroy the input, or that cannot be written, is refused before
    // anything is read; the temporary file exists from here on.
    sg::apps::refuse_output_over_input(options.output, {options.input});
    const std::unique_ptr<sg::OutputFile> output = sg::apps::reserve_output(options.output);
    const Made made = make(options);
    sg::write_ray_file(*output, made.rays);
    const std::size_t invalid = static_cast<std::size_t>(
        std::count_if(made.rays.begin(), made.rays.end(),
                      [](const sg::Ray& ray) { return !sg::is_valid(ray); }));
    if (invalid != 0)
        spdlog::warn("{}: {} of {} rays are invalid ({}); they are written as given, and "
                     "sg-trace traces them as misses",
                     options.input.string(), invalid, made.rays.size(),
                     sg::invalid_ray_description);
    if (options.json) {
        Json j;
        j["schema_version"] = sg::apps::json_schema_version;
        j["splitgrid_version"] = sg::version_string;
        j["mode"] = made.mode;
        j["input"] = options.input.string();
        j["output"] = options.output.string();
        j["ray_count"] = made.rays.size();
        j["invalid_rays"] = invalid;
        j.update(made.json);
        std::cout << j.dump(2) << '\n';
        return;
    }
    if (!options.log.shows_summary()) return;
    std::cout << fmt::format("wrote {} rays ({}: {}) to {}\n", made.rays.size(), made.mode,
                             made.details, options.output.string());
}

}  // namespace

int main(int argc, char** argv)
{
    Options options;
    CLI::App app{"", "sg-rays"};
    sg::apps::describe_tool(
        app,
        "Writes a ray file (SGRAY001, docs/FORMAT.md) for sg-trace or a script, in one of\n"
        "three modes:\n"
        "  sg-rays camera SCENE.sg -o rays.bin   the camera rays of an image, framed as\n"
        "                                        sg-render frames it\n"
        "  sg-rays random SCENE.sg -o rays.bin   random rays in the scene's box\n"
        "  sg-rays text RAYS.csv -o rays.bin     rays listed in a text or CSV file\n"
        "'sg-rays MODE --help' lists the options of a mode.",
        "camera: one ray per pixel through the pixel's centre, row by row from the top-left\n"
        "  pixel (ray y * width + x is pixel (x, y)): the rays of 'sg-render --spp 1' with the\n"
        "  same --width, --height and camera flags. Without --eye and --look-at the camera\n"
        "  frames the scene so that it fills the image, from above and to the side with --up\n"
        "  up. Directions are unit vectors, t_min 0, t_max infinity.\n"
        "random: --count rays, origins uniform in the box of the scene's triangles, directions\n"
        "  uniform on the unit sphere, t_min 0, t_max infinity. Ray k uses its own PCG32\n"
        "  stream (seed --seed, stream k): three numbers for the origin, two for the\n"
        "  direction; the same seed gives the same rays (sg-bench's incoherent workload).\n"
        "text: one ray per line, 'ox oy oz dx dy dz' or 'ox oy oz dx dy dz t_min t_max'\n"
        "  (t_min 0 and t_max infinity when absent), separated by commas and/or blanks;\n"
        "  inf and nan are allowed. Blank lines and lines starting with # are skipped, and a\n"
        "  first line that does not start with a number is a header. An error names the\n"
        "  line: 'error: rays.csv:3: field 2 'x' is not a number'.\n"
        "The output is written atomically: on failure or an interrupt no output file is left\n"
        "behind.");
    sg::apps::add_output_option(app, options.output,
                                "Output ray file (SGRAY001), written atomically; it may not be "
                                "the input");
    app.add_flag("--json", options.json,
                 "Print one JSON object (docs/STATS_JSON.md) instead of the summary");
    sg::apps::add_log_flags(app, options.log);
    // The options above may also follow the mode and its arguments.
    app.fallthrough();
    // At most one mode; none is refused in the work below, after parsing, so that an unknown
    // mode is named ("not expected: sphere") rather than reported as a missing one.
    app.require_subcommand(0, 1);

    CLI::App* camera = app.add_subcommand("camera", "Camera rays of an image of a .sg scene");
    camera->add_option("SCENE", options.input, "The .sg file (from sg-build)")->required();
    sg::apps::add_count_option(*camera, "--width", options.width, 1, max_side,
                               "Image width in pixels.");
    sg::apps::add_count_option(*camera, "--height", options.height, 1, max_side,
                               "Image height in pixels.");
    sg::apps::add_camera_flags(*camera, options.camera);
    camera->parse_complete_callback([&] { sg::apps::check_full_camera(options.camera); });

    CLI::App* random = app.add_subcommand("random", "Random rays in the box of a .sg scene");
    random->add_option("SCENE", options.input, "The .sg file (from sg-build)")->required();
    sg::apps::add_count_option(*random, "--count", options.count, 1, max_random_rays,
                               "Number of rays.");
    sg::apps::add_count_option(*random, "--seed", options.seed, 0,
                               std::numeric_limits<std::uint64_t>::max(),
                               "Seed of the random streams; the same seed gives the same rays.");

    CLI::App* text = app.add_subcommand("text", "Rays read from a text or CSV file");
    text->add_option("RAYS", options.input, "Text or CSV file, one ray per line")->required();

    return sg::apps::run_tool(app, argc, argv, options.log, [&] {
        if (camera->parsed()) write_rays(options, camera_rays);
        if (random->parsed()) write_rays(options, random_rays);
        if (text->parsed()) write_rays(options, text_rays);
        if (!camera->parsed() && !random->parsed() && !text->parsed())
            throw CLI::RequiredError("a mode: camera, random or text (see --help)");
    });
}
