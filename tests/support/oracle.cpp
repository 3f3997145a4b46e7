#include "support/oracle.hpp"

#include <cstdio>

#include "splitgrid/builder.hpp"
#include "splitgrid/traverse.hpp"
#include "splitgrid/validate.hpp"

namespace sg::test {

SplitGrid build_checked(const Mesh& mesh, const BuildConfig& config)
{
    SplitGrid grid = build_split_grid(mesh.view(), config);
    check_invariants(grid);
    check_coverage(grid, mesh.view());
    return grid;
}

bool same_closest_hit(const Hit& expected, const Hit& actual) noexcept
{
    if (expected.is_hit() != actual.is_hit()) return false;
    if (!expected.is_hit()) return true;
    return expected.t == actual.t;
}

OracleReport compare_with_brute_force(const SplitGrid& grid, const MeshView& mesh,
                                      const std::vector<Ray>& rays)
{
    return compare_with_brute_force(
        mesh, rays, [&](const Ray& r) { return intersect(grid, mesh, r); },
        [&](const Ray& r) { return occluded(grid, mesh, r); });
}

OracleReport compare_with_brute_force(const MeshView& mesh, const std::vector<Ray>& rays,
                                      const ClosestHitQuery& closest, const AnyHitQuery& any)
{
    return compare_with_oracle(
        rays, closest, any, [&](const Ray& r) { return intersect_brute_force(mesh, r); },
        [&](const Ray& r) { return occluded_brute_force(mesh, r); });
}

OracleReport compare_with_oracle(const std::vector<Ray>& rays, const ClosestHitQuery& closest,
                                 const AnyHitQuery& any, const ClosestHitQuery& expected_closest,
                                 const AnyHitQuery& expected_any)
{
    OracleReport report;
    for (const Ray& ray : rays) {
        ++report.rays;
        const Hit expected = expected_closest(ray);
        const Hit actual = closest(ray);
        if (expected.is_hit()) ++report.hits;
        const bool closest_ok = same_closest_hit(expected, actual);
        const bool any_ok = any(ray) == expected_any(ray);
        if (!closest_ok) ++report.closest_disagreements;
        if (!any_ok) ++report.any_hit_disagreements;
        if ((!closest_ok || !any_ok) && report.first_failure.empty()) {
            char buf[512];
            std::snprintf(buf, sizeof buf,
                          "ray o=(%.9g %.9g %.9g) d=(%.9g %.9g %.9g) t=[%.9g %.9g]: expected "
                          "tri %u t=%.9g, got tri %u t=%.9g; any-hit %s",
                          double(ray.origin.x), double(ray.origin.y), double(ray.origin.z),
                          double(ray.direction.x), double(ray.direction.y),
                          double(ray.direction.z), double(ray.t_min), double(ray.t_max),
                          expected.triangle, double(expected.t), actual.triangle,
                          double(actual.t), any_ok ? "agrees" : "disagrees");
            report.first_failure = buf;
        }
    }
    return report;
}

}  // namespace sg::test
