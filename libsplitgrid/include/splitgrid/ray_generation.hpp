#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/camera.hpp"
#include "splitgrid/ray.hpp"

/// Ray sets made without a scene's hits: the primary rays of an image and random rays in a
/// box. sg-rays writes them to ray files, sg-bench traces them as its "primary" and
/// "incoherent" workloads. Both are made in parallel and do not depend on the thread count.
namespace sg {

/// One ray through each pixel centre (x + 0.5, y + 0.5) of the camera's image, row by row
/// from the top-left pixel: ray y * width + x belongs to pixel (x, y). These are the camera
/// rays of sg-render with one sample per pixel. Normalised directions, t in [0, infinity].
[[nodiscard]] std::vector<Ray> pixel_centre_rays(const PrimaryRays& camera);

/// `count` rays with origins uniform in `box` and directions uniform on the unit sphere,
/// t in [0, infinity]. Ray k draws from its own stream Rng(seed, k) (sampling.hpp, PCG32), in
/// this order: three numbers u in [0, 1) for the origin, lower + u * extent on x, y and z,
/// then two for the direction, uniform_sphere(u1, u2). So ray k is the same whatever `count`
/// is, and the same seed always gives the same rays.
[[nodiscard]] std::vector<Ray> random_rays_in_box(const Aabb& box, std::size_t count,
                                                  std::uint64_t seed);

}  // namespace sg
