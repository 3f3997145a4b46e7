#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/build_config.hpp"
#include "splitgrid/grid_node.hpp"

namespace sg {

/// The Split Grid: passive data made by build_split_grid(), read by the traverser, the
/// statistics and the file writer. Plain vectors, equality-comparable.
///
/// The root box is the scene's bounding box, padded outward by a few float ulps (see
/// builder.hpp). `root` is the cell that covers the root box: empty for an empty mesh, a
/// leaf for a mesh too small to split, otherwise inner with child node 0.
/// Nodes are in depth-first pre-order; each node's cells are contiguous in `cells`, and each
/// leaf's references contiguous in `triangle_refs`, the last one marked (TriangleRef).
struct SplitGrid {
    Aabb root_box;
    CellRef root;
    std::vector<GridNode> nodes;
    std::vector<CellRef> cells;
    std::vector<TriangleRef> triangle_refs;
    /// Number of triangles in the mesh the grid was built for (ids are < triangle_count).
    std::uint32_t triangle_count = 0;
    /// The parameters the grid was built with; `threads` is always 0 (the result does not
    /// depend on it, so files built with any thread count are byte-identical).
    BuildConfig config;

    /// Bytes of the three arrays plus the root record: what traversal reads besides the mesh.
    [[nodiscard]] std::size_t memory_bytes() const noexcept
    {
        return sizeof(root_box) + sizeof(root) + nodes.size() * sizeof(GridNode) +
               cells.size() * sizeof(CellRef) + triangle_refs.size() * sizeof(TriangleRef);
    }

    friend bool operator==(const SplitGrid&, const SplitGrid&) = default;
};

/// The references of a leaf cell: from its first one to the first with the last bit set.
/// Precondition: `leaf` is a leaf of `grid` and check_invariants(grid) passes. Cost: linear
/// in the leaf's size.
[[nodiscard]] inline std::span<const TriangleRef> leaf_refs(const SplitGrid& grid,
                                                          CellRef leaf) noexcept
{
    const TriangleRef* const first = grid.triangle_refs.data() + leaf.first_ref();
    const TriangleRef* last = first;
    while (!last->is_last()) ++last;
    return {first, static_cast<std::size_t>(last - first) + 1};
}

}  // namespace sg
