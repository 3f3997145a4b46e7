#pragma once

// Traversal kernels, part 5: the Split Grid's traversal (docs/SPLIT_GRID.md, "Traversal").

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

/// 1 / n for a node's resolution: a table up to 64 cells (every default build), a division
/// beyond. The traverser needs the cell width only within the crossing allowance, so this
/// product replaces the builder's exact (hi - lo) / n (docs/SPLIT_GRID.md).
[[nodiscard]] inline float reciprocal_resolution(std::uint32_t n) noexcept
{
    static constexpr std::array<float, 65> table = [] {
        std::array<float, 65> t{};
        for (std::size_t i = 1; i < t.size(); ++i) t[i] = 1.0f / static_cast<float>(i);
        return t;
    }();
    return n < table.size() ? table[n] : 1.0f / static_cast<float>(n);
}

/// A node whose cells are being walked (the walked one in registers, its ancestors with cells
/// left on the stack while a child is visited). The ray parameter of the node's k-th cell
/// boundary is t_lo + k * dt (dt < 0 for a ray going down the axis); cells are visited from
/// `cell` in steps of `step` until `end`.
struct GridCursor {
    float t_lo;
    float dt;
    float enter;  ///< widened entry of `cell` (for the first one, the node's own entry)
    float t1;     ///< the ray's exit from the node's slab, widened
    float pad;    ///< the crossing allowance of the node's axis
    std::int32_t cell;
    std::int32_t end;
    std::int32_t step;
    std::uint32_t first_cell;
};

/// Max stack depth: one cursor per ancestor of the deepest node (check_invariants bounds
/// the depth by max_supported_depth); only ancestors with cells left are kept.
inline constexpr std::size_t grid_stack_size = max_supported_depth + 1;

/// Walks the Split Grid front to back for `ray`, testing leaves with `test` and keeping the
/// result in `search`. Per node entry: one slab clip (two crossings) and the entry cell from
/// one multiply by 1 / dt (a division that depends on the node's record only, so it runs
/// beside the clip instead of after it), no correction loop, and a prefetch of the node's
/// first cells; per cell: one crossing (a multiply and an add) and two compares; per
/// non-empty cell, a prefetch of what the node's next cell leads to. The instructions,
/// mispredicted branches and cache misses this costs per ray, walk and triangle tests apart,
/// are counted in docs/notebook/trace.md, "Triangles loaded as rows, not gathered". A class
/// rather than lambdas: GCC compiles lambdas without the instruction set of the target region
/// they are written in.
template <TriangleTest test, class Search>
class SplitGridWalk {
public:
    SplitGridWalk(const SplitGrid& grid, const MeshArrays& mesh, const KernelRay& ray,
                  Search& search) noexcept
        : grid_(grid), mesh_(mesh), ray_(ray), search_(search)
    {
    }

    void run() noexcept
    {
        float t0 = ray_.t_min;
        float t1 = ray_.t_max;
        if (grid_.root.is_empty() || !ray_.clip_box(grid_.root_box, t0, t1)) return;
        if (grid_.root.is_leaf()) {
            (void)test_leaf_cell(grid_.root);
            return;
        }
        // The cursor of the node being walked lives in registers; the stack keeps only the
        // ancestors that still have cells left. (Walked in place on the stack, every cell step
        // stored its cursor and loaded it back, a store-to-load round trip on the chain from
        // one cell's index to the next cell's load.)
        const CellRef* const cells = grid_.cells.data();
        GridCursor c{};
        Entry entry = enter_node(grid_.root, t0, t1, c);
        for (;;) {
            if (entry == Entry::done) return;
            // Cells are in ray order: once one starts past the closest hit so far (or past the
            // node), so do all after it.
            if (entry == Entry::none || c.cell == c.end ||
                c.enter > std::min(c.t1, search_.best_t())) {
                if (sp_ == 0) return;
                c = stack_[--sp_];
                entry = Entry::cursor;
                continue;
            }
            const std::int32_t exit_boundary = c.step > 0 ? c.cell + 1 : c.cell;
            const float t_exit = c.t_lo + static_cast<float>(exit_boundary) * c.dt;
            const float c0 = c.enter;
            // Operand order matters for extreme rays (t_exit NaN): std::min and std::max return
            // their first operand when the second is NaN.
            const float c1 = std::min(c.t1, t_exit + c.pad);
            // The plane this cell is left through is the plane the next one is entered through.
            c.enter = std::max(c.enter, t_exit - c.pad);
            const CellRef cell = cells[c.first_cell + static_cast<std::uint32_t>(c.cell)];
            c.cell += c.step;
            search_.count_cell();
            if (cell.is_empty() || c0 > c1) continue;
            if (c.cell != c.end)
                prefetch_target(cells[c.first_cell + static_cast<std::uint32_t>(c.cell)]);
            if (cell.is_leaf()) {
                if (test_leaf_cell(cell) && search_.done()) return;
                continue;
            }
            // Descend. This node is kept for later only if it has cells left; a full stack
            // (ruled out by check_invariants, which bounds the depth) ends the walk rather
            // than overflow.
            if (c.cell != c.end) {
                SG_ASSERT(sp_ < grid_stack_size);
                if (sp_ >= grid_stack_size) return;
                stack_[sp_++] = c;
            }
            entry = enter_node(cell, c0, c1, c);
        }
    }

private:
    /// What a node entry leaves: nothing to walk, a cursor to walk, or a finished any-hit query.
    enum class Entry { none, cursor, done };

    // Asks the cache for what the node's next cell leads to (its child's record, or its
    // leaf's first references) while this cell's leaf or subtree is visited: the walk comes
    // back to that cell only afterwards, if the ray gets that far (an empty cell asks for the
    // first reference). The addresses are computed as integers, since the index of one kind
    // may lie past the end of the other's array. GCC compiles the choice as a branch on the
    // kind; a mask instead traced slower (docs/notebook/trace.md, "The next cell's target asked
    // for ahead (prefetch)").
    [[gnu::always_inline]] void prefetch_target(CellRef next) const noexcept
    {
        const std::uintptr_t node = reinterpret_cast<std::uintptr_t>(grid_.nodes.data()) +
                                    std::uintptr_t{next.child()} * sizeof(GridNode);
        const std::uintptr_t words = reinterpret_cast<std::uintptr_t>(grid_.leaf_words.data()) +
                                     std::uintptr_t{next.first_word()} * sizeof(std::uint16_t);
        __builtin_prefetch(reinterpret_cast<const void*>(next.is_inner() ? node : words));
    }

    bool test_leaf_cell(CellRef cell) noexcept
    {
        const std::uint16_t* words = grid_.leaf_words.data();
        return test_packed_leaf<test>(ray_, mesh_, search_, mailbox_, words + cell.first_word(),
                                      words + grid_.leaf_words.size());
    }

    // Enters the child of the inner cell `inner`: clips [n0, n1] to the node's slab and sets
    // `c` to a cursor at the first cell the ray may be in. A one-cell node (a bounding node on
    // one axis) makes no cursor: its cell, kept in its record, is entered at once over the
    // clipped interval, and a chain of them is one loop. Which of the two a child is, the
    // cell's kind says, so the branch does not wait for the child's record to arrive. Always
    // inlined, so that `c` stays in registers.
    [[gnu::always_inline]] Entry enter_node(CellRef inner, float n0, float n1,
                                            GridCursor& c) noexcept
    {
        while (inner.has_one_cell_child()) {
            search_.count_node();
            const GridNode node = grid_.nodes[inner.child()];
            SG_ASSERT(node.resolution() == 1);  // check_invariants checks the kind
            // An extreme ray (crossings near FLT_MAX) is clipped here as make_cursor clips it;
            // its walk over the one cell would then keep the clipped interval.
            const int axis = node.axis();
            if (ray_.parallel[axis]) {
                const float o = ray_.origin[axis];
                if (!(o >= node.lo && o <= node.hi)) return Entry::none;
            } else if (float t_lo; !clip_to_slab(node, axis, n0, n1, t_lo)) {
                return Entry::none;
            }
            const CellRef cell = node.only_cell();
            search_.count_cell();
            if (cell.is_leaf())
                return test_leaf_cell(cell) && search_.done() ? Entry::done : Entry::none;
            if (!cell.is_inner()) return Entry::none;
            inner = cell;
        }
        search_.count_node();
        SG_ASSERT(grid_.nodes[inner.child()].resolution() >= 2);
        return make_cursor(grid_.nodes[inner.child()], n0, n1, c);
    }

    // Clips [n0, n1] to the node's slab widened by the axis's crossing allowance; false when
    // nothing is left. `t_lo` is the crossing of the lower plane.
    [[gnu::always_inline]] bool clip_to_slab(const GridNode& node, int axis, float& n0,
                                             float& n1, float& t_lo) const noexcept
    {
        const float pad = ray_.pad[axis];
        t_lo = ray_.crossing(axis, node.lo);
        const float t_hi = ray_.crossing(axis, node.hi);
        n0 = std::max(n0, std::min(t_lo, t_hi) - pad);
        n1 = std::min(n1, std::max(t_lo, t_hi) + pad);
        return n0 <= n1;
    }

    [[gnu::always_inline]] Entry make_cursor(const GridNode& node, float n0, float n1,
                                             GridCursor& c) noexcept
    {
        const int axis = node.axis();
        const std::uint32_t n = node.resolution();
        if (ray_.parallel[axis]) {
            // Parallel to the axis: the ray stays in the cell of its origin (the lowest one if
            // the origin lies on a boundary: triangles there are referenced by both cells).
            const float o = ray_.origin[axis];
            if (!(o >= node.lo && o <= node.hi)) return Entry::none;
            const auto cell =
                static_cast<std::int32_t>(CellMath(node.lo, node.hi, n).locate_lowest(o));
            c = GridCursor{std::numeric_limits<float>::infinity(), 0.0f, n0, n1, 0.0f,
                           cell, cell + 1, 1, node.first_cell()};
            return Entry::cursor;
        }
        // The entry cell is found from the interval as received, so that its multiply does not
        // wait for the clip (an earlier start only adds cells; docs/SPLIT_GRID.md).
        const float n0_in = n0;
        float t_lo;
        if (!clip_to_slab(node, axis, n0, n1, t_lo)) return Entry::none;
        const float pad = ray_.pad[axis];
        // Walk direction without a branch (its sign is the ray's, unpredictable per node):
        // up the axis from cell 0 to n - 1, or down from n - 1 to 0.
        const bool up = !ray_.negative[axis];
        const std::int32_t down = ray_.negative[axis] ? 1 : 0;
        const std::int32_t end = (static_cast<std::int32_t>(n) + 1) * (1 - down) - 1;
        const std::int32_t step = 1 - 2 * down;
        // The node's first cells, asked for while the entry cell is computed (its index
        // depends on the record's planes; where the cells lie, only on its first_cell).
        __builtin_prefetch(grid_.cells.data() + node.first_cell());
        if (ray_.extreme) {
            // Crossings near FLT_MAX: every cell, in ray order, over the node's whole interval.
            // A NaN t_lo makes every extrapolated crossing NaN, which the walk's std::min and
            // std::max drop (they keep their first operand), so no cell interval shrinks.
            const std::int32_t first = up ? 0 : static_cast<std::int32_t>(n) - 1;
            c = GridCursor{std::numeric_limits<float>::quiet_NaN(), 0.0f, n0, n1, pad,
                           first, end, step, node.first_cell()};
            return Entry::cursor;
        }
        const float dt = (node.hi - node.lo) * reciprocal_resolution(n) * ray_.inv[axis];
        // The first cell in ray order whose widened interval may reach n0: position of the
        // parameter n0_in - pad in cell units, rounded down (it is a lower bound going up the
        // axis and, dt being negative, an upper bound going down). 1 / dt and the product
        // round twice where a division rounds once; the allowance covers both
        // (docs/SPLIT_GRID.md). Where x is not finite (a flat node, dt = 0, or cells so thin
        // in t that 1 / dt overflows) the walk starts at the node's first cell in ray order,
        // which can only add cells. (std::max(0, x) is a min/max instruction, not a branch.)
        const float last = static_cast<float>(n - 1);
        const float cells_per_t = 1.0f / dt;
        float x = (n0_in - pad - t_lo) * cells_per_t;
        if (!(std::abs(x) <= std::numeric_limits<float>::max())) x = up ? 0.0f : last;
        const auto cell = static_cast<std::int32_t>(std::min(last, std::max(0.0f, x)));
        c = GridCursor{t_lo, dt, n0, n1, pad, cell, end, step, node.first_cell()};
        return Entry::cursor;
    }

    const SplitGrid& grid_;
    const MeshArrays& mesh_;
    const KernelRay& ray_;
    Search& search_;
    Mailbox mailbox_;
    std::array<GridCursor, grid_stack_size> stack_;  // not zeroed: only [0, sp_) is ever read
    std::size_t sp_ = 0;
};

template <TriangleTest test, class Search>
inline void walk_split_grid(const SplitGrid& grid, const MeshArrays& mesh, const KernelRay& ray,
                            Search& search) noexcept
{
    SplitGridWalk<test, Search>(grid, mesh, ray, search).run();
}

}  // namespace sg::kernels::SG_KERNEL_ISA
