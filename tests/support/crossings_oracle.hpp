#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"

namespace sg::test {

/// Independent references for the multi-hit and inside queries, in double precision and
/// without the library's triangle test.

using Vec3d = std::array<double, 3>;

/// The number of triangles of `mesh` the ray origin + t dir with t > t_min passes through,
/// Moeller-Trumbore in double with strict inequalities (a ray through an edge or a vertex
/// counts nothing there). Meant for rays in general position, moved off every edge and vertex
/// by more than rounding: then no inequality is near a tie.
[[nodiscard]] std::size_t count_crossings_double(const MeshView& mesh, Vec3d origin, Vec3d dir,
                                                 double t_min);

/// `ray` moved across by `e` along the axis kx and `e * e` along ky of its watertight frame
/// (WatertightRay), in double: the finite version of the symbolic perturbation that decides a
/// ray through an edge or vertex (docs/SPLIT_GRID.md, "Exact edge functions").
[[nodiscard]] Vec3d moved_origin(const Ray& ray, double e);

/// The side of a convex, closed, outward-wound mesh a point is on, by the planes of its faces in
/// double: inside when below every face's plane. `nearest_plane` is the smallest distance from
/// the point to a face's plane (not to the face), for tests that keep their points clear of
/// the planes, where the double computation could be wrong.
struct ConvexSide {
    bool inside = false;
    double nearest_plane = 0.0;
};
[[nodiscard]] ConvexSide convex_side(const MeshView& mesh, Vec3f point);

/// Every hit of `ray` by intersect_triangle over all triangles in id order, sorted by
/// (t, triangle): the reference of list_intersections (each triangle is tested once).
[[nodiscard]] std::vector<Hit> all_hits_brute_force(const MeshView& mesh, const Ray& ray);

}  // namespace sg::test
