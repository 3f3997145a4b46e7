#pragma once

#include <cstdint>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/grid_node.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/stats.hpp"

namespace sg::viz::detail {

/// What the export needs to know about every node, found in one walk of the grid: its box
/// (stored nowhere in the grid), its depth, and the totals of its subtree.
struct NodeFacts {
    Aabb box;
    std::uint32_t depth = 0;
    std::uint64_t subtree_references = 0;  ///< triangle references in all leaves below
    /// Cost of the subtree under the surface-area model of stats.hpp (not normalised):
    /// P(box) * node_cost + P(slab) * cell_cost * expected_cells_crossed
    /// + sum over its cells of their cell_cost() (see below).
    double subtree_cost = 0.0;
};

/// Per-node facts and the total expected cost (equal to compute_stats(grid).sah_cost up to
/// the order of the floating-point sums).
struct Hierarchy {
    const SplitGrid* grid = nullptr;  ///< the grid analysed, which must outlive this
    std::vector<NodeFacts> nodes;  ///< indexed like SplitGrid::nodes
    double total_cost = 0.0;
    CostModel model;
    double root_area = 0.0;  ///< surface area of the root box; P(X) = SA(X) / root_area
};

/// Walks the whole grid once (top-down for boxes and depths, bottom-up for the subtree
/// totals). Precondition: check_invariants(grid) passes.
[[nodiscard]] Hierarchy analyse_hierarchy(const SplitGrid& grid, const CostModel& model = {});

/// The cost of one cell's contents under the model: a leaf's triangle tests
/// P(cell) * triangle_cost * references, an inner cell's whole subtree, 0 for an empty cell.
[[nodiscard]] double cell_cost(const Hierarchy& hierarchy, const CellRef& cell,
                               const Aabb& cell_box) noexcept;

/// Triangle references under a cell: its own for a leaf, its subtree's for an inner cell.
[[nodiscard]] std::uint64_t cell_references(const Hierarchy& hierarchy,
                                            const CellRef& cell) noexcept;

}  // namespace sg::viz::detail
