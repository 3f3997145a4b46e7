#pragma once

// Traversal kernels, part 8: the uniform grid's traversal (baselines/uniform_grid.hpp).

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

/// One axis of the uniform grid as the walk sees it: its cell planes and the ray's crossings.
struct UniformAxis {
    const KernelRay* ray;
    CellMath cells;
    int axis;
    bool parallel;
    bool forward;  ///< the ray moves towards higher cell indices
    float pad;

    [[nodiscard]] float crossing(std::uint32_t boundary) const noexcept
    {
        return ray->crossing(axis, cells.boundary(boundary));
    }
    [[nodiscard]] std::uint32_t entry_plane(std::uint32_t i) const noexcept { return forward ? i : i + 1; }
    [[nodiscard]] std::uint32_t exit_plane(std::uint32_t i) const noexcept { return forward ? i + 1 : i; }
    /// The first cell, in ray order, whose widened interval holds t (a guess from the position
    /// at t, corrected with the same crossings the walk uses); for a parallel ray the cell
    /// holding the origin (the lower one on a plane: triangles touching it are in both).
    [[nodiscard]] std::uint32_t first_cell(float t) const noexcept
    {
        if (parallel) return cells.locate_lowest(ray->origin[axis]);
        std::uint32_t i = cells.guess(ray->origin[axis] + t * ray->direction[axis]);
        auto enters_after = [&](std::uint32_t c) { return crossing(entry_plane(c)) - pad > t; };
        auto leaves_before = [&](std::uint32_t c) { return crossing(exit_plane(c)) + pad < t; };
        if (forward) {
            while (i > 0 && enters_after(i)) --i;
            while (i + 1 < cells.n && leaves_before(i)) ++i;
        } else {
            while (i + 1 < cells.n && enters_after(i)) ++i;
            while (i > 0 && leaves_before(i)) --i;
        }
        return i;
    }
};

/// The 3D-DDA of Amanatides and Woo, made conservative by stepping the three axes as nested
/// one-dimensional DDAs: the x slabs the ray crosses in ray order, within each the y cells
/// over the slab's ray interval, within each of those the z cells. Every plane crossing is
/// widened by the axis's allowance, and a cell is visited when its widened x, y and z
/// intervals overlap inside the ray's window: a superset of the cells the exact ray touches,
/// in ray order. (The classic single walk that steps the axis with the nearest crossing, plus
/// the neighbours of near ties, lost rays whose origins were 10^7 scene units away, where the
/// widening spans many cells; this form loses none.) Each walk stops when its next cell starts
/// after the closest hit or the end of the interval, so a hit found in a cell but lying beyond
/// it is kept while cells in front of it are still visited. Triangles span about two cells each
/// (docs/BASELINES.md): a mailbox tests each once per query.
/// Counters: cells_visited = cells stepped through (side cells included).
template <TriangleTest test, class Search>
inline void walk_uniform_grid(const UniformGrid& grid, const MeshArrays& mesh,
                              const KernelRay& ray, Search& search) noexcept
{
    if (grid.reference_count() == 0) return;
    float t0 = ray.t_min;
    float t1 = ray.t_max;
    if (!ray.clip_box(grid.box(), t0, t1)) return;
    std::array<UniformAxis, 3> axes;
    for (int k = 0; k < 3; ++k)
        axes[static_cast<std::size_t>(k)] = UniformAxis{&ray, grid.axis_cells(k), k, ray.parallel[k],
                                                        !ray.negative[k], ray.pad[k]};

    // Calls inner(cell, lo, hi) for the cells of `g` whose widened interval meets [lo, hi],
    // in ray order, with the overlap; true as soon as inner says the query is done.
    auto step = [&](const UniformAxis& g, float lo, float hi, const auto& inner) {
        std::uint32_t i = g.first_cell(lo);
        if (g.parallel) return inner(i, lo, hi);
        float enter = g.crossing(g.entry_plane(i)) - g.pad;
        for (;;) {
            if (enter > std::min(hi, search.best_t())) return false;
            const float leave = g.crossing(g.exit_plane(i));
            const float cell_lo = std::max(lo, enter);
            const float cell_hi = std::min(hi, leave + g.pad);
            if (cell_lo <= cell_hi && inner(i, cell_lo, cell_hi)) return true;
            if (g.forward ? i + 1 >= g.cells.n : i == 0) return false;
            i = g.forward ? i + 1 : i - 1;
            enter = leave - g.pad;
        }
    };
    Mailbox mailbox;
    const std::span<const std::uint32_t> offsets = grid.cell_offsets();
    const std::uint32_t* const refs = grid.refs().data();
    const std::uint32_t* const refs_end = refs + grid.refs().size();
    auto visit = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) {
        search.count_cell();
        const std::size_t c = grid.cell_index(x, y, z);
        const std::uint32_t first = offsets[c];
        const std::uint32_t count = offsets[c + 1] - first;
        if (count == 0) return false;
        (void)test_id_leaf<test>(ray, mesh, search, mailbox, refs + first, count, refs_end);
        return search.done();
    };
    (void)step(axes[0], t0, t1, [&](std::uint32_t x, float x0, float x1) {
        return step(axes[1], x0, x1, [&](std::uint32_t y, float y0, float y1) {
            return step(axes[2], y0, y1,
                        [&](std::uint32_t z, float, float) { return visit(x, y, z); });
        });
    });
}

}  // namespace sg::kernels::SG_KERNEL_ISA
