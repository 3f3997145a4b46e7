#include "support/random_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace sg::test {
namespace {

Vec3f uniform_in(std::mt19937& rng, const Aabb& box)
{
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Vec3f p;
    for (int k = 0; k < 3; ++k) p[k] = box.lower[k] + u(rng) * box.extent(k);
    return p;
}

Vec3f uniform_direction(std::mt19937& rng)
{
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::uniform_real_distribution<float> phi(0.0f, 2.0f * std::numbers::pi_v<float>);
    const float z = u(rng);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float p = phi(rng);
    return {r * std::cos(p), r * std::sin(p), z};
}

}  // namespace

Mesh random_triangles(std::uint32_t seed, std::size_t count, const Aabb& box, float max_edge)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> e(-max_edge, max_edge);
    Mesh mesh;
    mesh.vertices.reserve(3 * count);
    mesh.triangles.reserve(count);
    for (std::size_t t = 0; t < count; ++t) {
        const Vec3f a = uniform_in(rng, box);
        const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
        mesh.vertices.push_back(a);
        mesh.vertices.push_back(a + Vec3f{e(rng), e(rng), e(rng)});
        mesh.vertices.push_back(a + Vec3f{e(rng), e(rng), e(rng)});
        mesh.triangles.push_back(Triangle{{base, base + 1, base + 2}});
    }
    return mesh;
}

Mesh uv_sphere(Vec3f center, float radius, std::uint32_t rings, std::uint32_t segments)
{
    Mesh mesh;
    const double pi = std::numbers::pi;
    mesh.vertices.push_back(center + Vec3f{0.0f, 0.0f, radius});  // north pole
    for (std::uint32_t r = 1; r < rings; ++r) {
        const double theta = pi * r / rings;
        for (std::uint32_t s = 0; s < segments; ++s) {
            const double phi = 2.0 * pi * s / segments;
            mesh.vertices.push_back(
                center + Vec3f{static_cast<float>(radius * std::sin(theta) * std::cos(phi)),
                               static_cast<float>(radius * std::sin(theta) * std::sin(phi)),
                               static_cast<float>(radius * std::cos(theta))});
        }
    }
    mesh.vertices.push_back(center + Vec3f{0.0f, 0.0f, -radius});  // south pole
    const auto south = static_cast<std::uint32_t>(mesh.vertices.size() - 1);
    auto ring_vertex = [&](std::uint32_t r, std::uint32_t s) {
        return 1 + (r - 1) * segments + (s % segments);
    };
    for (std::uint32_t s = 0; s < segments; ++s)
        mesh.triangles.push_back(Triangle{{0, ring_vertex(1, s), ring_vertex(1, s + 1)}});
    for (std::uint32_t r = 1; r + 1 < rings; ++r)
        for (std::uint32_t s = 0; s < segments; ++s) {
            const std::uint32_t a = ring_vertex(r, s), b = ring_vertex(r, s + 1);
            const std::uint32_t c = ring_vertex(r + 1, s), d = ring_vertex(r + 1, s + 1);
            mesh.triangles.push_back(Triangle{{a, c, b}});
            mesh.triangles.push_back(Triangle{{b, c, d}});
        }
    for (std::uint32_t s = 0; s < segments; ++s)
        mesh.triangles.push_back(
            Triangle{{ring_vertex(rings - 1, s), south, ring_vertex(rings - 1, s + 1)}});
    return mesh;
}

Mesh axis_plane(int axis, float offset, std::uint32_t n)
{
    Mesh mesh;
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (std::uint32_t i = 0; i <= n; ++i)
        for (std::uint32_t j = 0; j <= n; ++j) {
            Vec3f p;
            p[axis] = offset;
            p[a1] = static_cast<float>(i);
            p[a2] = static_cast<float>(j);
            mesh.vertices.push_back(p);
        }
    for (std::uint32_t i = 0; i < n; ++i)
        for (std::uint32_t j = 0; j < n; ++j) {
            const std::uint32_t a = i * (n + 1) + j, b = a + 1, c = a + n + 1, d = c + 1;
            mesh.triangles.push_back(Triangle{{a, b, d}});
            mesh.triangles.push_back(Triangle{{a, d, c}});
        }
    return mesh;
}

void append(Mesh& a, const Mesh& b)
{
    const auto base = static_cast<std::uint32_t>(a.vertices.size());
    a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
    for (Triangle t : b.triangles) {
        for (std::uint32_t& i : t.v) i += base;
        a.triangles.push_back(t);
    }
}

std::vector<Ray> random_rays(std::uint32_t seed, std::size_t count, const Aabb& box)
{
    std::mt19937 rng(seed);
    std::vector<Ray> rays(count);
    for (Ray& r : rays) {
        r.origin = uniform_in(rng, box);
        r.direction = uniform_direction(rng);
    }
    return rays;
}

std::vector<Ray> rays_at_triangles(std::uint32_t seed, std::size_t count, const Aabb& box,
                                   const MeshView& mesh)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> pick(0, mesh.triangle_count() - 1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Ray> rays(count);
    for (Ray& r : rays) {
        const std::uint32_t t = static_cast<std::uint32_t>(pick(rng));
        float b1 = u(rng), b2 = u(rng);
        if (b1 + b2 > 1.0f) {
            b1 = 1.0f - b1;
            b2 = 1.0f - b2;
        }
        const Vec3f target = mesh.vertex(t, 0) * (1.0f - b1 - b2) + mesh.vertex(t, 1) * b1 +
                             mesh.vertex(t, 2) * b2;
        r.origin = uniform_in(rng, box);
        r.direction = target - r.origin;
    }
    return rays;
}

std::vector<Ray> float_range_edge_rays(std::uint32_t seed, std::size_t count, const Aabb& box,
                                       const MeshView& mesh)
{
    constexpr float inf = std::numeric_limits<float>::infinity();
    constexpr float big = std::numeric_limits<float>::max();
    constexpr float tiny = std::numeric_limits<float>::min();
    std::vector<Ray> rays;
    const std::vector<Ray> aimed = rays_at_triangles(seed, count, box, mesh);
    for (std::size_t k = 0; k < aimed.size(); ++k) {
        const Ray& a = aimed[k];
        const Vec3f unit = normalize(a.direction);
        for (const float scale : {1e30f, 1e-30f, tiny * 4.0f, big / 4.0f}) {
            Ray r = a;
            r.direction = unit * scale;
            rays.push_back(r);
        }
        Ray thin = a;
        thin.direction[static_cast<int>(k % 3)] = (k / 3) % 2 == 0 ? 8.0f * tiny : -8.0f * tiny;
        rays.push_back(thin);
        Ray far = a;
        far.origin = a.origin - unit * 1e30f;
        far.direction = unit;
        rays.push_back(far);
        Ray window = a;
        window.t_min = -big;
        window.t_max = big;
        rays.push_back(window);
        window.t_min = window.t_max = 0.5f;
        rays.push_back(window);
    }
    const Vec3f centre = (box.lower + box.upper) * 0.5f;
    for (const float at : {big, -big})
        for (int k = 0; k < 3; ++k) {
            Ray r{centre, {0, 0, 0}, 0.0f, inf};
            r.origin[k] = at;
            r.direction[k] = at > 0 ? -1.0f : 1.0f;
            rays.push_back(r);
            r.direction[k] = -r.direction[k];
            rays.push_back(r);
        }
    return rays;
}

std::vector<Ray> zero_direction_rays(std::uint32_t seed, std::size_t count, const Aabb& box,
                                     const Mesh& mesh)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> pick_axis(0, 2);
    std::uniform_int_distribution<std::size_t> pick_vertex(0, mesh.vertices.size() - 1);
    std::vector<Ray> rays = random_rays(seed + 1, count, box);
    for (std::size_t k = 0; k < rays.size(); ++k) {
        Ray& r = rays[k];
        const int zeroed = pick_axis(rng);
        r.direction[zeroed] = (k & 1) ? 0.0f : -0.0f;
        if (k % 3 == 0) r.direction[(zeroed + 1) % 3] = (k & 2) ? 0.0f : -0.0f;
        if (k % 3 == 1) {
            const Vec3f v = mesh.vertices[pick_vertex(rng)];
            r.origin = v - r.direction * 20.0f;
            r.origin[zeroed] = v[zeroed];
        }
        if (r.direction == Vec3f{}) r.direction[zeroed] = 1.0f;
    }
    return rays;
}

void set_random_windows(std::vector<Ray>& rays, std::uint32_t seed, float lo, float hi)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(lo, hi);
    for (Ray& r : rays) {
        const float a = u(rng), b = u(rng);
        r.t_min = std::min(a, b);
        r.t_max = std::max(a, b);
    }
}

void append_rays_in_plane(std::vector<Ray>& rays, int axis, float coord, std::size_t count)
{
    for (std::size_t k = 0; k < count; ++k) {
        Ray r = rays[k];
        r.origin[axis] = coord;
        r.direction[axis] = (k & 1) ? 0.0f : -0.0f;
        if (r.direction == Vec3f{}) r.direction[(axis + 1) % 3] = 1.0f;
        rays.push_back(r);
    }
}

std::vector<Ray> axis_rays_through_lattice(std::uint32_t seed, std::size_t count, int n,
                                           bool start_on_lattice)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> coord(0, n);
    std::vector<Ray> rays;
    for (std::size_t k = 0; k < count; ++k) {
        const auto axis = static_cast<int>(k % 3);
        Ray r;
        r.origin = {float(coord(rng)), float(coord(rng)), float(coord(rng))};
        r.direction = {};
        r.direction[axis] = (k % 2) ? 1.0f : -1.0f;
        if (!start_on_lattice || k % 4 < 2) r.origin[axis] = (k % 2) ? -1.0f : float(n + 1);
        rays.push_back(r);
    }
    return rays;
}

std::vector<Ray> invalid_rays()
{
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    return {
        Ray{{nan, 0, 0}, {1, 0, 0}, 0, inf}, Ray{{0, 0, 0}, {nan, 1, 0}, 0, inf},
        Ray{{inf, 0, 0}, {1, 0, 0}, 0, inf}, Ray{{0, 0, 0}, {0, 0, 0}, 0, inf},
        Ray{{0, 0, 0}, {1, 0, 0}, 2, 1},     Ray{{0, 0, 0}, {1, 0, 0}, nan, inf},
        Ray{{0, 0, 0}, {1, 0, 0}, 0, nan},   Ray{{0, 0, 0}, {1e-40f, 0, 0}, 0, inf},
    };
}

}  // namespace sg::test
