#pragma once

// Build-time helpers shared by the three comparison structures.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>

#include <tbb/task_arena.h>

#include "splitgrid/aabb.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/float_step.hpp"
#include "splitgrid/mesh.hpp"

namespace sg::detail {

/// A float at or below (above) x: one float outward from the nearest, which is always enough.
/// At most one float wider than float_not_above (below), which the Split Grid's builder uses;
/// the comparison structures keep this step, so their boxes stay those measured in
/// docs/RESULTS.md.
[[nodiscard]] inline float float_below(double x) noexcept
{
    return next_float_down(static_cast<float>(x));
}
[[nodiscard]] inline float float_above(double x) noexcept
{
    return next_float_up(static_cast<float>(x));
}

/// Checks what every build requires of its mesh (ids that fit in 32 bits with one value to
/// spare, and check_mesh's checks) and returns the scene's box (checked_bounds); throws
/// InputError otherwise, naming the structure for the count. Called inside the build's arena
/// (run_with_threads), as the Split Grid's builder calls checked_bounds, so that the build's
/// thread count bounds it.
[[nodiscard]] inline Aabb checked_build_bounds(const MeshView& mesh, const char* structure)
{
    if (mesh.triangle_count() >= std::numeric_limits<std::uint32_t>::max())
        throw InputError(std::string(structure) + ": the mesh has 2^32 - 1 triangles or more");
    return checked_bounds(mesh);
}

/// Runs `work` in a oneTBB arena of `threads` workers (0 = all hardware threads), as
/// build_split_grid does for BuildConfig::threads.
template <class Work>
void run_with_threads(unsigned threads, const Work& work)
{
    tbb::task_arena arena(threads == 0 ? tbb::task_arena::automatic : static_cast<int>(threads));
    arena.execute(work);
}

}  // namespace sg::detail
