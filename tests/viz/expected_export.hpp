#pragma once

// What an export of a grid must contain, worked out here by a recursive walk of the grid that
// shares no code with viz/ (only the library's cell boundaries and the cost model's
// expected_cells_crossed, which define the structure and the cost).

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "splitgrid/cell_math.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/stats.hpp"
#include "support/leaf_triangles.hpp"

namespace sg::test {

struct ExpectedCell {
    Aabb box;
    std::uint32_t depth = 0;
    int axis = -1;
    int kind = 0;  // 0 empty, 1 leaf, 2 inner
    std::uint64_t triangles = 0;
    double cost = 0.0;  // not normalised
};

struct ExpectedPlane {
    Aabb quad;
    std::uint32_t depth = 0;
    int axis = 0;
    double cut_fraction = 0.0;
};

struct ExpectedExport {
    /// Every cell of the grid, empty ones included, by (node_id, cell_index); the root cell of
    /// a grid whose root is not a node is (-1, 0).
    std::map<std::pair<std::int64_t, std::uint32_t>, ExpectedCell> cells;
    /// Both planes of every node, by (node_id, side).
    std::map<std::pair<std::int64_t, int>, ExpectedPlane> planes;
    std::vector<std::uint32_t> node_depth;
    std::vector<std::int64_t> node_parent;  ///< -1 for the root node
    std::vector<std::uint64_t> references_per_triangle;
    double total_cost = 0.0;
};

namespace detail {

struct Totals {
    std::uint64_t references = 0;
    double cost = 0.0;
};

inline Totals walk_node(const SplitGrid& grid, std::uint32_t id, const Aabb& box,
                        std::uint32_t depth, std::int64_t parent, ExpectedExport& e)
{
    const double root_area = grid.root_box.surface_area();
    const GridNode& node = grid.nodes.at(id);
    const int axis = node.axis();
    e.node_depth.at(id) = depth;
    e.node_parent.at(id) = parent;
    Aabb slab = box;
    slab.lower[axis] = node.lo;
    slab.upper[axis] = node.hi;
    Totals t;
    t.cost = box.surface_area() / root_area +
             slab.surface_area() / root_area * expected_cells_crossed(slab, axis, node.resolution());

    const double extent = double(box.upper[axis]) - box.lower[axis];
    for (int side = 0; side < 2; ++side) {
        ExpectedPlane p;
        p.quad = box;
        p.quad.lower[axis] = p.quad.upper[axis] = side == 0 ? node.lo : node.hi;
        p.depth = depth;
        p.axis = axis;
        const double cut = side == 0 ? double(node.lo) - box.lower[axis]
                                     : double(box.upper[axis]) - node.hi;
        p.cut_fraction = extent > 0.0 ? cut / extent : 0.0;
        e.planes[{id, side}] = p;
    }

    const CellMath cm(node.lo, node.hi, node.resolution());
    for (std::uint32_t i = 0; i < node.resolution(); ++i) {
        const CellRef cell = node_cell(grid, node, i);
        ExpectedCell c;
        c.box = box;
        c.box.lower[axis] = cm.boundary(i);
        c.box.upper[axis] = cm.boundary(i + 1);
        c.depth = depth;
        c.axis = axis;
        if (cell.is_leaf()) {
            c.kind = 1;
            const std::vector<std::uint32_t> ids = test::leaf_triangles(grid, cell);
            c.triangles = ids.size();
            c.cost = c.box.surface_area() / root_area * static_cast<double>(ids.size());
            for (const std::uint32_t tri : ids) ++e.references_per_triangle.at(tri);
        } else if (cell.is_inner()) {
            c.kind = 2;
            const Totals sub = walk_node(grid, cell.child(), c.box, depth + 1, id, e);
            c.triangles = sub.references;
            c.cost = sub.cost;
        }
        t.references += c.triangles;
        t.cost += c.cost;
        e.cells[{id, i}] = c;
    }
    return t;
}

}  // namespace detail

/// The expected contents of a full export of `grid` under the unit cost model of stats.hpp.
inline ExpectedExport expected_export(const SplitGrid& grid)
{
    ExpectedExport e;
    e.node_depth.assign(grid.nodes.size(), 0);
    e.node_parent.assign(grid.nodes.size(), -1);
    e.references_per_triangle.assign(grid.triangle_count, 0);
    if (grid.root.is_inner()) {
        e.total_cost = detail::walk_node(grid, grid.root.child(), grid.root_box, 0, -1, e).cost;
    } else {
        ExpectedCell c;
        c.box = grid.root_box;
        c.kind = grid.root.is_leaf() ? 1 : 0;
        const std::vector<std::uint32_t> ids =
            grid.root.is_leaf() ? test::leaf_triangles(grid, grid.root) : std::vector<std::uint32_t>{};
        c.triangles = ids.size();
        c.cost = static_cast<double>(c.triangles);
        for (const std::uint32_t t : ids) ++e.references_per_triangle.at(t);
        e.cells[{-1, 0}] = c;
        e.total_cost = c.cost;
    }
    return e;
}

}  // namespace sg::test
