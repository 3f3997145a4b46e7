#pragma once

// Point queries, part 2: the Split Grid's closest point search (docs/SPLIT_GRID.md, "Closest
// points").

#include "point_search.hpp"
#include "splitgrid/cell_math.hpp"
#include "splitgrid/leaf_words.hpp"
#include "splitgrid/split_grid.hpp"

namespace sg::kernels::points {

/// Depth first from the root, each node's cells nearest first: from the cell holding the
/// point's coordinate on the node's axis (clamped to the node's slab) outwards in both
/// directions, always taking the nearer of the two next cells. A cell's box is the node's box
/// narrowed on the axis to the cell's bounds (CellMath, as the builder assigned triangles),
/// widened by the grid's pad; its distance from the point is the sum of the other axes' part,
/// the same for every cell of the node, and the axis' gap, which only grows outwards, so a
/// direction ends at its first cell beyond the search's bound.
class SplitGridPointWalk {
public:
    SplitGridPointWalk(const SplitGrid& grid, const MeshView& mesh, PointSearch& search,
                       float pad) noexcept
        : grid_(grid), mesh_(mesh), search_(search), pad_(pad)
    {
        const Vec3d q = search.point();
        q_[0] = q.x;
        q_[1] = q.y;
        q_[2] = q.z;
    }

    void run() noexcept
    {
        if (grid_.root.is_empty()) return;
        const Aabb box = widened(grid_.root_box);
        if (search_.prunes(box_distance2(search_.point(), box))) return;
        visit(grid_.root, grid_.root_box);
    }

private:
    [[nodiscard]] Aabb widened(Aabb box) const noexcept
    {
        for (int k = 0; k < 3; ++k) {
            box.lower[k] -= pad_;
            box.upper[k] += pad_;
        }
        return box;
    }

    // The point's gap to [lo, hi] widened by the pad, on `axis`.
    [[nodiscard]] double gap(int axis, float lo, float hi) const noexcept
    {
        const double q = q_[axis];
        return std::max({double{lo} - double{pad_} - q, 0.0, q - (double{hi} + double{pad_})});
    }

    // `box`: the cell's box, unwidened; the caller checked its widened distance.
    void visit(CellRef cell, const Aabb& box) noexcept
    {
        if (cell.is_empty()) return;
        if (cell.is_leaf()) {
            (void)read_leaf(grid_.leaf_words, cell.first_word(), [&](std::uint32_t tri) {
                if (mailbox_.first_visit(tri)) search_.offer(mesh_, tri);
            });
            return;
        }
        const GridNode& node = grid_.nodes[cell.child()];
        const int axis = node.axis();
        const std::uint32_t n = node.resolution();
        // The other axes' part of every cell's distance.
        double across = 0.0;
        for (int k = 0; k < 3; ++k) {
            if (k == axis) continue;
            const double g = gap(k, box.lower[k], box.upper[k]);
            across += g * g;
        }
        const CellMath cells(node.lo, node.hi, n);
        auto enter = [&](std::uint32_t i) {
            const double g = gap(axis, cells.boundary(i), cells.boundary(i + 1));
            const double d2 = across + g * g;
            if (search_.prunes(d2)) return false;
            visit(node_cell(grid_, node, i), cells.cell_box(box, axis, i));
            return true;
        };
        const float clamped = std::clamp(static_cast<float>(q_[axis]), node.lo, node.hi);
        std::uint32_t down = cells.locate_lowest(clamped);  // next cell going down
        std::uint32_t up = down + 1;                         // next cell going up
        bool going_down = true, going_up = up < n;
        while (going_down || going_up) {
            // The nearer of the two next cells first.
            bool take_down = going_down;
            if (going_down && going_up)
                take_down = gap(axis, cells.boundary(down), cells.boundary(down + 1)) <=
                            gap(axis, cells.boundary(up), cells.boundary(up + 1));
            if (take_down) {
                going_down = enter(down) && down > 0;
                if (going_down) --down;
            } else {
                going_up = enter(up) && up + 1 < n;
                if (going_up) ++up;
            }
        }
    }

    const SplitGrid& grid_;
    const MeshView& mesh_;
    PointSearch& search_;
    float pad_;
    double q_[3];
    PointMailbox mailbox_;
};

}  // namespace sg::kernels::points
