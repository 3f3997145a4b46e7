#include "splitgrid/arena_scene.hpp"

#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include "splitgrid/error.hpp"

namespace sg {

Mesh make_arena_scene(const MeshView& model, const ArenaConfig& config)
{
    if (config.copies < 1 || config.copies > (1u << 24))
        throw ConfigError("ArenaConfig.copies = " + std::to_string(config.copies) +
                          " is out of range [1, 16777216]");
    if (!(config.spacing >= 0.5 && config.spacing <= 1e6))
        throw ConfigError("ArenaConfig.spacing = " + std::to_string(config.spacing) +
                          " is out of range [0.5, 1e6]");
    if (model.triangle_count() == 0) throw InputError("arena scene: the model has no triangles");
    check_mesh(model);

    const std::uint64_t floor_triangles = config.floor ? 2 : 0;
    const std::uint64_t triangles =
        std::uint64_t{config.copies} * model.triangle_count() + floor_triangles;
    const std::uint64_t vertices =
        std::uint64_t{config.copies} * model.vertices.size() + 2 * floor_triangles;
    constexpr std::uint64_t limit = std::numeric_limits<std::uint32_t>::max();
    if (triangles > limit || vertices > limit)
        throw InputError("arena scene: " + std::to_string(triangles) +
                         " triangles is too many for 32-bit indices");

    const Aabb box = bounds(model);
    const double dx = box.extent(0), dy = box.extent(1), dz = box.extent(2);
    const double diagonal = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double cx = 0.5 * (double{box.lower.x} + box.upper.x);
    const double cz = 0.5 * (double{box.lower.z} + box.upper.z);
    const double step = config.spacing * diagonal;
    const auto side = static_cast<std::uint32_t>(std::ceil(std::sqrt(static_cast<double>(config.copies))));

    Mesh out;
    out.vertices.reserve(static_cast<std::size_t>(vertices));
    out.triangles.reserve(static_cast<std::size_t>(triangles));
    std::mt19937 rng(config.seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (std::uint32_t copy = 0; copy < config.copies; ++copy) {
        const double angle = 2.0 * std::numbers::pi * unit(rng);
        const double scale = 0.75 + 0.5 * unit(rng);
        const double jitter_x = (unit(rng) - 0.5) * 0.5 * step;
        const double jitter_z = (unit(rng) - 0.5) * 0.5 * step;
        const double px = (copy % side) * step + jitter_x;
        const double pz = (copy / side) * step + jitter_z;
        const double c = std::cos(angle), s = std::sin(angle);
        const auto base = static_cast<std::uint32_t>(out.vertices.size());
        for (const Vec3f& v : model.vertices) {
            // Rotate about the model's vertical axis through its centre, standing on y = 0.
            const double x = v.x - cx, y = double{v.y} - box.lower.y, z = v.z - cz;
            out.vertices.push_back(Vec3f{static_cast<float>(px + scale * (c * x + s * z)),
                                         static_cast<float>(scale * y),
                                         static_cast<float>(pz + scale * (-s * x + c * z))});
        }
        for (const Triangle& t : model.triangles)
            out.triangles.push_back(Triangle{{t.v[0] + base, t.v[1] + base, t.v[2] + base}});
    }
    if (config.floor) {
        const double margin = 0.2 * side * step + step;
        const auto lo = static_cast<float>(-margin);
        const auto hi = static_cast<float>((side - 1) * step + margin);
        const auto base = static_cast<std::uint32_t>(out.vertices.size());
        out.vertices.push_back({lo, 0.0f, lo});
        out.vertices.push_back({hi, 0.0f, lo});
        out.vertices.push_back({hi, 0.0f, hi});
        out.vertices.push_back({lo, 0.0f, hi});
        out.triangles.push_back(Triangle{{base, base + 2, base + 1}});
        out.triangles.push_back(Triangle{{base, base + 3, base + 2}});
    }
    return out;
}

}  // namespace sg
