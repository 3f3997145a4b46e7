#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/mesh.hpp"

namespace sg {

/// The order of the triangles' centroids along a Morton (Z-order) curve over the mesh's
/// bounding box: element i is the id of the triangle that comes i-th. Triangles near in space
/// then lie near in the arrays, so the triangles of one leaf (and their corners) can share
/// cache lines. Centroids are quantised to 2^21 steps per axis of the box (an axis of zero
/// extent to one step); triangles with equal codes keep their relative order, so the result
/// depends on the mesh alone. Throws InputError as checked_bounds does (an index past the
/// vertex array, a non-finite corner) and for more than 2^32 - 1 triangles. Cost: one pass
/// over the triangles to check them and find the box, one to code them, and a sort.
[[nodiscard]] std::vector<std::uint32_t> morton_order(const MeshView& mesh);

/// The indices of `points` in the order of a Morton curve over `box` (2^21 steps per axis;
/// points outside the box clamped to it, a NaN to its lower side; equal codes keep their
/// order), so that point queries taken in this order visit the structure's nodes and the
/// mesh near where the query before them did. At most 2^32 - 1 points. Cost: a pass and a
/// sort.
[[nodiscard]] std::vector<std::uint32_t> morton_order(std::span<const Vec3f> points,
                                                      const Aabb& box);

/// The triangles `ids` of `mesh`, in that order, with only the vertices they use, numbered in
/// the order the triangles first use them. Each triangle keeps its corners in their order with
/// their exact positions, so a ray hits it as it hits the triangle in `mesh` (the same t, u
/// and v), under its new id, its position in `ids`. Throws ConfigError for an id past the
/// triangle array and InputError for a vertex index past the vertex array.
[[nodiscard]] Mesh extract_triangles(const MeshView& mesh, std::span<const std::uint32_t> ids);

/// Puts the triangles of `mesh` in `order` (element i: the id in the input of the triangle
/// that becomes triangle i): extract_triangles of every triangle; vertices no triangle uses
/// are dropped. Throws ConfigError if `order` is not a permutation of the triangle ids and
/// InputError as check_mesh does; the mesh is then unchanged.
void reorder_triangles(Mesh& mesh, std::span<const std::uint32_t> order);

}  // namespace sg
