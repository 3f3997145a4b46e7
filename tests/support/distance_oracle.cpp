#include "support/distance_oracle.hpp"

#include <cmath>
#include <limits>

namespace sg::test {
namespace {

using V = std::array<double, 3>;
V sub(V a, V b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V add(V a, V b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
V mul(V a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(V a, V b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V of(Vec3f v) { return {v.x, v.y, v.z}; }

}  // namespace

std::array<double, 3> closest_point_on_triangle(V p, V a, V b, V c)
{
    const V ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return a;
    const V bp = sub(p, b);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return add(a, mul(ab, d1 / (d1 - d3)));
    const V cp = sub(p, c);
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return add(a, mul(ac, d2 / (d2 - d6)));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
        return add(b, mul(sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
    const double denom = 1.0 / (va + vb + vc);
    return add(a, add(mul(ab, vb * denom), mul(ac, vc * denom)));
}

double triangle_distance(const MeshView& mesh, std::uint32_t tri, Vec3f p)
{
    const V q = of(p);
    const V c = closest_point_on_triangle(q, of(mesh.vertex(tri, 0)), of(mesh.vertex(tri, 1)),
                                          of(mesh.vertex(tri, 2)));
    const V d = sub(q, c);
    return std::sqrt(dot(d, d));
}

DistanceOracle distance_oracle(const MeshView& mesh, Vec3f p, double tolerance)
{
    std::vector<double> distances(mesh.triangle_count());
    double best = std::numeric_limits<double>::infinity();
    for (std::uint32_t tri = 0; tri < mesh.triangle_count(); ++tri) {
        distances[tri] = triangle_distance(mesh, tri, p);
        best = std::min(best, distances[tri]);
    }
    DistanceOracle out;
    out.distance = best;
    for (std::uint32_t tri = 0; tri < mesh.triangle_count(); ++tri)
        if (distances[tri] <= best + tolerance) out.nearest.push_back(tri);
    return out;
}

}  // namespace sg::test
