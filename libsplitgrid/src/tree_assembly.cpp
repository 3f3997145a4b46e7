#include "tree_assembly.hpp"

#include <cstddef>

#include "splitgrid/error.hpp"
#include "splitgrid/leaf_words.hpp"

namespace sg::detail {
namespace {

// A fragment's cell with its indices shifted past the grid's `node_base` nodes and
// `word_base` leaf words.
CellRef shifted(CellRef cell, std::uint32_t node_base, std::uint32_t word_base)
{
    if (cell.is_inner())
        return CellRef::make_inner(cell.child() + node_base, cell.has_one_cell_child() ? 1 : 2);
    if (cell.is_leaf()) return CellRef::make_leaf(cell.first_word() + word_base);
    return cell;
}

// Appends a serially built subtree, already in pre-order, and releases it.
CellRef append_fragment(Fragment& fragment, SplitGrid& grid)
{
    if (grid.leaf_words.size() + fragment.leaf_words.size() > std::size_t{max_cell_index} + 1)
        throw InputError("Split Grid too large: more than 2^30 leaf words");
    if (grid.nodes.size() + fragment.nodes.size() > std::size_t{max_cell_index} + 1 ||
        grid.cells.size() + fragment.cells.size() > std::size_t{0xFFFFFFFFu})
        throw InputError("Split Grid too large: more than 2^30 nodes or 2^32 cells");
    const auto node_base = static_cast<std::uint32_t>(grid.nodes.size());
    const auto cell_base = static_cast<std::uint32_t>(grid.cells.size());
    const auto word_base = static_cast<std::uint32_t>(grid.leaf_words.size());
    for (const GridNode& node : fragment.nodes) {
        const std::uint32_t cells = node.resolution() == 1
                                        ? shifted(node.only_cell(), node_base, word_base).raw_bits()
                                        : node.first_cell() + cell_base;
        grid.nodes.push_back(GridNode::from_raw(node.lo, node.hi, cells, node.axis_res_bits()));
    }
    for (const CellRef cell : fragment.cells) grid.cells.push_back(shifted(cell, node_base, word_base));
    grid.leaf_words.insert(grid.leaf_words.end(), fragment.leaf_words.begin(),
                           fragment.leaf_words.end());
    const CellRef root = shifted(fragment.root, node_base, word_base);
    fragment = {};
    return root;
}

// Numbers of nodes, cells and leaf words under `cell`.
struct GridSize {
    std::size_t nodes = 0;
    std::size_t cells = 0;
    std::size_t leaf_words = 0;
};
void add_size(const BuiltCell& cell, GridSize& size)
{
    if (cell.fragment) {
        size.nodes += cell.fragment->nodes.size();
        size.cells += cell.fragment->cells.size();
        size.leaf_words += cell.fragment->leaf_words.size();
    } else if (cell.kind == CellKind::Leaf) {
        size.leaf_words += leaf_word_count(cell.triangles);
    } else if (cell.kind == CellKind::Inner) {
        size.nodes += 1;
        if (cell.node->cells.size() >= 2) size.cells += cell.node->cells.size();
        for (const BuiltCell& child : cell.node->cells) add_size(child, size);
    }
}

// Depth-first pre-order: a node's record, then its cells as one block, then its children.
CellRef flatten(BuiltCell& cell, SplitGrid& grid)
{
    if (cell.fragment) {
        const CellRef root = append_fragment(*cell.fragment, grid);
        cell.fragment.reset();
        return root;
    }
    switch (cell.kind) {
    case CellKind::Empty:
        return CellRef::make_empty();
    case CellKind::Leaf: {
        if (grid.leaf_words.size() + leaf_word_count(cell.triangles) >
            std::size_t{max_cell_index} + 1)
            throw InputError("Split Grid too large: more than 2^30 leaf words");
        // Strictly ascending, as emit_leaf's (append_leaf needs it).
        const std::uint32_t first = append_leaf(grid.leaf_words, cell.triangles);
        cell.triangles = {};
        return CellRef::make_leaf(first);
    }
    case CellKind::Inner:
        break;
    }
    BuiltNode& node = *cell.node;
    if (grid.nodes.size() > max_cell_index ||
        grid.cells.size() + node.cells.size() > std::size_t{0xFFFFFFFFu})
        throw InputError("Split Grid too large: more than 2^30 nodes or 2^32 cells");
    const auto index = static_cast<std::uint32_t>(grid.nodes.size());
    const auto resolution = static_cast<std::uint32_t>(node.cells.size());
    grid.nodes.push_back(new_node(node.axis, node.lo, node.hi, resolution, grid.cells));
    for (std::uint32_t c = 0; c < resolution; ++c)
        store_cell(grid.nodes, grid.cells, index, c, flatten(node.cells[c], grid));
    cell.node.reset();
    return CellRef::make_inner(index, resolution);
}

}  // namespace

void assemble(BuiltCell& root, SplitGrid& grid)
{
    // The arrays get their final size at once: growing them by doubling would hold up to
    // three times their size while the built tree is still held too.
    GridSize size;
    add_size(root, size);
    if (size.nodes > std::size_t{max_cell_index} + 1 || size.cells > std::size_t{0xFFFFFFFFu})
        throw InputError("Split Grid too large: more than 2^30 nodes or 2^32 cells");
    if (size.leaf_words > std::size_t{max_cell_index} + 1)
        throw InputError("Split Grid too large: more than 2^30 leaf words");
    grid.nodes.reserve(size.nodes);
    grid.cells.reserve(size.cells);
    grid.leaf_words.reserve(size.leaf_words);
    grid.root = flatten(root, grid);
}

}  // namespace sg::detail
