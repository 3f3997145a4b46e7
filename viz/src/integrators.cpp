#include "integrators.hpp"

#include <algorithm>

#include "splitgrid/ray_offset.hpp"

namespace sg::detail {
namespace {

/// The unit geometric normal at a hit, turned against `direction`: the side the ray
/// arrives from, so both sides of a triangle shade alike.
Vec3f facing_normal(const SurfacePoint& at, Vec3f direction) noexcept
{
    const Vec3f n = normalize(at.normal);
    return dot(n, direction) > 0.0f ? n * -1.0f : n;
}

float shade_diffuse(const ShadingContext& context, const Ray& ray, const Hit& hit) noexcept
{
    const Vec3f d = normalize(ray.direction);
    const Vec3f n = facing_normal(surface_point(context.mesh, hit), d);
    const ShadedLighting& light = shaded_lighting;
    return light.ambient + light.headlight * std::max(0.0f, -dot(n, d)) +
           light.key * std::max(0.0f, dot(n, context.key_light));
}

SampleResult shade_ambient_occlusion(const ShadingContext& context, const Ray& ray,
                                     const Hit& hit, Rng& rng) noexcept
{
    const SurfacePoint at = surface_point(context.mesh, hit);
    const Vec3f n = facing_normal(at, ray.direction);
    std::uint32_t open = 0;
    for (std::uint32_t i = 0; i < context.ao_samples; ++i) {
        const float u1 = rng.next_float();
        const float u2 = rng.next_float();
        const Ray probe = spawn_ray(at, cosine_hemisphere(n, u1, u2), context.ao_reach);
        if (!occluded(context.grid, context.mesh, probe)) ++open;
    }
    return {true, static_cast<float>(open) / static_cast<float>(context.ao_samples),
            context.ao_samples};
}

/// Each bounce samples the cosine-weighted hemisphere, whose density cos/pi cancels the
/// Lambertian BRDF's albedo/pi times cos: the path weight is multiplied by the albedo alone.
SampleResult shade_path(const ShadingContext& context, const Ray& camera_ray, const Hit& first,
                        Rng& rng) noexcept
{
    SampleResult result{true, 0.0f, 0};
    float weight = 1.0f;
    Ray ray = camera_ray;
    Hit hit = first;
    for (std::uint32_t reflections = 0;; ++reflections) {
        if (reflections == context.bounces) return result;  // the sky is out of reach
        const SurfacePoint at = surface_point(context.mesh, hit);
        const Vec3f n = facing_normal(at, ray.direction);
        weight *= path_albedo;
        const float u1 = rng.next_float();
        const float u2 = rng.next_float();
        ray = spawn_ray(at, cosine_hemisphere(n, u1, u2));
        ++result.secondary_rays;
        hit = intersect(context.grid, context.mesh, ray);
        if (!hit.is_hit()) {
            result.value = weight * sky_radiance;
            return result;
        }
    }
}

}  // namespace

Vec3f key_light_direction(const Camera& camera) noexcept
{
    const Vec3f f = normalize(camera.look_at - camera.eye);
    const Vec3f r = normalize(cross(f, camera.up));
    const Vec3f u = cross(r, f);
    const ShadedLighting& light = shaded_lighting;
    return normalize(u * light.key_up - r * light.key_left - f * light.key_back);
}

SampleResult shade(const ShadingContext& context, const Ray& ray, const Hit& hit,
                   Rng& rng) noexcept
{
    switch (context.mode) {
    case RenderMode::shaded: return {true, shade_diffuse(context, ray, hit), 0};
    case RenderMode::ambient_occlusion: return shade_ambient_occlusion(context, ray, hit, rng);
    case RenderMode::path: return shade_path(context, ray, hit, rng);
    case RenderMode::heat_cells:
    case RenderMode::heat_triangles: break;
    }
    return {true, 0.0f, 0};
}

}  // namespace sg::detail
