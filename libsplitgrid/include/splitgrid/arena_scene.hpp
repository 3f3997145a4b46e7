#pragma once

#include <cstdint>

#include "splitgrid/mesh.hpp"

namespace sg {

/// How make_arena_scene lays out its copies.
struct ArenaConfig {
    /// Copies of the model. Range [1, 2^24]; the result must stay below 2^32 triangles and
    /// vertices.
    std::uint32_t copies = 1;
    /// Distance between neighbouring copies' centres, in units of the model's bounding-box
    /// diagonal. Range [0.5, 1e6]. 1.5 leaves about half a model of empty floor between
    /// neighbours; large values give the "teapot in a stadium" case (small dense objects in a
    /// large empty box), which uniform grids handle badly.
    double spacing = 1.5;
    /// Seed of the copies' rotations, scales and jitter. The scene depends only on the model,
    /// the config and the seed.
    std::uint32_t seed = 1;
    /// Add a floor of two triangles under all copies, 20% wider than the arena on each side.
    bool floor = true;
};

/// A large test scene made of copies of `model` standing on a square lattice in the x-z plane
/// (y up), each rotated about y by a random angle, scaled by a random factor in [0.75, 1.25]
/// and moved by up to a quarter of the spacing: the benchmark's scale scenes (10^3 to 10^7
/// triangles from one real mesh). Copies share no vertices. Throws ConfigError for a config
/// out of range, InputError for an empty model or a result too large for 32-bit indices.
/// Cost: linear in the output size.
[[nodiscard]] Mesh make_arena_scene(const MeshView& model, const ArenaConfig& config);

}  // namespace sg
