#pragma once

#include <functional>
#include <string>
#include <vector>

#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/split_grid.hpp"

namespace sg::test {

/// Result of comparing a structure's answers with brute force over all triangles.
struct OracleReport {
    std::size_t rays = 0;
    std::size_t closest_disagreements = 0;
    std::size_t any_hit_disagreements = 0;
    std::size_t hits = 0;  ///< rays the oracle says hit something
    std::string first_failure;  ///< description of the first disagreement

    /// Adds the counts of `other` (a later batch of rays); keeps the earlier first failure.
    OracleReport& operator+=(const OracleReport& other)
    {
        rays += other.rays;
        closest_disagreements += other.closest_disagreements;
        any_hit_disagreements += other.any_hit_disagreements;
        hits += other.hits;
        if (first_failure.empty()) first_failure = other.first_failure;
        return *this;
    }
};

/// Same closest hit: both miss, or the same triangle at the same t, or (a tie) another
/// triangle at exactly the same t.
[[nodiscard]] bool same_closest_hit(const Hit& expected, const Hit& actual) noexcept;

/// Builds a grid and runs both checkers on it (check_invariants, check_coverage), as every
/// test build should.
[[nodiscard]] SplitGrid build_checked(const Mesh& mesh, const BuildConfig& config = {});

/// A structure's two queries for one ray, as callbacks.
using ClosestHitQuery = std::function<Hit(const Ray&)>;
using AnyHitQuery = std::function<bool(const Ray&)>;

/// Runs both queries on every ray and compares with intersect_brute_force and
/// occluded_brute_force over all triangles of `mesh`.
[[nodiscard]] OracleReport compare_with_brute_force(const MeshView& mesh,
                                                    const std::vector<Ray>& rays,
                                                    const ClosestHitQuery& closest,
                                                    const AnyHitQuery& any);

/// The same with other reference answers (`expected_closest`, `expected_any`), e.g. brute
/// force restricted to the triangles a ray can reach.
[[nodiscard]] OracleReport compare_with_oracle(const std::vector<Ray>& rays,
                                               const ClosestHitQuery& closest,
                                               const AnyHitQuery& any,
                                               const ClosestHitQuery& expected_closest,
                                               const AnyHitQuery& expected_any);

/// Runs intersect() and occluded() on every ray and compares with the brute-force answers.
[[nodiscard]] OracleReport compare_with_brute_force(const SplitGrid& grid, const MeshView& mesh,
                                                    const std::vector<Ray>& rays);

/// The same for a comparison structure (uniform grid, kd-tree, BVH): anything with
/// intersect(mesh, ray) and occluded(mesh, ray) members.
template <class Structure>
[[nodiscard]] OracleReport compare_structure_with_brute_force(const Structure& structure,
                                                              const MeshView& mesh,
                                                              const std::vector<Ray>& rays)
{
    return compare_with_brute_force(
        mesh, rays, [&](const Ray& r) { return structure.intersect(mesh, r); },
        [&](const Ray& r) { return structure.occluded(mesh, r); });
}

}  // namespace sg::test
