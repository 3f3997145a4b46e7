#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"

namespace sg::test {

/// `count` random triangles inside `box`, each with edges up to `max_edge` (scene units).
/// Vertices are not shared. Deterministic for a given seed.
[[nodiscard]] Mesh random_triangles(std::uint32_t seed, std::size_t count, const Aabb& box,
                                    float max_edge);

/// A closed UV sphere with shared vertices: `rings` latitude bands, `segments` longitudes;
/// 2 * segments * (rings - 1) triangles.
[[nodiscard]] Mesh uv_sphere(Vec3f center, float radius, std::uint32_t rings,
                             std::uint32_t segments);

/// An axis-aligned grid of unit quads (2 triangles each) in the plane axis = offset,
/// spanning [0, n] on the other two axes.
[[nodiscard]] Mesh axis_plane(int axis, float offset, std::uint32_t n);

/// Appends b to a (indices shifted).
void append(Mesh& a, const Mesh& b);

/// Random rays: origins uniform in `box`, directions uniform on the sphere, t in [0, inf).
[[nodiscard]] std::vector<Ray> random_rays(std::uint32_t seed, std::size_t count,
                                           const Aabb& box);

/// Rays from random points of `box` towards random points on random triangles of `mesh`
/// (so most of them hit something).
[[nodiscard]] std::vector<Ray> rays_at_triangles(std::uint32_t seed, std::size_t count,
                                                 const Aabb& box, const MeshView& mesh);

}  // namespace sg::test
