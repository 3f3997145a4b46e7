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

/// Valid rays at the edges of the float range, from rays_at_triangles(seed, count, box, mesh):
/// each with its direction scaled to lengths 1e30, 1e-30, 4 FLT_MIN and FLT_MAX / 4 (t scales
/// inversely); with one direction component set to +-8 FLT_MIN (a crossing on that axis near
/// FLT_MAX, the others ordinary); with its origin 1e30 back along the ray; with the window
/// [-FLT_MAX, FLT_MAX] and the empty window [0.5, 0.5]; and rays from origins at +-FLT_MAX on
/// each axis, looking back at `box`'s centre and away from it.
[[nodiscard]] std::vector<Ray> float_range_edge_rays(std::uint32_t seed, std::size_t count,
                                                     const Aabb& box, const MeshView& mesh);

/// Random rays (random_rays(seed + 1, count, box)) with one or two direction components set
/// to +0.0 or -0.0, a third of them aimed exactly through a vertex of `mesh` with the origin
/// on the vertex's plane of the zeroed axis.
[[nodiscard]] std::vector<Ray> zero_direction_rays(std::uint32_t seed, std::size_t count,
                                                   const Aabb& box, const Mesh& mesh);

/// Gives every ray a random window [t_min, t_max] within [lo, hi].
void set_random_windows(std::vector<Ray>& rays, std::uint32_t seed, float lo, float hi);

/// Appends copies of the first `count` rays moved into the plane axis = coord, with their
/// direction component on that axis set to +0.0 or -0.0 (rays lying in the plane).
void append_rays_in_plane(std::vector<Ray>& rays, int axis, float coord, std::size_t count);

/// Axis-aligned rays (+-x, +-y, +-z in turn) through random points of the integer lattice
/// [0, n]^3, starting outside the lattice; with `start_on_lattice`, every other pair starts on
/// the lattice point itself.
[[nodiscard]] std::vector<Ray> axis_rays_through_lattice(std::uint32_t seed, std::size_t count,
                                                         int n, bool start_on_lattice);

/// One ray of each invalid kind (see is_valid): NaN or infinite origin, NaN or zero or
/// denormal-only direction, t_min > t_max, NaN t_min or t_max.
[[nodiscard]] std::vector<Ray> invalid_rays();

}  // namespace sg::test
