#pragma once

#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"

namespace sg {

/// Reference answer: tests every triangle of the mesh in id order with the same watertight
/// test, in plain scalar code independent of the traversal kernels (src/brute_force.cpp).
/// O(triangles) per ray: for tests and the benchmark's correctness checks. Returns the smallest
/// t in [t_min, t_max], the lowest id on equal t; a miss has t = t_max. Invalid rays (is_valid)
/// miss.
[[nodiscard]] Hit intersect_brute_force(const MeshView& mesh, const Ray& ray) noexcept;
/// True if any triangle is hit with t in [t_min, t_max]; stops at the first.
[[nodiscard]] bool occluded_brute_force(const MeshView& mesh, const Ray& ray) noexcept;

}  // namespace sg
