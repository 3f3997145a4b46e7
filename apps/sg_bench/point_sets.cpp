#include "point_sets.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "splitgrid/brute_force.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/closed_shapes.hpp"
#include "splitgrid/occupancy.hpp"
#include "splitgrid/ray_generation.hpp"
#include "splitgrid/sampling.hpp"

namespace sg::bench {
namespace {

double diagonal(const Aabb& box) noexcept
{
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) sum += double(box.extent(k)) * box.extent(k);
    return std::sqrt(sum);
}

// The six directions of an axis, each way, and the eight diagonals, as unit vectors.
std::vector<Vec3f> axes_and_diagonals()
{
    std::vector<Vec3f> directions;
    for (int k = 0; k < 3; ++k)
        for (const float s : {1.0f, -1.0f}) {
            Vec3f d{};
            d[k] = s;
            directions.push_back(d);
        }
    for (const float x : {1.0f, -1.0f})
        for (const float y : {1.0f, -1.0f})
            for (const float z : {1.0f, -1.0f}) directions.push_back(normalize(Vec3f{x, y, z}));
    return directions;
}

// Every vertex of `mesh`, and the midpoint of every edge of every triangle (an edge shared by
// two triangles comes twice, at the same point).
std::vector<Vec3f> vertices_and_edge_midpoints(const Mesh& mesh)
{
    std::vector<Vec3f> targets = mesh.vertices;
    const MeshView view = mesh.view();
    for (std::uint32_t t = 0; t < view.triangle_count(); ++t)
        for (int e = 0; e < 3; ++e)
            targets.push_back((view.vertex(t, e) + view.vertex(t, (e + 1) % 3)) * 0.5f);
    std::sort(targets.begin(), targets.end(), [](Vec3f a, Vec3f b) {
        return a.x < b.x || (a.x == b.x && (a.y < b.y || (a.y == b.y && a.z < b.z)));
    });
    targets.erase(std::unique(targets.begin(), targets.end(),
                              [](Vec3f a, Vec3f b) {
                                  return a.x == b.x && a.y == b.y && a.z == b.z;
                              }),
                  targets.end());
    return targets;
}

// The root box every structure of ours is built in (builder.hpp).
Aabb structure_box(const MeshView& mesh) noexcept
{
    const Aabb scene = bounds(mesh);
    return padded_root_box(scene, boundary_pad(scene));
}

bool strictly_inside(Vec3f p, const Aabb& box) noexcept
{
    for (int k = 0; k < 3; ++k)
        if (!(p[k] > box.lower[k] && p[k] < box.upper[k])) return false;
    return true;
}

InsideSet decided_by_winding_number(std::string name, std::string scene, const MeshView& mesh,
                                    std::vector<Vec3f> points)
{
    InsideSet set{std::move(name), std::move(scene), "winding number", std::move(points), {}};
    set.expected.resize(set.points.size());
    tbb::parallel_for(std::size_t{0}, set.points.size(), [&](std::size_t k) {
        set.expected[k] = side_by_winding_number(mesh, set.points[k]);
    });
    return set;
}

}  // namespace

std::vector<Vec3f> random_points(const Aabb& box, std::size_t count, std::uint32_t seed)
{
    std::vector<Vec3f> points;
    points.reserve(count);
    for (const Ray& r : random_rays_in_box(box, count, seed)) points.push_back(r.origin);
    return points;
}

std::vector<Vec3f> near_points(const MeshView& mesh, std::size_t count, std::uint32_t seed)
{
    const double scale = diagonal(bounds(mesh));
    std::vector<Vec3f> points(count);
    for (std::size_t k = 0; k < count; ++k) {
        Rng rng(seed, k);
        const auto t = static_cast<std::uint32_t>(rng.next_u32() % mesh.triangle_count());
        float u = rng.next_float(), v = rng.next_float();
        if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
        const Vec3f a = mesh.vertex(t, 0), b = mesh.vertex(t, 1), c = mesh.vertex(t, 2);
        const Vec3f on = a + (b - a) * u + (c - a) * v;
        const double distance = scale * std::pow(10.0, -5.0 + 2.0 * rng.next_float());
        const float side = rng.next_u32() % 2 == 0 ? 1.0f : -1.0f;
        points[k] = on + normalize(cross(b - a, c - a)) * (side * static_cast<float>(distance));
    }
    return points;
}

double occupancy_band(const Aabb& box) noexcept
{
    double m = 0.0;
    for (int k = 0; k < 3; ++k)
        m = std::max({m, std::abs(double(box.lower[k])), std::abs(double(box.upper[k]))});
    return std::ldexp(m, -17);
}

Side side_by_winding_number(const MeshView& mesh, Vec3f point) noexcept
{
    const double w = std::abs(winding_number(mesh, Vec3d(point)));
    if (w < 1e-3) return Side::outside;
    if (std::abs(w - 1.0) < 1e-3) return Side::inside;
    return Side::undecided;
}

std::vector<Vec3f> aimed_points(const std::vector<Vec3f>& targets,
                                const std::vector<float>& distances, const Aabb& box)
{
    std::vector<Vec3f> points;
    for (const Vec3f target : targets)
        for (const float s : distances)
            for (int axis = 0; axis < 3; ++axis)
                for (const float sign : {1.0f, -1.0f}) {
                    // The direction occupancy_ray takes towards the face (axis, sign).
                    Vec3f d{};
                    d[axis] = sign;
                    d[(axis + 1) % 3] = 0x1p-5f;
                    d[(axis + 2) % 3] = 0x1p-7f;
                    const Vec3f p = target - d * s;
                    if (!strictly_inside(p, box)) continue;
                    const Ray ray = occupancy_ray(p, box, 0, 1);
                    if (ray.direction.x == d.x && ray.direction.y == d.y && ray.direction.z == d.z)
                        points.push_back(p);
                }
    return points;
}

Mesh inside_test_cube() { return tessellated_cube(8); }

Mesh inside_test_icosphere() { return icosphere(2, 1.0f); }

std::vector<InsideSet> cube_inside_sets(const Mesh& cube)
{
    const Aabb box = bounds(cube.view());
    const float n = box.upper.x;
    auto decide = [&](InsideSet& set) {
        for (const Vec3f p : set.points) {
            const auto in = [&](float c) { return c > 0.0f && c < n; };
            set.expected.push_back(in(p.x) && in(p.y) && in(p.z) ? Side::inside : Side::outside);
        }
    };
    std::vector<float> coords{-0.125f, 0.125f, n - 0.125f, n + 0.125f};
    for (float c = 0.5f; c < n; c += 0.5f) coords.push_back(c);
    InsideSet grid{"cube_grid", "tessellated_cube", "analytic", {}, {}};
    for (const float x : coords)
        for (const float y : coords)
            for (const float z : coords) grid.points.push_back({x, y, z});
    decide(grid);
    InsideSet aimed{"cube_aimed",
                    "tessellated_cube",
                    "analytic",
                    aimed_points(vertices_and_edge_midpoints(cube), {0.25f, 1.0f, 2.0f},
                                 structure_box(cube.view())),
                    {}};
    decide(aimed);
    return {grid, aimed};
}

std::vector<InsideSet> icosphere_inside_sets(const Mesh& sphere)
{
    std::vector<Vec3f> grid;
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            for (int k = 0; k < 6; ++k)
                grid.push_back(
                    {-1.25f + 0.5f * float(i), -1.25f + 0.5f * float(j), -1.25f + 0.5f * float(k)});
    grid.push_back({0.0f, 0.0f, 0.0f});
    for (const Vec3f v : sphere.vertices) {
        grid.push_back(v * 0.98f);
        grid.push_back(v * 1.02f);
    }
    const MeshView view = sphere.view();
    return {decided_by_winding_number("icosphere_grid", "icosphere", view, std::move(grid)),
            decided_by_winding_number("icosphere_aimed", "icosphere", view,
                                      aimed_points(vertices_and_edge_midpoints(sphere),
                                                   {0.125f, 0.25f}, structure_box(view)))};
}

InsideSet near_vertex_set(const MeshView& mesh, const std::string& scene, std::size_t vertices)
{
    const double scale = diagonal(bounds(mesh));
    const std::vector<float> distances{static_cast<float>(1e-3 * scale),
                                       static_cast<float>(1e-5 * scale)};
    std::vector<Vec3f> targets;
    const std::size_t n = mesh.vertices.size();
    for (std::size_t k = 0; k < std::min(vertices, n); ++k)
        targets.push_back(mesh.vertices[k * n / std::min(vertices, n)]);
    std::vector<Vec3f> points;
    for (const Vec3f v : targets)
        for (const Vec3f d : axes_and_diagonals())
            for (const float s : distances) points.push_back(v + d * s);
    const std::vector<Vec3f> aimed = aimed_points(targets, distances, structure_box(mesh));
    points.insert(points.end(), aimed.begin(), aimed.end());
    return decided_by_winding_number(scene + "_near_vertices", scene, mesh, std::move(points));
}

}  // namespace sg::bench
