#include "workloads.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "splitgrid/ray_generation.hpp"
#include "splitgrid/ray_offset.hpp"
#include "splitgrid/sampling.hpp"

namespace sg::bench {
namespace {

Vec3f facing_normal(const SurfacePoint& at, Vec3f direction) noexcept
{
    const Vec3f n = normalize(at.normal);
    return dot(n, direction) > 0.0f ? n * -1.0f : n;
}

// Per image row: the rows are made in parallel and joined in order, so the rays do not
// depend on how the work was split.
template <class MakeRow>
std::vector<Ray> by_rows(int height, const MakeRow& make_row)
{
    std::vector<std::vector<Ray>> rows(static_cast<std::size_t>(height));
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y) rows[static_cast<std::size_t>(y)] = make_row(y);
    });
    std::vector<Ray> all;
    for (const auto& row : rows) all.insert(all.end(), row.begin(), row.end());
    return all;
}

}  // namespace

Camera workload_camera(const MeshView& mesh, const WorkloadSizes& sizes)
{
    return frame_box(bounds(mesh), static_cast<float>(sizes.width) / static_cast<float>(sizes.height));
}

std::vector<Ray> path_rays(const MeshView& mesh, const BenchStructure& reference,
                           const PrimaryRays& camera, std::uint32_t bounces, std::uint32_t seed)
{
    const int width = camera.width();
    return by_rows(camera.height(), [&](int y) {
        std::vector<Ray> row;
        for (int x = 0; x < width; ++x) {
            Rng rng(seed, static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(width) +
                              static_cast<std::uint64_t>(x));
            Ray ray = camera.ray(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
            for (std::uint32_t bounce = 0;; ++bounce) {
                row.push_back(ray);
                if (bounce == bounces) break;
                Hit hit;
                reference.intersect({&ray, 1}, {&hit, 1}, QueryVariant{});
                if (!hit.is_hit()) break;
                const SurfacePoint at = surface_point(mesh, hit);
                const float u1 = rng.next_float();
                const float u2 = rng.next_float();
                ray = spawn_ray(at, cosine_hemisphere(facing_normal(at, ray.direction), u1, u2));
            }
        }
        return row;
    });
}

std::vector<Workload> make_scene_workloads(const MeshView& mesh, const BenchStructure& reference,
                                           const WorkloadSizes& sizes, std::uint32_t seed)
{
    const PrimaryRays camera(workload_camera(mesh, sizes), sizes.width, sizes.height);
    const Aabb box = bounds(mesh);
    const Vec3f centre = (box.lower + box.upper) * 0.5f;
    const float size = std::max({box.extent(0), box.extent(1), box.extent(2), 1e-6f});
    // Above the scene and off to one side, so shadows fall across it.
    const Vec3f light = centre + Vec3f{0.3f * size, 1.5f * size, 0.2f * size};

    std::vector<Workload> out(4);
    out[0].name = "primary";
    out[1].name = "path";
    out[2].name = "incoherent";
    out[3].name = "shadow";
    out[3].any_hit = true;

    out[0].rays = pixel_centre_rays(camera);

    out[1].rays = path_rays(mesh, reference, camera, sizes.bounces, seed);

    // seed + 1 in 32 bits, as this workload has always been seeded.
    out[2].rays = random_rays_in_box(box, sizes.incoherent_rays,
                                     static_cast<std::uint32_t>(seed + 1));

    out[3].rays = by_rows(sizes.height, [&](int y) {
        std::vector<Ray> row;
        for (int x = 0; x < sizes.width; ++x) {
            const Ray primary =
                camera.ray(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
            Hit hit;
            reference.intersect({&primary, 1}, {&hit, 1}, QueryVariant{});
            if (!hit.is_hit()) continue;
            const SurfacePoint at = surface_point(mesh, hit);
            Ray shadow = spawn_ray(at, light - at.position, 1.0f);
            shadow.direction = light - shadow.origin;
            shadow.t_max = 1.0f - 0x1p-10f;  // stop short of the light itself
            row.push_back(shadow);
        }
        return row;
    });
    return out;
}

Mesh closed_sphere(Vec3f centre, float radius, std::size_t min_triangles)
{
    // 2 * segments * (rings - 1) triangles with segments = 2 * rings.
    std::uint32_t rings = 4;
    while (std::size_t{4} * rings * (rings - 1) < min_triangles) ++rings;
    const std::uint32_t segments = 2 * rings;
    Mesh m;
    m.vertices.push_back(centre + Vec3f{0.0f, radius, 0.0f});
    for (std::uint32_t r = 1; r < rings; ++r) {
        const double theta = std::numbers::pi * r / rings;
        for (std::uint32_t s = 0; s < segments; ++s) {
            const double phi = 2.0 * std::numbers::pi * s / segments;
            m.vertices.push_back(
                centre + Vec3f{static_cast<float>(radius * std::sin(theta) * std::cos(phi)),
                               static_cast<float>(radius * std::cos(theta)),
                               static_cast<float>(radius * std::sin(theta) * std::sin(phi))});
        }
    }
    m.vertices.push_back(centre + Vec3f{0.0f, -radius, 0.0f});
    const auto south = static_cast<std::uint32_t>(m.vertices.size() - 1);
    auto ring_vertex = [&](std::uint32_t r, std::uint32_t s) {
        return 1 + (r - 1) * segments + (s % segments);
    };
    for (std::uint32_t s = 0; s < segments; ++s) {
        m.triangles.push_back(Triangle{{0, ring_vertex(1, s + 1), ring_vertex(1, s)}});
        m.triangles.push_back(
            Triangle{{south, ring_vertex(rings - 1, s), ring_vertex(rings - 1, s + 1)}});
    }
    for (std::uint32_t r = 1; r + 1 < rings; ++r)
        for (std::uint32_t s = 0; s < segments; ++s) {
            const std::uint32_t a = ring_vertex(r, s), b = ring_vertex(r, s + 1);
            const std::uint32_t c = ring_vertex(r + 1, s), d = ring_vertex(r + 1, s + 1);
            m.triangles.push_back(Triangle{{a, b, d}});
            m.triangles.push_back(Triangle{{a, d, c}});
        }
    return m;
}

std::vector<Ray> interior_rays(const Mesh& sphere, Vec3f centre, float radius, std::size_t count,
                               std::uint32_t seed)
{
    std::vector<Ray> rays(count);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t k = r.begin(); k < r.end(); ++k) {
            Rng rng(seed, k);
            // A point well inside (at most half the radius from the centre), so rounding of
            // the origin never puts it outside.
            Vec3f o;
            do {
                for (int a = 0; a < 3; ++a) o[a] = 2.0f * rng.next_float() - 1.0f;
            } while (dot(o, o) > 1.0f);
            o = centre + o * (0.5f * radius);
            Vec3f target;
            const std::size_t kind = interior_ray_kind(k);
            const Triangle& t = sphere.triangles[rng.next_u32() % sphere.triangles.size()];
            if (kind == 1) {
                target = sphere.vertices[t.v[rng.next_u32() % 3]];
            } else if (kind == 2) {
                const std::uint32_t e = rng.next_u32() % 3;
                target = (sphere.vertices[t.v[e]] + sphere.vertices[t.v[(e + 1) % 3]]) * 0.5f;
            } else {
                const float u1 = rng.next_float();
                const float u2 = rng.next_float();
                target = o + uniform_sphere(u1, u2);
            }
            rays[k] = Ray{o, target - o};
        }
    });
    return rays;
}

}  // namespace sg::bench
