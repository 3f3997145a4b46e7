#pragma once

// Point queries, part 5: the uniform grid's closest point search (baselines/uniform_grid.hpp).

#include <array>

#include "point_search.hpp"
#include "splitgrid/baselines/uniform_grid.hpp"

namespace sg::kernels::points {

/// Shell after shell of cells around the cell nearest the point (its position clamped to the
/// grid): shell s holds the cells s steps away in the largest of the three axes. Every cell of
/// shell s + 1 lies behind a cell of shell s as seen from the point (one step nearer the
/// centre on each axis it is farthest on), so the nearest cell of each shell is no nearer than
/// that of the shell before: the search ends at the first shell whose every cell lies beyond
/// its bound. A cell is tested when its box, widened by the pad the builder assigned triangles
/// with, lies within the bound.
inline void walk_uniform_grid(const UniformGrid& grid, const MeshView& mesh, PointSearch& search,
                              float pad) noexcept
{
    if (grid.cell_count() == 0) return;
    const Vec3d q = search.point();
    const double qk[3] = {q.x, q.y, q.z};
    const std::array<std::uint32_t, 3> n = grid.resolution();
    std::array<CellMath, 3> cells;
    std::array<std::int64_t, 3> centre;
    for (int k = 0; k < 3; ++k) {
        cells[k] = grid.axis_cells(k);
        const Aabb& box = grid.box();
        const float clamped = std::clamp(static_cast<float>(qk[k]), box.lower[k], box.upper[k]);
        centre[k] = cells[k].locate_lowest(clamped);
    }
    // Squared gap of the point to cell i on axis k, widened by the pad.
    auto gap2 = [&](int k, std::int64_t i) {
        const auto c = static_cast<std::uint32_t>(i);
        const double g = std::max({double{cells[k].boundary(c)} - pad - qk[k], 0.0,
                                   qk[k] - (double{cells[k].boundary(c + 1)} + pad)});
        return g * g;
    };
    PointMailbox mailbox;  // a triangle spans about two cells
    const std::int64_t widest = std::max({n[0], n[1], n[2]});
    for (std::int64_t s = 0; s <= widest; ++s) {
        bool any_within = false;
        std::array<std::int64_t, 3> lo, hi;
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::max<std::int64_t>(0, centre[k] - s);
            hi[k] = std::min<std::int64_t>(n[k] - 1, centre[k] + s);
        }
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z) {
            const double dz = gap2(2, z);
            const bool z_face = z == centre[2] - s || z == centre[2] + s;
            for (std::int64_t y = lo[1]; y <= hi[1]; ++y) {
                const double dyz = dz + gap2(1, y);
                const bool yz_face = z_face || y == centre[1] - s || y == centre[1] + s;
                // On the shell: all of the x row when z or y is on its face, else its two ends.
                const std::int64_t step = yz_face ? 1 : 2 * s;
                for (std::int64_t x = centre[0] - s; x <= centre[0] + s; x += step == 0 ? 1 : step) {
                    if (x < lo[0] || x > hi[0]) continue;
                    const double d2 = dyz + gap2(0, x);
                    if (search.prunes(d2)) continue;
                    any_within = true;
                    for (const std::uint32_t tri : grid.cell_triangles(static_cast<std::uint32_t>(x),
                                                                       static_cast<std::uint32_t>(y),
                                                                       static_cast<std::uint32_t>(z)))
                        if (mailbox.first_visit(tri)) search.offer(mesh, tri);
                }
            }
        }
        if (!any_within) return;
    }
}

}  // namespace sg::kernels::points
