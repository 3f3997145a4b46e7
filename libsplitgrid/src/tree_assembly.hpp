#pragma once

// The Split Grid builder's last seam: the built tree and its assembly into the grid's three
// arrays. The top of the tree is built in parallel as BuiltNode objects, each subtree below
// parallel_grain triangles by one thread as a Fragment already in the grid's layout;
// assemble() lays them out in one fixed depth-first order, which is what makes the grid the
// same for every thread count.

#include <cstdint>
#include <memory>
#include <vector>

#include "build_extents.hpp"
#include "splitgrid/grid_node.hpp"
#include "splitgrid/split_grid.hpp"

namespace sg::detail {

// A subtree built by one thread, in its final depth-first pre-order, with indices local to
// its own arrays: assemble() appends it to the grid and shifts them. Every subtree of fewer
// than parallel_grain triangles is built this way, without allocating per node.
struct Fragment {
    CellRef root;
    std::vector<GridNode> nodes;
    std::vector<CellRef> cells;
    std::vector<std::uint16_t> leaf_words;
};

// The top of the tree, where nodes are built in parallel; flattened into SplitGrid arrays
// afterwards, in a fixed order, which is what makes the output independent of the thread
// count. Below parallel_grain triangles a cell holds a Fragment.
struct BuiltNode;
struct BuiltCell {
    CellKind kind = CellKind::Empty;
    TriangleIds triangles;               // leaf
    std::unique_ptr<BuiltNode> node;     // inner
    std::unique_ptr<Fragment> fragment;  // a serially built subtree (kind: its root's)
};
struct BuiltNode {
    int axis = 0;
    float lo = 0.0f;
    float hi = 0.0f;
    std::vector<BuiltCell> cells;
};

// The record of a new node whose cells are still empty: a one-cell node holds its cell, the
// others get a block at the end of `cells`.
inline GridNode new_node(int axis, float lo, float hi, std::uint32_t resolution,
                         std::vector<CellRef>& cells)
{
    if (resolution == 1) return GridNode::make_one_cell(axis, lo, hi, CellRef::make_empty());
    const auto first_cell = static_cast<std::uint32_t>(cells.size());
    cells.resize(cells.size() + resolution);
    return GridNode::make(axis, lo, hi, resolution, first_cell);
}

// Stores cell `c` of node `index`, in the node's record or in its block of `cells`.
inline void store_cell(std::vector<GridNode>& nodes, std::vector<CellRef>& cells,
                       std::uint32_t index, std::uint32_t c, CellRef cell)
{
    GridNode& node = nodes[index];
    if (node.resolution() == 1)
        node.set_only_cell(cell);
    else
        cells[node.first_cell() + c] = cell;
}

// Lays the built tree `root` out in the grid's arrays (which must be empty) and sets
// grid.root: depth-first pre-order, a node's record, then its cells as one block, then its
// children. The arrays get their final size at once; the built tree is released as it is
// laid out. Throws InputError when the grid would exceed its indices (2^30 nodes or leaf
// words, 2^32 cells).
void assemble(BuiltCell& root, SplitGrid& grid);

}  // namespace sg::detail
