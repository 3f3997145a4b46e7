#include "selection.hpp"

#include <string>

#include "splitgrid/error.hpp"

namespace sg::viz::detail {

std::vector<std::uint32_t> selected_nodes(const SplitGrid& grid, const Hierarchy& hierarchy,
                                          const Selection& selection)
{
    std::vector<std::uint32_t> pending;
    if (selection.subtree) {
        const std::uint32_t start = *selection.subtree;
        if (start >= grid.nodes.size())
            throw ConfigError(
                "subtree node " + std::to_string(start) + " does not exist: " +
                (grid.nodes.empty() ? std::string("the structure has no nodes")
                                    : "node ids go from 0 to " +
                                          std::to_string(grid.nodes.size() - 1)));
        pending.push_back(start);
    } else if (grid.root.is_inner()) {
        pending.push_back(grid.root.child());
    }

    // Depth-first, children pushed in reverse so that they come out in cell order.
    std::vector<std::uint32_t> selected;
    while (!pending.empty()) {
        const std::uint32_t id = pending.back();
        pending.pop_back();
        const std::uint32_t depth = hierarchy.nodes[id].depth;
        if (depth > selection.max_depth) continue;
        if (depth >= selection.min_depth) selected.push_back(id);
        const GridNode& node = grid.nodes[id];
        for (std::uint32_t i = node.resolution(); i-- > 0;) {
            const CellRef cell = node_cell(grid, node, i);
            if (cell.is_inner()) pending.push_back(cell.child());
        }
    }
    return selected;
}

bool root_cell_selected(const SplitGrid& grid, const Selection& selection) noexcept
{
    return !grid.root.is_inner() && !selection.subtree && selection.min_depth == 0 &&
           is_exported(grid.root, selection);
}

CellRecord root_cell_record(const SplitGrid& grid, const Hierarchy& hierarchy)
{
    CellRecord r;
    r.box = grid.root_box;
    r.kind = grid.root.kind();
    r.triangle_count = grid.root.is_leaf() ? leaf_size(grid, grid.root) : 0;
    r.cost_share = hierarchy.total_cost > 0.0 ? 1.0 : 0.0;
    return r;
}

PlaneRecord plane_record(const SplitGrid& grid, const Hierarchy& hierarchy, std::uint32_t id,
                         int side)
{
    const GridNode& node = grid.nodes[id];
    const NodeFacts& facts = hierarchy.nodes[id];
    PlaneRecord r;
    r.depth = facts.depth;
    r.node_id = id;
    r.side = side;
    r.axis = node.axis();
    const float at = side == 0 ? node.lo : node.hi;
    r.quad = facts.box;
    r.quad.lower[r.axis] = at;
    r.quad.upper[r.axis] = at;
    // In double: a float extent of a box near +-FLT_MAX overflows.
    const double extent = double(facts.box.upper[r.axis]) - facts.box.lower[r.axis];
    const double cut = side == 0 ? double(node.lo) - facts.box.lower[r.axis]
                                 : double(facts.box.upper[r.axis]) - node.hi;
    r.cut_fraction = extent > 0.0 ? cut / extent : 0.0;
    return r;
}

}  // namespace sg::viz::detail
