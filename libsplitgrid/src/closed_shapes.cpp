#include "splitgrid/closed_shapes.hpp"

#include <array>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "splitgrid/error.hpp"

namespace sg {

Mesh tessellated_cube(std::uint32_t n)
{
    if (n < 1 || n > 1024)
        throw ConfigError("tessellated_cube: n = " + std::to_string(n) +
                          " is out of range [1, 1024]");
    Mesh mesh;
    std::map<std::array<std::uint32_t, 3>, std::uint32_t> index;
    auto vertex = [&](std::array<std::uint32_t, 3> p) {
        const auto [it, fresh] = index.try_emplace(p, static_cast<std::uint32_t>(mesh.vertices.size()));
        if (fresh)
            mesh.vertices.push_back(Vec3f{static_cast<float>(p[0]), static_cast<float>(p[1]),
                                          static_cast<float>(p[2])});
        return it->second;
    };
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // (u, v, axis) is right-handed
        for (const std::uint32_t side : {0u, n}) {
            for (std::uint32_t i = 0; i < n; ++i) {
                for (std::uint32_t j = 0; j < n; ++j) {
                    auto corner = [&](std::uint32_t di, std::uint32_t dj) {
                        std::array<std::uint32_t, 3> p{};
                        p[static_cast<std::size_t>(axis)] = side;
                        p[static_cast<std::size_t>(u)] = i + di;
                        p[static_cast<std::size_t>(v)] = j + dj;
                        return vertex(p);
                    };
                    const std::uint32_t a = corner(0, 0), b = corner(1, 0), c = corner(1, 1),
                                        d = corner(0, 1);
                    // Counter-clockwise around +axis seen from outside on the upper side.
                    std::array<Triangle, 2> quad;
                    if ((i + j) % 2 == 0)
                        quad = {Triangle{{a, b, c}}, Triangle{{a, c, d}}};
                    else
                        quad = {Triangle{{a, b, d}}, Triangle{{b, c, d}}};
                    for (Triangle t : quad) {
                        if (side == 0) std::swap(t.v[1], t.v[2]);
                        mesh.triangles.push_back(t);
                    }
                }
            }
        }
    }
    return mesh;
}

Mesh icosphere(std::uint32_t subdivisions, float radius)
{
    if (subdivisions > 7)
        throw ConfigError("icosphere: subdivisions = " + std::to_string(subdivisions) +
                          " is out of range [0, 7]");
    if (!(radius > 0.0f && radius <= 1e18f))
        throw ConfigError("icosphere: radius = " + std::to_string(radius) +
                          " is out of range (0, 1e18]");
    const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<std::array<double, 3>> points = {
        {-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0}, {0, -1, phi}, {0, 1, phi},
        {0, -1, -phi}, {0, 1, -phi}, {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
    std::vector<std::array<std::uint32_t, 3>> faces = {
        {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    auto on_sphere = [](std::array<double, 3> p) {
        const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        return std::array<double, 3>{p[0] / len, p[1] / len, p[2] / len};
    };
    for (auto& p : points) p = on_sphere(p);
    for (std::uint32_t level = 0; level < subdivisions; ++level) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoint;
        auto middle = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            const auto [it, fresh] = midpoint.try_emplace(key, static_cast<std::uint32_t>(points.size()));
            if (fresh)
                points.push_back(on_sphere({points[a][0] + points[b][0], points[a][1] + points[b][1],
                                            points[a][2] + points[b][2]}));
            return it->second;
        };
        std::vector<std::array<std::uint32_t, 3>> finer;
        finer.reserve(4 * faces.size());
        for (const auto& f : faces) {
            const std::uint32_t ab = middle(f[0], f[1]), bc = middle(f[1], f[2]), ca = middle(f[2], f[0]);
            finer.push_back({f[0], ab, ca});
            finer.push_back({f[1], bc, ab});
            finer.push_back({f[2], ca, bc});
            finer.push_back({ab, bc, ca});
        }
        faces = std::move(finer);
    }
    Mesh mesh;
    mesh.vertices.reserve(points.size());
    for (const auto& p : points)
        mesh.vertices.push_back(Vec3f{static_cast<float>(p[0] * radius),
                                      static_cast<float>(p[1] * radius),
                                      static_cast<float>(p[2] * radius)});
    for (const auto& f : faces) mesh.triangles.push_back(Triangle{{f[0], f[1], f[2]}});
    return mesh;
}

}  // namespace sg
