#pragma once

// Shared by the fuzz targets: how a disagreement is reported, the rays that probe a grid, and
// the checks run on them. The targets abort on a failed check, which libFuzzer (or the replay
// driver) turns into a saved crash input.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/split_grid.hpp"

namespace sg::fuzz {

/// Prints "fuzz check failed: <what>" on stderr and aborts, so that the input is kept.
[[noreturn]] void fail(const std::string& what);

/// A few rays that reach every triangle from several sides: from the corners and the centre of
/// `box` (grown by half its size) towards each triangle's centroid, and axis-parallel rays
/// through each centroid in both directions (they have two zero direction components, the
/// classic way to make a grid stepper divide by zero). At most `max_triangles` triangles are
/// aimed at, so the cost stays bounded on large inputs.
[[nodiscard]] std::vector<Ray> probe_rays(const MeshView& mesh, const Aabb& box,
                                          std::size_t max_triangles);

/// Full oracle: closest hit and any-hit of the grid equal brute force over all triangles
/// (same rule as tests/support/oracle.hpp). Aborts on the first disagreement.
void require_brute_force_agreement(const SplitGrid& grid, const MeshView& mesh,
                                   const std::vector<Ray>& rays);

/// The checks that hold for any grid that passes check_invariants, even one that does not
/// cover its mesh (a forged file): tracing terminates without touching memory outside the
/// arrays (the sanitizers see to that), a reported hit names a real triangle that the ray
/// really hits at that distance, and no hit is closer than the true closest hit.
void require_sound_hits(const SplitGrid& grid, const MeshView& mesh,
                        const std::vector<Ray>& rays);

}  // namespace sg::fuzz
