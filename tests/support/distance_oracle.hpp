#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "splitgrid/mesh.hpp"

namespace sg::test {

/// An independent reference for closest point queries: Ericson's region-by-region closest
/// point on a triangle ("Real-Time Collision Detection", 2005, section 5.1.5), in double,
/// over every triangle. It shares no code with the library's point search.
struct DistanceOracle {
    double distance = 0.0;                ///< the smallest distance
    std::vector<std::uint32_t> nearest;  ///< every triangle within `tolerance` of it, ascending
};

/// The closest point of triangle (a, b, c) to p, in double.
[[nodiscard]] std::array<double, 3> closest_point_on_triangle(std::array<double, 3> p,
                                                              std::array<double, 3> a,
                                                              std::array<double, 3> b,
                                                              std::array<double, 3> c);

/// The smallest distance from p to the triangles of `mesh`, and the triangles within
/// `tolerance` of it.
[[nodiscard]] DistanceOracle distance_oracle(const MeshView& mesh, Vec3f p, double tolerance);

/// Distance from p to triangle `tri` of `mesh` by closest_point_on_triangle.
[[nodiscard]] double triangle_distance(const MeshView& mesh, std::uint32_t tri, Vec3f p);

}  // namespace sg::test
