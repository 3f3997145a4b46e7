#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/vec3.hpp"

/// The points sg-bench queries and the oracles that decide them: the point workloads' random
/// and near points, and the inside tests' sets of points where a ray from the point meets an
/// edge or a vertex of the surface (docs/BENCH.md, "Point and multi-hit workloads"). Every
/// set is made from fixed seeds and does not depend on the thread count.
namespace sg::bench {

/// `count` points uniform in `box`: the origins of random_rays_in_box(box, count, seed)
/// (ray_generation.hpp), so `sg-rays random --seed <seed>` writes rays from the same points.
[[nodiscard]] std::vector<Vec3f> random_points(const Aabb& box, std::size_t count,
                                               std::uint32_t seed);

/// `count` points near the surface: each on a random triangle (uniform over the triangle ids,
/// uniform on the triangle), moved along its normal to either side by a distance between 1e-5
/// and 1e-3 of the box's diagonal, log-uniform (half the points each way on average).
[[nodiscard]] std::vector<Vec3f> near_points(const MeshView& mesh, std::size_t count,
                                             std::uint32_t seed);

/// The distance from the surface below which compute_occupancy may answer either way:
/// 2^-17 times the largest coordinate magnitude of `box` (docs/SPLIT_GRID.md, "Inside or
/// outside"). The oracle checks leave such points out.
[[nodiscard]] double occupancy_band(const Aabb& box) noexcept;

/// The side of a point, as an oracle decides it.
enum class Side : std::uint8_t { outside, inside, undecided };

/// The side of `point` by the generalized winding number in double (winding_number,
/// brute_force.hpp): inside within 1e-3 of +1 or -1 (an inward-wound mesh), outside within
/// 1e-3 of 0, undecided otherwise (an open or self-overlapping surface, or a point on it).
/// O(triangles).
[[nodiscard]] Side side_by_winding_number(const MeshView& mesh, Vec3f point) noexcept;

/// A set of points for the inside tests, with the oracle's answer for each.
struct InsideSet {
    std::string name;    ///< e.g. "cube_grid", "bunny_npm_near_vertices"
    std::string scene;   ///< the mesh: "tessellated_cube", "icosphere" or the scene's name
    std::string oracle;  ///< "analytic" or "winding number"
    std::vector<Vec3f> points;
    std::vector<Side> expected;
};

/// The points of `targets` (on the surface) moved back by each of `distances` along the ray
/// compute_occupancy casts from the moved point (occupancy_ray, occupancy.hpp, with `box` the
/// structure's root box): the ray from each point runs to its target, a vertex or a point of
/// an edge, through float roundings at most. Of the six axis directions the ray can take,
/// only those it does take from the moved point are kept, and only points strictly inside
/// `box` (a point outside needs no ray).
[[nodiscard]] std::vector<Vec3f> aimed_points(const std::vector<Vec3f>& targets,
                                              const std::vector<float>& distances, const Aabb& box);

/// The tessellated cube of the inside tests: tessellated_cube(8), [0, 8]^3, 768 triangles.
[[nodiscard]] Mesh inside_test_cube();
/// The icosphere of the inside tests: icosphere(2, 1), 320 triangles.
[[nodiscard]] Mesh inside_test_icosphere();

/// The inside tests on `cube` (inside_test_cube), decided analytically (inside iff every
/// coordinate lies strictly between 0 and 8): "cube_grid", every point of a lattice of the
/// integers and half-integers in [0.5, 7.5], 1/8 off the faces and 1/8 outside them, where
/// axis-parallel rays (CGAL's vertical rays) run through the tessellation's vertices and
/// edges; and "cube_aimed", points 1/4, 1 and 2 from every vertex and edge midpoint of the
/// surface along the ray compute_occupancy casts (aimed_points).
[[nodiscard]] std::vector<InsideSet> cube_inside_sets(const Mesh& cube);

/// The inside tests on `sphere` (inside_test_icosphere), decided by the winding number:
/// "icosphere_grid", a 6 x 6 x 6 grid over [-1.25, 1.25]^3, the centre, and points 2% inside
/// and outside every vertex along its radius; "icosphere_aimed", points 1/8 and 1/4 from every
/// vertex and edge midpoint along compute_occupancy's ray (aimed_points).
[[nodiscard]] std::vector<InsideSet> icosphere_inside_sets(const Mesh& sphere);

/// The inside test on a closed scan `mesh` named `scene`, decided by the winding number:
/// "<scene>_near_vertices", points at 1e-3 and 1e-5 of the box's diagonal from `vertices`
/// vertices (evenly spaced over the vertex array) along the 6 axis directions, the 8
/// diagonals and compute_occupancy's ray (aimed_points). Points the winding number leaves
/// undecided keep Side::undecided.
[[nodiscard]] InsideSet near_vertex_set(const MeshView& mesh, const std::string& scene,
                                        std::size_t vertices);

}  // namespace sg::bench
