#pragma once

#include "splitgrid/aabb.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/vec3.hpp"

namespace sg {

/// A pinhole camera: the image plane is perpendicular to look_at - eye, `up` tilts it, and
/// fov_y_degrees is the full vertical opening angle. sg-render and sg-bench both generate
/// their primary rays here, so a benchmark's "primary rays" are the rays of a rendered image.
struct Camera {
    Vec3f eye{0.0f, 0.0f, 1.0f};
    Vec3f look_at{0.0f, 0.0f, 0.0f};
    Vec3f up{0.0f, 1.0f, 0.0f};
    float fov_y_degrees = 45.0f;
};

/// Throws ConfigError when the camera cannot form an image: a non-finite vector, eye equal to
/// look_at, `up` parallel to the view direction, or a field of view outside (0, 180).
void validate(const Camera& camera);

/// sg-bench's camera of its primary-ray workloads: it looks at the box centre from the
/// direction (1, 0.6, 1.4) (a three-quarter view from above; +y is up), far enough back that
/// the box's bounding sphere fits the vertical and horizontal field of view for `aspect` =
/// width/height. An empty box frames the unit cube. Kept as it is so that the benchmark's
/// figures stay comparable from one version to the next; it leaves much of the image empty
/// (the sphere is larger than the scene) and ignores the scene's up direction, so sg-render
/// and sg-rays frame with frame_mesh instead.
[[nodiscard]] Camera frame_box(const Aabb& box, float aspect, float fov_y_degrees = 45.0f);

/// The view direction of automatic framing: (1, 0.6, 1.4) normalised, turned by the smallest
/// rotation that takes +y to `up` (the half turn about x when `up` is -y). So the eye is at
/// the same 19-degree elevation above the ground plane (perpendicular to `up`) and the same
/// three-quarter angle for every `up`; with +y up it is the direction of frame_box.
/// Returns the unit vector from the scene towards the eye. Throws ConfigError for an `up`
/// that is zero or not finite.
[[nodiscard]] Vec3f framing_direction(Vec3f up);

/// The automatic camera of sg-render and sg-rays: it looks along -framing_direction(up) with
/// `up` up, and is placed so that the triangles fill the image: every corner of every
/// triangle is inside the image, and the corners' outline, centred in the image, reaches 95%
/// of the way to the edges along its tighter axis (the other 5% is a margin). `aspect` is
/// width/height. Camera::up is `up` as given. A mesh without triangles frames the unit cube.
/// Throws ConfigError for an `up` that is zero or not finite, or a field of view outside
/// (0, 180). Cost: a few passes over the vertices that triangles use.
[[nodiscard]] Camera frame_mesh(const MeshView& mesh, float aspect, float fov_y_degrees = 45.0f,
                                Vec3f up = {0.0f, 1.0f, 0.0f});

/// Pixel-to-ray mapping for one image size: precomputes the camera basis once per image.
class PrimaryRays {
public:
    /// Throws ConfigError for an invalid camera (see validate) or a zero width or height.
    PrimaryRays(const Camera& camera, int width, int height);

    /// The ray through image position (x, y), in pixels from the top-left corner: pixel
    /// (i, j) spans [i, i+1) x [j, j+1), so (i + 0.5, j + 0.5) is its centre. The direction
    /// is normalised; t_min is 0 and t_max infinity.
    [[nodiscard]] Ray ray(float x, float y) const noexcept;

    [[nodiscard]] int width() const noexcept { return width_; }
    [[nodiscard]] int height() const noexcept { return height_; }

private:
    Vec3f eye_;
    Vec3f forward_;   // unit vector towards look_at
    Vec3f right_;     // image +x, scaled by the half-width of the image plane at distance 1
    Vec3f down_;      // image +y (downwards), scaled by the half-height
    int width_;
    int height_;
};

}  // namespace sg
