// The reference answers of brute_force.hpp: every triangle, in id order, in plain scalar code
// that shares nothing with the traversal kernels but the watertight test itself.
#include "splitgrid/brute_force.hpp"

#include <cmath>
#include <limits>

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

}  // namespace sg
