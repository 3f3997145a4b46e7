#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/vec3.hpp"

namespace sg {

/// Three vertex indices into a vertex array. 12 bytes, stored as is in .sg files.
struct Triangle {
    std::array<std::uint32_t, 3> v{};
    friend constexpr bool operator==(const Triangle&, const Triangle&) = default;
};
static_assert(sizeof(Triangle) == 12 && std::is_trivially_copyable_v<Triangle>,
              "Triangle must be three packed uint32 indices: it is stored in .sg files");

/// Non-owning view of an indexed triangle mesh: the caller keeps the arrays alive.
/// Triangle ids used everywhere (hits, references, .sg files) are positions in `triangles`.
struct MeshView {
    std::span<const Vec3f> vertices;
    std::span<const Triangle> triangles;

    [[nodiscard]] std::size_t triangle_count() const noexcept { return triangles.size(); }
    [[nodiscard]] Vec3f vertex(std::uint32_t tri, int corner) const noexcept
    {
        return vertices[triangles[tri].v[static_cast<std::size_t>(corner)]];
    }
};

/// An indexed triangle mesh that owns its arrays.
struct Mesh {
    std::vector<Vec3f> vertices;
    std::vector<Triangle> triangles;

    [[nodiscard]] MeshView view() const noexcept { return {vertices, triangles}; }
    friend bool operator==(const Mesh&, const Mesh&) = default;
};

/// Bounding box of the vertices referenced by the triangles (unreferenced vertices ignored).
[[nodiscard]] Aabb bounds(const MeshView& mesh) noexcept;

/// Throws InputError naming the first triangle with an index >= vertices.size() or the first
/// referenced vertex with a NaN or infinite coordinate. Cost: one pass over the triangles.
void check_mesh(const MeshView& mesh);

/// check_mesh and bounds in one pass: the bounding box of the referenced vertices, after the
/// checks of check_mesh (the same InputError, for the same first triangle). Reads each
/// triangle's corners once; a mesh of 65,536 triangles or more is read in parallel, in blocks
/// whose boxes are joined in a fixed order, on the calling thread's oneTBB arena, so the
/// builders call it inside theirs and their thread count bounds it.
[[nodiscard]] Aabb checked_bounds(const MeshView& mesh);

/// Counts of what `clean_mesh` removed.
struct CleanReport {
    std::size_t bad_index_triangles = 0;  ///< an index past the vertex array
    std::size_t nonfinite_triangles = 0;  ///< a corner with NaN or infinite coordinates
    std::size_t degenerate_triangles = 0; ///< zero area: collinear corners, decided exactly
    [[nodiscard]] std::size_t dropped() const noexcept
    {
        return bad_index_triangles + nonfinite_triangles + degenerate_triangles;
    }
};

/// Removes triangles with out-of-range indices, non-finite corners or zero area (collinear or
/// coincident corners, decided in exact arithmetic: the cross product of two edges is zero),
/// keeping the order of the rest. Vertices are left as they are. Returns what was removed.
CleanReport clean_mesh(Mesh& mesh);

}  // namespace sg
