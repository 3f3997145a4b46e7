#pragma once

#include <cstdint>

#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/vec3.hpp"

namespace sg {

/// Reference answer: tests every triangle of the mesh in id order with the same watertight
/// test, in plain scalar code independent of the traversal kernels (src/brute_force.cpp).
/// O(triangles) per ray: for tests and the benchmark's correctness checks. Returns the smallest
/// t in [t_min, t_max], the lowest id on equal t; a miss has t = t_max. Invalid rays (is_valid)
/// miss.
[[nodiscard]] Hit intersect_brute_force(const MeshView& mesh, const Ray& ray) noexcept;
/// True if any triangle is hit with t in [t_min, t_max]; stops at the first.
[[nodiscard]] bool occluded_brute_force(const MeshView& mesh, const Ray& ray) noexcept;
/// The number of triangles hit with t in [t_min, t_max], each tested once by the watertight
/// test (intersect_triangle, symbolic perturbation included): what count_intersections
/// returns. 0 for an invalid ray.
[[nodiscard]] std::int32_t count_intersections_brute_force(const MeshView& mesh,
                                                           const Ray& ray) noexcept;

/// The generalized winding number of `point` with respect to the triangles of `mesh`: the sum
/// of their signed solid angles over 4 pi (Van Oosterom and Strackee's formula), in double
/// precision and without any ray test, so it is an oracle of compute_occupancy independent of
/// the code it checks. 1 inside a closed outward-wound mesh (-1 inward-wound), 0 outside, to
/// within rounding for points not too close to the surface; between the two (or a multiple
/// elsewhere) for an open or self-overlapping mesh. O(triangles) per point, about 30 ns each.
[[nodiscard]] double winding_number(const MeshView& mesh, Vec3d point) noexcept;

}  // namespace sg
