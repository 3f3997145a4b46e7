// The reference answers of brute_force.hpp: every triangle, in id order, in plain scalar code
// that shares nothing with the traversal kernels but the watertight test itself.
#include "splitgrid/brute_force.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "splitgrid/ray_triangle.hpp"

namespace sg {
namespace {

// Direction components below FLT_MIN count as zero (ray.hpp).
Vec3f flush_denormals(Vec3f d) noexcept
{
    for (int k = 0; k < 3; ++k)
        if (std::abs(d[k]) < std::numeric_limits<float>::min()) d[k] = 0.0f;
    return d;
}

template <bool any_hit>
bool brute_force(const MeshView& mesh, const Ray& ray, Hit& hit) noexcept
{
    if (!is_valid(ray)) return false;
    Ray flushed = ray;
    flushed.direction = flush_denormals(ray.direction);
    const WatertightRay wr(flushed);
    bool found = false;
    float best = ray.t_max;
    for (std::uint32_t tri = 0; tri < mesh.triangle_count(); ++tri) {
        float t, u, v;
        if (!intersect_triangle(wr, mesh.vertex(tri, 0), mesh.vertex(tri, 1), mesh.vertex(tri, 2),
                                ray.t_min, best, t, u, v))
            continue;
        if (found && !(t < best)) continue;
        found = true;
        best = t;
        hit = Hit{t, tri, u, v};
        if constexpr (any_hit) return true;
    }
    return found;
}

}  // namespace

Hit intersect_brute_force(const MeshView& mesh, const Ray& ray) noexcept
{
    Hit hit;
    hit.t = ray.t_max;
    Hit found;
    return brute_force<false>(mesh, ray, found) ? found : hit;
}

bool occluded_brute_force(const MeshView& mesh, const Ray& ray) noexcept
{
    Hit unused;
    return brute_force<true>(mesh, ray, unused);
}

std::int32_t count_intersections_brute_force(const MeshView& mesh, const Ray& ray) noexcept
{
    if (!is_valid(ray)) return 0;
    Ray flushed = ray;
    flushed.direction = flush_denormals(ray.direction);
    const WatertightRay wr(flushed);
    std::int32_t count = 0;
    for (std::uint32_t tri = 0; tri < mesh.triangle_count(); ++tri) {
        float t, u, v;
        count += intersect_triangle(wr, mesh.vertex(tri, 0), mesh.vertex(tri, 1),
                                    mesh.vertex(tri, 2), ray.t_min, ray.t_max, t, u, v)
                     ? 1
                     : 0;
    }
    return count;
}

double winding_number(const MeshView& mesh, Vec3d point) noexcept
{
    const auto norm = [](Vec3d a) { return std::sqrt(dot(a, a)); };
    double sum = 0.0;
    for (std::uint32_t tri = 0; tri < mesh.triangle_count(); ++tri) {
        const Vec3d a = Vec3d(mesh.vertex(tri, 0)) - point;
        const Vec3d b = Vec3d(mesh.vertex(tri, 1)) - point;
        const Vec3d c = Vec3d(mesh.vertex(tri, 2)) - point;
        const double la = norm(a), lb = norm(b), lc = norm(c);
        const double numerator = dot(a, cross(b, c));
        const double denominator = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
        sum += 2.0 * std::atan2(numerator, denominator);
    }
    return sum / (4.0 * std::numbers::pi);
}

}  // namespace sg
