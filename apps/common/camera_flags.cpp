#include "camera_flags.hpp"

#include <charconv>
#include <cmath>
#include <system_error>

#include "splitgrid/error.hpp"

#include <spdlog/fmt/fmt.h>

namespace sg::apps {
namespace {

/// "x,y,z" with three finite numbers, or nothing.
std::optional<Vec3f> parse_vec3(const std::string& text)
{
    Vec3f v;
    const char* p = text.data();
    const char* end = text.data() + text.size();
    for (int axis = 0; axis < 3; ++axis) {
        const auto [next, ec] = std::from_chars(p, end, v[axis]);
        if (ec != std::errc{} || !std::isfinite(v[axis])) return std::nullopt;
        p = next;
        if (axis < 2) {
            if (p == end || *p != ',') return std::nullopt;
            ++p;
        }
    }
    if (p != end) return std::nullopt;
    return v;
}

/// Adds a "x,y,z" option whose value lands in `target`.
void add_vec3_option(CLI::App& app, const std::string& name, std::optional<Vec3f>& target,
                     const std::string& description)
{
    app.add_option_function<std::string>(
           name, [&target](const std::string& text) { target = parse_vec3(text); }, description)
        ->type_name("X,Y,Z")
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                return parse_vec3(text) ? std::string{}
                                        : text + " is not three finite numbers x,y,z";
            },
            "", ""));
}

std::string format_vec3(Vec3f v) { return fmt::format("{},{},{}", v.x, v.y, v.z); }

void validate_as_flags(const Camera& camera)
{
    try {
        validate(camera);
    } catch (const ConfigError& e) {
        throw CLI::ValidationError("--eye/--look-at/--up/--fov", e.what());
    }
}

}  // namespace

void add_camera_flags(CLI::App& app, CameraFlags& flags)
{
    const std::string group = "Camera (default: automatic framing)";
    add_vec3_option(app, "--eye", flags.eye,
                    "Camera position: automatic framing places the eye so that the scene fills "
                    "the image, seen from 19 degrees above the ground plane (perpendicular to "
                    "--up), three-quarter on. Default automatic framing.");
    add_vec3_option(app, "--look-at", flags.look_at,
                    "Point at the image centre. Default the centre of the scene's outline as "
                    "automatic framing sees it (near the centre of its box).");
    add_vec3_option(app, "--up", flags.up,
                    "Direction that points up in the image, and the scene's up for automatic "
                    "framing (0,0,1 for a z-up scene); must not be parallel to the view. "
                    "Default 0,1,0.");
    app.add_option("--fov", flags.fov_y_degrees,
                   help_text("Vertical field of view in degrees.", "(0, 180)",
                             number_text(flags.fov_y_degrees)))
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                float value = 0.0f;
                const char* end = text.data() + text.size();
                const auto [ptr, ec] = std::from_chars(text.data(), end, value);
                return ec == std::errc{} && ptr == end && value > 0.0f && value < 180.0f
                           ? std::string{}
                           : text + " is not a number in (0, 180)";
            },
            "", ""));
    for (const char* name : {"--eye", "--look-at", "--up", "--fov"})
        app.get_option(name)->group(group);
}

void check_full_camera(const CameraFlags& flags)
{
    if (flags.eye && flags.look_at)
        validate_as_flags(
            Camera{*flags.eye, *flags.look_at, flags.up_or_default(), flags.fov_y_degrees});
}

Camera choose_camera(const CameraFlags& flags, const MeshView& mesh, int width, int height,
                     bool& automatic)
{
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    Camera camera;
    try {
        camera = frame_mesh(mesh, aspect, flags.fov_y_degrees, flags.up_or_default());
    } catch (const ConfigError& e) {
        throw CLI::ValidationError("--up/--fov", e.what());
    }
    automatic = !flags.eye || !flags.look_at;
    if (flags.eye) camera.eye = *flags.eye;
    if (flags.look_at) camera.look_at = *flags.look_at;
    validate_as_flags(camera);
    return camera;
}

std::string camera_as_flags(const Camera& camera)
{
    return fmt::format("--eye {} --look-at {} --up {} --fov {}", format_vec3(camera.eye),
                       format_vec3(camera.look_at), format_vec3(camera.up),
                       camera.fov_y_degrees);
}

Json camera_json(const Camera& camera, bool automatic)
{
    return {{"eye", {camera.eye.x, camera.eye.y, camera.eye.z}},
            {"look_at", {camera.look_at.x, camera.look_at.y, camera.look_at.z}},
            {"up", {camera.up.x, camera.up.y, camera.up.z}},
            {"fov_y_degrees", camera.fov_y_degrees},
            {"automatic", automatic}};
}

}  // namespace sg::apps
