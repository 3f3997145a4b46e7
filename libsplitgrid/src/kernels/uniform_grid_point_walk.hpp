#pragma once

// Traversal kernels, part 13: the uniform grid's closest point search (baselines/uniform_grid.hpp).

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

/// Squared gap of coordinate q to cell i of `cells`, widened by `pad`.
[[nodiscard]] inline double uniform_gap2(const CellMath& cells, double q, float pad,
                                         std::int64_t i) noexcept
{
    const auto c = static_cast<std::uint32_t>(i);
    const double g = std::max({double{cells.boundary(c)} - double{pad} - q, 0.0,
                               q - (double{cells.boundary(c + 1)} + double{pad})});
    return g * g;
}

/// Shell after shell of cells around the cell nearest the point (its position clamped to the
/// grid): shell s holds the cells s steps away in the largest of the three axes. Every cell of
/// shell s + 1 lies behind a cell of shell s as seen from the point (one step nearer the
/// centre on each axis it is farthest on), so the nearest cell of each shell is no nearer than
/// that of the shell before: the search ends at the first shell whose every cell lies beyond
/// its bound. A cell is tested when its box, widened by the pad the builder assigned triangles
/// with, lies within the bound.
inline void walk_uniform_grid_points(const UniformGrid& grid, const MeshArrays& mesh,
                                     points::PointSearch& search, float pad) noexcept
{
    if (grid.cell_count() == 0) return;
    const points::Vec3d q = search.point();
    const double qk[3] = {q.x, q.y, q.z};
    const std::array<std::uint32_t, 3> n = grid.resolution();
    std::array<CellMath, 3> cells;
    std::array<std::int64_t, 3> centre;
    for (std::size_t k = 0; k < 3; ++k) {
        const int axis = static_cast<int>(k);
        cells[k] = grid.axis_cells(axis);
        const Aabb& box = grid.box();
        const float clamped =
            std::clamp(static_cast<float>(qk[k]), box.lower[axis], box.upper[axis]);
        centre[k] = cells[k].locate_lowest(clamped);
    }
    const std::uint32_t* const refs = grid.refs().data();
    const std::uint32_t* const refs_end = refs + grid.refs().size();
    const std::span<const std::uint32_t> offsets = grid.cell_offsets();
    Mailbox mailbox;  // a triangle spans about two cells
    const std::int64_t widest = std::max({n[0], n[1], n[2]});
    for (std::int64_t s = 0; s <= widest; ++s) {
        bool any_within = false;
        std::array<std::int64_t, 3> lo, hi;
        for (std::size_t k = 0; k < 3; ++k) {
            lo[k] = std::max<std::int64_t>(0, centre[k] - s);
            hi[k] = std::min<std::int64_t>(std::int64_t{n[k]} - 1, centre[k] + s);
        }
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z) {
            const double dz = uniform_gap2(cells[2], qk[2], pad, z);
            const bool z_face = z == centre[2] - s || z == centre[2] + s;
            for (std::int64_t y = lo[1]; y <= hi[1]; ++y) {
                const double dyz = dz + uniform_gap2(cells[1], qk[1], pad, y);
                const bool yz_face = z_face || y == centre[1] - s || y == centre[1] + s;
                // On the shell: all of the x row when z or y is on its face, else its two ends.
                const std::int64_t step = yz_face ? 1 : 2 * s;
                for (std::int64_t x = centre[0] - s; x <= centre[0] + s; x += step == 0 ? 1 : step) {
                    if (x < lo[0] || x > hi[0]) continue;
                    const double d2 = dyz + uniform_gap2(cells[0], qk[0], pad, x);
                    if (search.prunes(d2)) continue;
                    any_within = true;
                    const std::size_t c = grid.cell_index(static_cast<std::uint32_t>(x),
                                                          static_cast<std::uint32_t>(y),
                                                          static_cast<std::uint32_t>(z));
                    if (offsets[c + 1] > offsets[c])
                        test_point_ids(search, mesh, mailbox, refs + offsets[c],
                                       offsets[c + 1] - offsets[c], refs_end);
                }
            }
        }
        if (!any_within) return;
    }
}

}  // namespace sg::kernels::SG_KERNEL_ISA
