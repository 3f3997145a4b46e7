#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/mesh.hpp"

/// The scenes of sg-bench's dynamic workload (dynamic.hpp): a real model, moved frame by
/// frame by a deterministic function of the frame number.
namespace sg::bench {

/// How a dynamic scene moves. Deterministic: frame f of n is a function of f / n alone.
enum class Motion {
    /// Copies of a model, each turning about its vertical axis while its centre circles its
    /// own spot of an arena: every copy moves rigidly, the scene as a whole does not.
    rigid,
    /// The model itself, twisted about its vertical axis and swelling in a wave that runs up
    /// it: every vertex moves smoothly, the triangles stay connected.
    deform,
};

[[nodiscard]] const char* motion_name(Motion motion) noexcept;

/// A model and how it moves.
struct DynamicScene {
    std::string name;    ///< for tables and the chart: "<stem>_rigid" or "<stem>_deform"
    std::string source;  ///< the model's file and what was made of it
    Motion motion = Motion::deform;
    Mesh model;          ///< the model; rigid: centred on the origin, each copy turns about it
    std::uint32_t copies = 1;  ///< rigid: copies of the model, each model.vertices in turn
    std::vector<Triangle> triangles;  ///< the whole scene's (copy c's vertices shifted)
    Aabb arena;          ///< a box every frame's vertices stay inside

    [[nodiscard]] std::size_t vertex_count() const noexcept
    {
        return model.vertices.size() * copies;
    }
};

/// The scene for `motion` from `model`: for rigid, as many copies as reach `min_triangles`
/// (at least 2), laid out on a square arena with room to move; for deform, the model.
[[nodiscard]] DynamicScene make_dynamic_scene(const std::string& stem, const std::string& source,
                                              const MeshView& model, Motion motion,
                                              std::size_t min_triangles);

/// Writes the vertex positions of frame `frame` of `frames` into `out` (vertex_count()
/// entries); for deform, frame 0 is the model as it is.
void animate(const DynamicScene& scene, std::uint32_t frame, std::uint32_t frames,
             std::span<Vec3f> out);

}  // namespace sg::bench
