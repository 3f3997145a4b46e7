#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "hierarchy.hpp"
#include "splitgrid/aabb.hpp"
#include "splitgrid/cell_math.hpp"
#include "splitgrid/grid_node.hpp"
#include "splitgrid/split_grid.hpp"

namespace sg::viz::detail {

/// The part of ExportOptions that picks nodes and cells (see vtk_export.hpp).
struct Selection {
    std::uint32_t min_depth = 0;
    std::uint32_t max_depth = 0;
    std::optional<std::uint32_t> subtree;
    bool empty_cells = false;
};

/// One exported cell, with the values of its cell-data arrays (docs/VIZ.md).
struct CellRecord {
    Aabb box;
    std::uint32_t depth = 0;
    std::int64_t node_id = -1;  ///< -1: the root cell of a grid whose root is not a node
    std::uint32_t cell_index = 0;
    int axis = -1;              ///< -1 for the root cell
    CellKind kind = CellKind::Empty;
    std::uint64_t triangle_count = 0;
    double cost_share = 0.0;
};

/// One exported bounding plane: a flat box (zero extent on `axis`) spanning the node's box.
struct PlaneRecord {
    Aabb quad;
    std::uint32_t depth = 0;
    std::uint32_t node_id = 0;
    int side = 0;  ///< 0: the lo plane, 1: the hi plane
    int axis = 0;
    double cut_fraction = 0.0;  ///< share of the node's extent on `axis` it cuts away
};

/// The selected nodes, parents before children. Throws ConfigError if the subtree node does
/// not exist. Nodes deeper than max_depth are not visited at all.
[[nodiscard]] std::vector<std::uint32_t> selected_nodes(const SplitGrid& grid,
                                                        const Hierarchy& hierarchy,
                                                        const Selection& selection);

/// True if the grid's root is not a node (a single leaf, or empty) and the selection takes
/// its one cell, the root box: depth 0 selected, no subtree, and a leaf or empty_cells.
[[nodiscard]] bool root_cell_selected(const SplitGrid& grid, const Selection& selection) noexcept;

/// The record of the root cell (see root_cell_selected).
[[nodiscard]] CellRecord root_cell_record(const SplitGrid& grid, const Hierarchy& hierarchy);

/// Whether a cell of this kind is exported under `selection` (empty ones only on request).
[[nodiscard]] inline bool is_exported(const CellRef& cell, const Selection& selection) noexcept
{
    return !cell.is_empty() || selection.empty_cells;
}

/// Calls visit(const CellRecord&) for every exported cell of `nodes` (in node order, then
/// cell order), after the root cell if it is selected.
template <class Visit>
void for_each_cell(const SplitGrid& grid, const Hierarchy& hierarchy,
                   const std::vector<std::uint32_t>& nodes, const Selection& selection,
                   Visit&& visit)
{
    if (root_cell_selected(grid, selection)) visit(root_cell_record(grid, hierarchy));
    for (const std::uint32_t id : nodes) {
        const GridNode& node = grid.nodes[id];
        const NodeFacts& facts = hierarchy.nodes[id];
        const CellMath cm(node.lo, node.hi, node.resolution());
        for (std::uint32_t i = 0; i < node.resolution(); ++i) {
            const CellRef cell = node_cell(grid, node, i);
            if (!is_exported(cell, selection)) continue;
            CellRecord r;
            r.box = cm.cell_box(facts.box, node.axis(), i);
            r.depth = facts.depth;
            r.node_id = id;
            r.cell_index = i;
            r.axis = node.axis();
            r.kind = cell.kind();
            r.triangle_count = cell_references(hierarchy, cell);
            r.cost_share = hierarchy.total_cost > 0.0
                               ? cell_cost(hierarchy, cell, r.box) / hierarchy.total_cost
                               : 0.0;
            visit(r);
        }
    }
}

/// The lo (side 0) or hi (side 1) bounding plane of node `id`.
[[nodiscard]] PlaneRecord plane_record(const SplitGrid& grid, const Hierarchy& hierarchy,
                                       std::uint32_t id, int side);

}  // namespace sg::viz::detail
