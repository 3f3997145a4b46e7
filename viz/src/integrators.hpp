#pragma once

#include <cstdint>

#include "splitgrid/camera.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/sampling.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/traverse.hpp"
#include "splitgrid/viz/render.hpp"

namespace sg::detail {

/// What one camera ray contributes to its pixel.
struct SampleResult {
    bool hit = false;
    float value = 0.0f;                 ///< linear grey value of the surface, when hit
    std::uint32_t secondary_rays = 0;   ///< occlusion or bounce rays traced
};

/// Per-render constants shared by every sample.
struct ShadingContext {
    const SplitGrid& grid;
    MeshView mesh;
    RenderMode mode;
    Vec3f key_light;             ///< unit direction towards the shaded mode's key light
    float ao_reach = 0.0f;       ///< ao_distance in scene units
    std::uint32_t ao_samples = 1;
    std::uint32_t bounces = 0;
};

/// The shaded mode's key light direction for `camera` (ShadedLighting documents it).
[[nodiscard]] Vec3f key_light_direction(const Camera& camera) noexcept;

/// Shades the first hit `hit` of the camera ray `ray` for the context's mode (shaded, ao or
/// path; heat maps need no shading), drawing random numbers from `rng`.
[[nodiscard]] SampleResult shade(const ShadingContext& context, const Ray& ray, const Hit& hit,
                                 Rng& rng) noexcept;

}  // namespace sg::detail
