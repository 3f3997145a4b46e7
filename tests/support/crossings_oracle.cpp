#include "support/crossings_oracle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "splitgrid/ray_triangle.hpp"

namespace sg::test {
namespace {

Vec3d sub(Vec3d a, Vec3d b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(Vec3d a, Vec3d b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3d cross(Vec3d a, Vec3d b)
{
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3d to_double(Vec3f v) { return {v.x, v.y, v.z}; }

}  // namespace

std::size_t count_crossings_double(const MeshView& mesh, Vec3d origin, Vec3d dir, double t_min)
{
    std::size_t count = 0;
    for (std::uint32_t tri = 0; tri < mesh.triangle_count(); ++tri) {
        const Vec3d a = to_double(mesh.vertex(tri, 0));
        const Vec3d e1 = sub(to_double(mesh.vertex(tri, 1)), a);
        const Vec3d e2 = sub(to_double(mesh.vertex(tri, 2)), a);
        const Vec3d p = cross(dir, e2);
        const double det = dot(e1, p);
        if (det == 0.0) continue;
        const Vec3d s = sub(origin, a);
        const double u = dot(s, p) / det;
        const Vec3d q = cross(s, e1);
        const double v = dot(dir, q) / det;
        const double t = dot(e2, q) / det;
        if (u > 0.0 && v > 0.0 && u + v < 1.0 && t > t_min) ++count;
    }
    return count;
}

Vec3d moved_origin(const Ray& ray, double e)
{
    const WatertightRay frame(ray);
    Vec3d o = to_double(ray.origin);
    o[static_cast<std::size_t>(frame.kx)] += e;
    o[static_cast<std::size_t>(frame.ky)] += e * e;
    return o;
}

ConvexSide convex_side(const MeshView& mesh, Vec3f point)
{
    ConvexSide side{true, std::numeric_limits<double>::infinity()};
    const Vec3d p = to_double(point);
    for (std::uint32_t tri = 0; tri < mesh.triangle_count(); ++tri) {
        const Vec3d a = to_double(mesh.vertex(tri, 0));
        const Vec3d n = cross(sub(to_double(mesh.vertex(tri, 1)), a),
                              sub(to_double(mesh.vertex(tri, 2)), a));
        const double distance = dot(n, sub(p, a)) / std::sqrt(dot(n, n));
        side.inside = side.inside && distance < 0.0;
        side.nearest_plane = std::min(side.nearest_plane, std::abs(distance));
    }
    return side;
}

std::vector<Hit> all_hits_brute_force(const MeshView& mesh, const Ray& ray)
{
    std::vector<Hit> hits;
    if (!is_valid(ray)) return hits;
    Ray flushed = ray;
    for (int k = 0; k < 3; ++k)
        if (std::abs(flushed.direction[k]) < std::numeric_limits<float>::min())
            flushed.direction[k] = 0.0f;
    const WatertightRay wr(flushed);
    for (std::uint32_t tri = 0; tri < mesh.triangle_count(); ++tri) {
        float t, u, v;
        if (intersect_triangle(wr, mesh.vertex(tri, 0), mesh.vertex(tri, 1), mesh.vertex(tri, 2),
                               ray.t_min, ray.t_max, t, u, v))
            hits.push_back(Hit{t, tri, u, v});
    }
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
        return a.t < b.t || (a.t == b.t && a.triangle < b.triangle);
    });
    return hits;
}

}  // namespace sg::test
