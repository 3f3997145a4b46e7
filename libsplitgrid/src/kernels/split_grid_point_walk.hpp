#pragma once

// Traversal kernels, part 10: the Split Grid's closest point search (docs/SPLIT_GRID.md, "Closest
// points").

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

/// Depth first from the root, each node's cells nearest first: from the cell holding the
/// point's coordinate on the node's axis (clamped to the node's slab) outwards in both
/// directions, always taking the nearer of the two next cells. A cell's box is the node's box
/// narrowed on the axis to the cell's bounds (CellMath, as the builder assigned triangles),
/// widened by the grid's pad; its distance from the point is the sum of the other axes' part,
/// the same for every cell of the node, and the axis' gap, which only grows outwards, so a
/// direction ends at its first cell beyond the search's bound. A leaf's references are
/// measured eight at a time (test_point_lanes).
class SplitGridPointWalk {
public:
    SplitGridPointWalk(const SplitGrid& grid, const MeshArrays& mesh, points::PointSearch& search,
                       float pad) noexcept
        : grid_(grid), mesh_(mesh), search_(search), pad_(pad)
    {
        const points::Vec3d q = search.point();
        q_[0] = q.x;
        q_[1] = q.y;
        q_[2] = q.z;
    }

    void run() noexcept
    {
        if (grid_.root.is_empty()) return;
        Aabb box = grid_.root_box;
        for (int k = 0; k < 3; ++k) {
            box.lower[k] -= pad_;
            box.upper[k] += pad_;
        }
        if (search_.prunes(points::box_distance2(search_.point(), box))) return;
        visit(grid_.root, grid_.root_box);
    }

private:
    // The point's gap to [lo, hi] widened by the pad, on `axis`.
    [[nodiscard]] double gap(int axis, float lo, float hi) const noexcept
    {
        const double q = q_[axis];
        return std::max({double{lo} - double{pad_} - q, 0.0, q - (double{hi} + double{pad_})});
    }

    void test_leaf(CellRef cell) noexcept
    {
        PointBatch<Mailbox> batch(search_, mesh_, mailbox_);
        const std::uint16_t* words = grid_.leaf_words.data();
        for_each_leaf_batch(words + cell.first_word(), words + grid_.leaf_words.size(), batch);
    }

    // `box`: the cell's box, unwidened; the caller checked its widened distance.
    void visit(CellRef cell, const Aabb& box) noexcept
    {
        if (cell.is_empty()) return;
        if (cell.is_leaf()) {
            test_leaf(cell);
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
        const float clamped = std::clamp(static_cast<float>(q_[axis]), node.lo, node.hi);
        std::uint32_t down = cells.locate_lowest(clamped);  // next cell going down
        std::uint32_t up = down + 1;                         // next cell going up
        double down_gap = gap(axis, cells.boundary(down), cells.boundary(down + 1));
        double up_gap = up < n ? gap(axis, cells.boundary(up), cells.boundary(up + 1)) : 0.0;
        bool going_down = true, going_up = up < n;
        while (going_down || going_up) {
            // The nearer of the two next cells first; a direction ends at its first cell
            // beyond the bound.
            if (going_down && (!going_up || down_gap <= up_gap)) {
                going_down = !search_.prunes(across + down_gap * down_gap);
                if (!going_down) continue;
                visit(node_cell(grid_, node, down), cells.cell_box(box, axis, down));
                going_down = down > 0;
                if (going_down) {
                    --down;
                    down_gap = gap(axis, cells.boundary(down), cells.boundary(down + 1));
                }
            } else {
                going_up = !search_.prunes(across + up_gap * up_gap);
                if (!going_up) continue;
                visit(node_cell(grid_, node, up), cells.cell_box(box, axis, up));
                going_up = up + 1 < n;
                if (going_up) {
                    ++up;
                    up_gap = gap(axis, cells.boundary(up), cells.boundary(up + 1));
                }
            }
        }
    }

    const SplitGrid& grid_;
    const MeshArrays& mesh_;
    points::PointSearch& search_;
    float pad_;
    double q_[3];
    Mailbox mailbox_;
};

}  // namespace sg::kernels::SG_KERNEL_ISA
