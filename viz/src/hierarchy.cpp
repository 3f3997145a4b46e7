#include "hierarchy.hpp"

#include <cstddef>

#include "splitgrid/cell_math.hpp"

namespace sg::viz::detail {

double cell_cost(const Hierarchy& hierarchy, const CellRef& cell, const Aabb& cell_box) noexcept
{
    if (cell.is_inner()) return hierarchy.nodes[cell.child()].subtree_cost;
    if (cell.is_leaf() && hierarchy.root_area > 0.0)
        return cell_box.surface_area() / hierarchy.root_area * hierarchy.model.triangle_cost *
               static_cast<double>(leaf_size(*hierarchy.grid, cell));
    return 0.0;
}

std::uint64_t cell_references(const Hierarchy& hierarchy, const CellRef& cell) noexcept
{
    if (cell.is_inner()) return hierarchy.nodes[cell.child()].subtree_references;
    return cell.is_leaf() ? leaf_size(*hierarchy.grid, cell) : 0;
}

Hierarchy analyse_hierarchy(const SplitGrid& grid, const CostModel& model)
{
    Hierarchy h;
    h.grid = &grid;
    h.model = model;
    h.nodes.resize(grid.nodes.size());
    h.root_area = grid.root_box.surface_area();
    const auto probability = [&](const Aabb& box) {
        return h.root_area > 0.0 ? box.surface_area() / h.root_area : 0.0;
    };

    // Top-down: boxes and depths, recording the visiting order so that the bottom-up pass
    // below sees every child before its parent without relying on how the builder ordered
    // the node array.
    std::vector<std::uint32_t> order;
    order.reserve(grid.nodes.size());
    if (grid.root.is_inner()) {
        h.nodes[grid.root.child()].box = grid.root_box;
        order.push_back(grid.root.child());
    }
    for (std::size_t k = 0; k < order.size(); ++k) {
        const std::uint32_t id = order[k];
        const GridNode& node = grid.nodes[id];
        const CellMath cm(node.lo, node.hi, node.resolution());
        for (std::uint32_t i = 0; i < node.resolution(); ++i) {
            const CellRef cell = node_cell(grid, node, i);
            if (!cell.is_inner()) continue;
            NodeFacts& child = h.nodes[cell.child()];
            child.box = cm.cell_box(h.nodes[id].box, node.axis(), i);
            child.depth = h.nodes[id].depth + 1;
            order.push_back(cell.child());
        }
    }

    // Bottom-up: subtree references and cost, the same terms as compute_stats().
    for (std::size_t k = order.size(); k-- > 0;) {
        const std::uint32_t id = order[k];
        const GridNode& node = grid.nodes[id];
        NodeFacts& facts = h.nodes[id];
        const int axis = node.axis();
        Aabb slab = facts.box;
        slab.lower[axis] = node.lo;
        slab.upper[axis] = node.hi;
        facts.subtree_cost =
            probability(facts.box) * model.node_cost +
            probability(slab) * model.cell_cost *
                expected_cells_crossed(slab, axis, node.resolution());
        const CellMath cm(node.lo, node.hi, node.resolution());
        for (std::uint32_t i = 0; i < node.resolution(); ++i) {
            const CellRef cell = node_cell(grid, node, i);
            facts.subtree_references += cell_references(h, cell);
            facts.subtree_cost += cell_cost(h, cell, cm.cell_box(facts.box, axis, i));
        }
    }
    h.total_cost = cell_cost(h, grid.root, grid.root_box);
    return h;
}

}  // namespace sg::viz::detail
