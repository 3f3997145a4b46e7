#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/build_config.hpp"
#include "splitgrid/grid_node.hpp"
#include "splitgrid/leaf_words.hpp"

namespace sg {

/// The Split Grid: passive data made by build_split_grid(), read by the traverser, the
/// statistics and the file writer. Plain vectors, equality-comparable.
///
/// The root box is the scene's bounding box, padded outward by a few float ulps (see
/// builder.hpp). `root` is the cell that covers the root box: empty for an empty mesh, a
/// leaf for a mesh too small to split, otherwise inner with child node 0.
/// Nodes are in depth-first pre-order; the cells of each node of two or more cells are
/// contiguous in `cells` (a one-cell node holds its cell in its record: GridNode), and each
/// leaf's references contiguous in `leaf_words`, in the encoding of leaf_words.hpp.
struct SplitGrid {
    Aabb root_box;
    CellRef root;
    std::vector<GridNode> nodes;
    std::vector<CellRef> cells;
    /// The leaves' triangle references, 16-bit words (leaf_words.hpp).
    std::vector<std::uint16_t> leaf_words;
    /// Number of triangles in the mesh the grid was built for (ids are < triangle_count).
    std::uint32_t triangle_count = 0;
    /// The parameters the grid was built with; `threads` is always 0 (the result does not
    /// depend on it, so files built with any thread count are byte-identical).
    BuildConfig config;

    /// Bytes of the three arrays plus the root record: what traversal reads besides the mesh.
    [[nodiscard]] std::size_t memory_bytes() const noexcept
    {
        return sizeof(root_box) + sizeof(root) + nodes.size() * sizeof(GridNode) +
               cells.size() * sizeof(CellRef) + leaf_words.size() * sizeof(std::uint16_t);
    }

    /// Cells of all nodes, the sum of their resolutions: `cells` plus one per one-cell node
    /// (the root cell not counted).
    [[nodiscard]] std::size_t cell_count() const noexcept
    {
        std::size_t count = 0;
        for (const GridNode& node : nodes) count += node.resolution();
        return count;
    }

    friend bool operator==(const SplitGrid&, const SplitGrid&) = default;
};

/// Cell `i` of `node`, wherever it is kept. Precondition: i < node.resolution(), and the
/// node's cells are in range (check_invariants).
[[nodiscard]] inline CellRef node_cell(const SplitGrid& grid, const GridNode& node,
                                       std::uint32_t i) noexcept
{
    return node.resolution() == 1 ? node.only_cell() : grid.cells[node.first_cell() + i];
}

/// Number of triangle references of a leaf cell, without allocating (its ids: leaf_ids in
/// leaf_words.hpp). Precondition: `leaf` is a leaf of `grid`; 0 if the leaf is not well formed
/// (check_invariants refuses such a grid).
[[nodiscard]] inline std::size_t leaf_size(const SplitGrid& grid, CellRef leaf) noexcept
{
    std::size_t n = 0;
    return read_leaf(grid.leaf_words, leaf.first_word(), [&](std::uint32_t) { ++n; }) == 0 ? 0 : n;
}

/// Number of triangle references of all leaves. Precondition: check_invariants(grid) passes
/// (so the leaves fill `leaf_words` one after another).
[[nodiscard]] inline std::size_t reference_count(const SplitGrid& grid)
{
    return count_references(grid.leaf_words);
}

}  // namespace sg
