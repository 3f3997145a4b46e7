#pragma once

#include <cstdint>

#include "splitgrid/mesh.hpp"

namespace sg {

/// Closed meshes whose inside is known exactly, for the tests and the benchmark's inside tests:
/// every point of their surfaces and every edge is where a ray through an edge or a vertex is
/// decided, so they are where an inside test that guesses at edges fails.

/// The cube [0, n]^3 with each face cut into n x n unit squares of two triangles (diagonals
/// alternating like a checkerboard), outward winding, shared vertices: 12 n^2 triangles, every
/// coordinate an integer (exact in float), every edge shared by two triangles. Range n in
/// [1, 1024]; throws ConfigError outside it.
[[nodiscard]] Mesh tessellated_cube(std::uint32_t n);

/// The icosahedron inscribed in the sphere of `radius` around the origin, each face cut into
/// 4^subdivisions triangles whose new vertices are pushed out onto the sphere (rounded to
/// float): 20 * 4^subdivisions triangles, outward winding, shared vertices, convex to the
/// precision of its float corners. Range subdivisions in [0, 7], radius in (0, 1e18]; throws
/// ConfigError outside them.
[[nodiscard]] Mesh icosphere(std::uint32_t subdivisions, float radius);

}  // namespace sg
