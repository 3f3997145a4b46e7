// The Split Grid builder's entry points. The build itself is cut along its seams, in the
// order a build runs through them:
//   build_extents.hpp   each triangle's extent inside a node's box, and their summary
//   split_planning.hpp  what a cell becomes: a leaf, or a node with its axis, planes and
//                       resolution, inside its one-cell bounding nodes
//   node_building.hpp   the tree built top-down, in parallel at the top and by one thread
//                       per subtree below (NodeBuilder)
//   tree_assembly.hpp   the built tree laid out in the grid's three arrays
#include "splitgrid/builder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/task_arena.h>

#include "node_building.hpp"
#include "splitgrid/error.hpp"
#include "tree_assembly.hpp"

namespace sg {

float boundary_pad(const Aabb& scene) noexcept
{
    float magnitude = 0.0f;
    for (int k = 0; k < 3; ++k)
        magnitude = std::max({magnitude, std::abs(scene.lower[k]), std::abs(scene.upper[k])});
    // Never below a normal float, so the pad survives being added to coordinates near zero.
    return std::max(magnitude * 0x1p-20f, std::numeric_limits<float>::min() * 64.0f);
}

Aabb padded_root_box(const Aabb& scene, float pad) noexcept
{
    constexpr float float_max = std::numeric_limits<float>::max();
    Aabb box;
    for (int k = 0; k < 3; ++k) {
        box.lower[k] = std::max(-float_max, scene.lower[k] - pad);
        box.upper[k] = std::min(float_max, scene.upper[k] + pad);
    }
    return box;
}

SplitGrid build_split_grid(const MeshView& mesh, const BuildConfig& config,
                           const BuildProgress& progress)
{
    SplitGrid grid;
    rebuild_split_grid(grid, mesh, config, progress);
    return grid;
}

void rebuild_split_grid(SplitGrid& grid, const MeshView& mesh, const BuildConfig& config,
                        const BuildProgress& progress)
{
    validate(config);
    if (mesh.triangle_count() > std::size_t{max_referenced_triangle} + 1)
        throw InputError("mesh has more than 2^30 triangles");
    // Every step runs in the build's arena, the mesh's check and box too (in parallel for a
    // large mesh), so that `threads` bounds all of it.
    tbb::task_arena arena(config.threads == 0 ? tbb::task_arena::automatic
                                              : static_cast<int>(config.threads));
    Aabb scene;
    arena.execute([&] { scene = checked_bounds(mesh); });

    // The arrays are emptied, not freed: their memory is what a rebuild reuses.
    grid.nodes.clear();
    grid.cells.clear();
    grid.leaf_words.clear();
    grid.root = CellRef{};
    grid.root_box = Aabb{};
    grid.config = config;
    grid.config.threads = 0;  // the thread count does not change the result, so it is not kept
    grid.triangle_count = static_cast<std::uint32_t>(mesh.triangle_count());
    if (mesh.triangle_count() == 0) return;

    const float pad = boundary_pad(scene);
    grid.root_box = padded_root_box(scene, pad);

    detail::NodeBuilder builder(detail::BuildContext{mesh, config, pad}, progress);
    detail::BuiltCell root;
    arena.execute([&] {
        root = builder.build_root(grid.root_box);
    });
    builder.release_workspaces();
    detail::assemble(root, grid);
}

}  // namespace sg
