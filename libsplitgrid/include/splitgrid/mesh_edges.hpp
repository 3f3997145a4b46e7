#pragma once

#include <cstdint>

#include "splitgrid/mesh.hpp"

namespace sg {

/// The edges of a mesh by how many triangles share them, vertices at the same position taken
/// as one (as sg-build's welding does; -0 and +0 alike). A triangle with two corners at one
/// position contributes its other edge twice, which cancels, as its zero area does.
struct EdgeReport {
    std::uint64_t edges = 0;              ///< distinct edges
    std::uint64_t open_edges = 0;         ///< edges shared by an odd number of triangles
    std::uint64_t nonmanifold_edges = 0;  ///< edges shared by more than two triangles

    /// True when every edge is shared by an even number of triangles: then a generic line
    /// crosses the surface an even number of times, and the parity of the crossings along a
    /// ray from a point tells inside from outside (docs/SPLIT_GRID.md, "Inside or outside").
    [[nodiscard]] bool is_closed() const noexcept { return open_edges == 0; }
    friend bool operator==(const EdgeReport&, const EdgeReport&) = default;
};

/// Counts the edges of `mesh` (check_mesh must hold). Cost: a sort of 3 keys per triangle
/// and a hash of the vertices, in parallel on the calling thread's oneTBB arena.
[[nodiscard]] EdgeReport edge_report(const MeshView& mesh);

}  // namespace sg
