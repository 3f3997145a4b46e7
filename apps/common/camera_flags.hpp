#pragma once

#include <optional>
#include <string>

#include "cli_common.hpp"
#include "splitgrid/camera.hpp"
#include "splitgrid/mesh.hpp"

#include <CLI/CLI.hpp>

/// The camera flags of the tools that make camera rays (sg-render, sg-rays): one parser, one
/// help text and one automatic framing (sg::frame_mesh), so both tools see a scene the same.
namespace sg::apps {

/// --eye, --look-at, --up and --fov as given; what is absent is framed automatically.
struct CameraFlags {
    std::optional<Vec3f> eye;
    std::optional<Vec3f> look_at;
    std::optional<Vec3f> up;
    float fov_y_degrees = 45.0f;

    /// `up`, or +y when --up was not given.
    [[nodiscard]] Vec3f up_or_default() const noexcept { return up.value_or(Vec3f{0, 1, 0}); }
};

/// Adds --eye, --look-at, --up (each "x,y,z", three finite numbers) and --fov.
void add_camera_flags(CLI::App& app, CameraFlags& flags);

/// Refuses (CLI::ValidationError, a usage error) a camera given in full (--eye and --look-at)
/// that cannot form an image; for a parse-complete callback, before any file is read.
void check_full_camera(const CameraFlags& flags);

/// The camera the flags ask for: sg::frame_mesh(mesh, width / height, --fov, --up), with
/// --eye and --look-at replacing its eye and look-at where given. `automatic` tells whether
/// framing chose either. A camera that cannot form an image is a usage error
/// (CLI::ValidationError), like any other bad flag value.
[[nodiscard]] Camera choose_camera(const CameraFlags& flags, const MeshView& mesh, int width,
                                   int height, bool& automatic);

/// "--eye x,y,z --look-at x,y,z --up x,y,z --fov f": the camera as flags, to adjust from.
[[nodiscard]] std::string camera_as_flags(const Camera& camera);

/// The camera as a JSON object: eye, look_at, up (arrays of 3), fov_y_degrees, automatic.
[[nodiscard]] Json camera_json(const Camera& camera, bool automatic);

}  // namespace sg::apps
