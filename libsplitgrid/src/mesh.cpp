#include "splitgrid/mesh.hpp"

#include <string>

#include "splitgrid/error.hpp"
#include "splitgrid/ray.hpp"

namespace sg {

bool is_valid(const Ray& ray) noexcept
{
    const Vec3f d = ray.direction;
    const bool nonzero = std::abs(d.x) >= std::numeric_limits<float>::min() ||
                         std::abs(d.y) >= std::numeric_limits<float>::min() ||
                         std::abs(d.z) >= std::numeric_limits<float>::min();
    return is_finite(ray.origin) && is_finite(d) && nonzero && std::isfinite(ray.t_min) &&
           !std::isnan(ray.t_max) && ray.t_min <= ray.t_max;
}

Aabb bounds(const MeshView& mesh) noexcept
{
    Aabb box;
    for (const Triangle& t : mesh.triangles)
        for (std::uint32_t i : t.v) box.extend(mesh.vertices[i]);
    return box;
}

void check_mesh(const MeshView& mesh)
{
    const std::size_t nv = mesh.vertices.size();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (std::uint32_t i : mesh.triangles[t].v) {
            if (i >= nv)
                throw InputError("triangle " + std::to_string(t) + " has vertex index " +
                                 std::to_string(i) + " but the mesh has " + std::to_string(nv) +
                                 " vertices");
            if (!is_finite(mesh.vertices[i]))
                throw InputError("vertex " + std::to_string(i) + " (of triangle " +
                                 std::to_string(t) + ") has a NaN or infinite coordinate");
        }
    }
}

CleanReport clean_mesh(Mesh& mesh)
{
    CleanReport report;
    const std::size_t nv = mesh.vertices.size();
    std::size_t kept = 0;
    for (const Triangle& t : mesh.triangles) {
        if (t.v[0] >= nv || t.v[1] >= nv || t.v[2] >= nv) {
            ++report.bad_index_triangles;
            continue;
        }
        const Vec3f a = mesh.vertices[t.v[0]];
        const Vec3f b = mesh.vertices[t.v[1]];
        const Vec3f c = mesh.vertices[t.v[2]];
        if (!is_finite(a) || !is_finite(b) || !is_finite(c)) {
            ++report.nonfinite_triangles;
            continue;
        }
        // Edge vectors and their cross product in double: exact enough that only truly
        // collinear corners give zero.
        const double e1x = double(b.x) - a.x, e1y = double(b.y) - a.y, e1z = double(b.z) - a.z;
        const double e2x = double(c.x) - a.x, e2y = double(c.y) - a.y, e2z = double(c.z) - a.z;
        const double nx = e1y * e2z - e1z * e2y;
        const double ny = e1z * e2x - e1x * e2z;
        const double nz = e1x * e2y - e1y * e2x;
        if (nx == 0.0 && ny == 0.0 && nz == 0.0) {
            ++report.degenerate_triangles;
            continue;
        }
        mesh.triangles[kept++] = t;
    }
    mesh.triangles.resize(kept);
    return report;
}

}  // namespace sg
