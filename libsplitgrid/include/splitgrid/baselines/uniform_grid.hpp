#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/baselines/traversal_common.hpp"
#include "splitgrid/cell_math.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/traverse.hpp"

namespace sg {

/// Parameters of the uniform grid (a comparison structure for sg-bench; docs/BASELINES.md).
///
/// Resolution rule (the usual cube-root rule, Cleary and Wyvill 1988; Wald et al. 2006): the
/// cells are cubes of edge s chosen so that the grid has about density * N cells for N
/// triangles, s = cbrt(volume / (density * N)), and an axis of extent e gets round(e / s)
/// cells. An axis thinner than one cell (a flat or thin scene) gets one cell and s is
/// recomputed over the other axes (square root, or the extent itself), so flat scenes are
/// not cut into slivers. The product is then capped at max_cells.
struct UniformGridConfig {
    /// Cells per triangle (lambda). Range (0, 1e4]. 4 measured here (docs/BASELINES.md):
    /// on the Stanford dragon lambda 2 and 4 trace equally fast and 8 is slower, on the
    /// Sponza part trace speed rises by 10-15% per doubling up to 8; 4 costs about 25 bytes
    /// per triangle on the dragon, 8 about 43.
    double density = 4.0;
    /// Most cells in total (each costs a 4-byte offset). Range [1, 2^30]. 2^26 cells = 256 MiB
    /// of offsets; the rule reaches it at 16.7 million triangles with the default density.
    std::uint64_t max_cells = std::uint64_t{1} << 26;
    /// Cells per axis, overriding the rule when all three are non-zero (tests place geometry
    /// on known cell planes; sg-bench may sweep it). Each in [0, 2^20]; all zero or all set.
    std::array<std::uint32_t, 3> resolution{0, 0, 0};
    /// Worker threads for the build; 0 means all hardware threads. Range [0, 1024]. The grid
    /// is identical for every value.
    unsigned threads = 0;

    /// Throws ConfigError naming the first field out of range.
    void validate() const;
    friend bool operator==(const UniformGridConfig&, const UniformGridConfig&) = default;
};

/// Cells per axis that the resolution rule of UniformGridConfig gives for a scene whose
/// (unpadded) bounding box is `scene` and which has `triangles` triangles. {1, 1, 1} for an
/// empty scene. Each entry is in [1, 2^20] and their product is at most config.max_cells.
[[nodiscard]] std::array<std::uint32_t, 3> grid_resolution(const Aabb& scene,
                                                           std::size_t triangles,
                                                           const UniformGridConfig& config);

/// A uniform grid over the scene's bounding box (padded by boundary_pad), traversed with the
/// 3D-DDA of Amanatides and Woo ("A Fast Voxel Traversal Algorithm for Ray Tracing",
/// Eurographics 1987), stepped as nested per-axis walks so that it is conservative (see walk).
///
/// Storage (compact, 32-bit): `cell_offsets` has cell_count() + 1 entries; cell c (linear
/// index (z * ny + y) * nx + x) references triangles refs[cell_offsets[c] ..
/// cell_offsets[c + 1]), in increasing id order. A triangle is referenced by every cell whose
/// box, padded by boundary_pad, its polygon overlaps; overlap is decided exactly by clipping
/// the triangle in double precision (clip.hpp), first to the cell's x slab, then its y slab.
/// Cell planes on each axis come from CellMath, the same mapping at build and traversal.
class UniformGrid : public BaselineQueries<UniformGrid> {
public:
    using Config = UniformGridConfig;

    /// Builds the grid. Throws ConfigError for a bad config, InputError for a bad mesh (see
    /// check_mesh) or one with 2^32 - 1 triangles or references or more. An empty mesh gives
    /// an empty grid on which every query misses. Cost: O(references) after a parallel
    /// per-triangle pass; the counting sort into cells is serial.
    [[nodiscard]] static UniformGrid build(const MeshView& mesh, const UniformGridConfig& config = {});

    // Queries (intersect, occluded, intersect_with, occluded_with): BaselineQueries in
    // traversal_common.hpp. Counters: cells_visited = cells stepped through (side cells included).

    /// Bytes of the grid itself: the box, resolution, offsets and references (not the mesh).
    [[nodiscard]] std::size_t memory_bytes() const noexcept
    {
        return sizeof(box_) + sizeof(resolution_) + sizeof(triangle_count_) +
               cell_offsets_.size() * sizeof(std::uint32_t) + refs_.size() * sizeof(std::uint32_t);
    }

    /// The grid's box: the scene's bounding box padded by boundary_pad (empty for no triangles).
    [[nodiscard]] const Aabb& box() const noexcept { return box_; }
    /// Cells per axis ({0, 0, 0} for an empty mesh).
    [[nodiscard]] const std::array<std::uint32_t, 3>& resolution() const noexcept
    {
        return resolution_;
    }
    /// The cell planes on `axis` (0, 1, 2). Precondition: the mesh was not empty.
    [[nodiscard]] CellMath axis_cells(int axis) const noexcept
    {
        return CellMath(box_.lower[axis], box_.upper[axis], resolution_[static_cast<std::size_t>(axis)]);
    }
    [[nodiscard]] std::size_t cell_count() const noexcept
    {
        return cell_offsets_.empty() ? 0 : cell_offsets_.size() - 1;
    }
    [[nodiscard]] std::size_t empty_cell_count() const noexcept;
    [[nodiscard]] std::size_t reference_count() const noexcept { return refs_.size(); }
    [[nodiscard]] std::uint32_t triangle_count() const noexcept { return triangle_count_; }
    /// Triangles referenced by the cell (x, y, z), in increasing id order.
    [[nodiscard]] std::span<const std::uint32_t> cell_triangles(std::uint32_t x, std::uint32_t y,
                                                                std::uint32_t z) const noexcept
    {
        const std::size_t c = cell_index(x, y, z);
        return {refs_.data() + cell_offsets_[c], refs_.data() + cell_offsets_[c + 1]};
    }

    friend bool operator==(const UniformGrid&, const UniformGrid&) = default;

private:
    // Ray intervals are widened by this much, relative, wherever a plane crossing
    // (plane - origin) * (1 / direction) decides which cells are visited or when the walk
    // stops. The crossing has three roundings (relative error below 2^-22), so the widened
    // interval contains the exact one. The same factor as the Split Grid's traverser.
    static constexpr float t_pad(Padding padding) noexcept
    {
        return padding == Padding::Conservative ? 0x1p-20f : 0.0f;
    }

    [[nodiscard]] std::size_t cell_index(std::uint32_t x, std::uint32_t y, std::uint32_t z) const noexcept
    {
        return (std::size_t{z} * resolution_[1] + y) * resolution_[0] + x;
    }

    friend class BaselineQueries<UniformGrid>;
    template <Padding padding, class Search>
    void walk(const detail::BaselineRay& ray, Search& search) const noexcept;

    Aabb box_;
    std::array<std::uint32_t, 3> resolution_{0, 0, 0};
    std::uint32_t triangle_count_ = 0;
    std::vector<std::uint32_t> cell_offsets_;
    std::vector<std::uint32_t> refs_;
};

namespace detail {

// One axis of the grid as the walk sees it: its cell planes and the ray's crossings of them.
struct GridAxis {
    const BaselineRay* ray;
    CellMath cells;
    int axis;
    bool parallel;
    bool forward;  // the ray moves towards higher cell indices

    [[nodiscard]] float crossing(std::uint32_t boundary) const noexcept
    {
        return ray->crossing(axis, cells.boundary(boundary));
    }
    // Plane through which the ray enters (leaves) cell i.
    [[nodiscard]] std::uint32_t entry_plane(std::uint32_t i) const noexcept { return forward ? i : i + 1; }
    [[nodiscard]] std::uint32_t exit_plane(std::uint32_t i) const noexcept { return forward ? i + 1 : i; }
    // The first cell, in ray order, whose interval widened by `pad` holds t (a guess from the
    // position at t, corrected with the same crossings the walk uses); for a parallel ray the
    // cell holding the origin (the lower one on a plane: triangles touching the plane are
    // referenced by both).
    [[nodiscard]] std::uint32_t first_cell(float t, float pad) const noexcept
    {
        if (parallel) return cells.locate_lowest(ray->origin[axis]);
        std::uint32_t i = cells.guess(ray->origin[axis] + t * ray->direction[axis]);
        auto enters_after = [&](std::uint32_t c) { return widen_down(crossing(entry_plane(c)), pad) > t; };
        auto leaves_before = [&](std::uint32_t c) { return widen_up(crossing(exit_plane(c)), pad) < t; };
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

}  // namespace detail

// The 3D-DDA of Amanatides and Woo, made conservative by stepping the three axes as nested
// one-dimensional DDAs: the x slabs the ray crosses in ray order, within each the y cells over
// the slab's ray interval, within each of those the z cells. Every plane crossing is widened
// by t_pad, and a cell is visited when its widened x, y and z intervals overlap inside the
// ray's window: a superset of the cells the exact ray touches, in ray order. (The classic
// single walk that steps the axis with the nearest crossing, plus the neighbours of near
// ties, lost 50 of 10^4 rays whose origins were 10^7 scene units away, where the widening
// spans many cells; this form lost none.) Triangles are tested over [t_min, closest so far]
// and each walk stops when its next cell starts (widened down) after the closest hit or the
// end of the interval, so a hit found in a cell but lying beyond it is kept while cells in
// front of it are still visited.
template <Padding padding, class Search>
void UniformGrid::walk(const detail::BaselineRay& ray, Search& search) const noexcept
{
    if (refs_.empty()) return;
    constexpr float pad = t_pad(padding);
    float t0 = ray.t_min;
    float t1 = ray.t_max;
    if (!detail::clip_to_box(ray, box_, pad, t0, t1)) return;
    std::array<detail::GridAxis, 3> axes;
    for (int k = 0; k < 3; ++k)
        axes[static_cast<std::size_t>(k)] =
            detail::GridAxis{&ray, axis_cells(k), k, ray.is_parallel[k], ray.direction[k] > 0.0f};

    // Calls inner(cell, lo, hi) for the cells of `g` whose widened interval meets [lo, hi],
    // in ray order, with the overlap; true as soon as inner says the query is done.
    auto step = [&](const detail::GridAxis& g, float lo, float hi, const auto& inner) {
        std::uint32_t i = g.first_cell(lo, pad);
        if (g.parallel) return inner(i, lo, hi);
        float enter = detail::widen_down(g.crossing(g.entry_plane(i)), pad);
        for (;;) {
            if (enter > std::min(hi, search.best_t())) return false;
            const float leave = g.crossing(g.exit_plane(i));
            const float cell_lo = std::max(lo, enter);
            const float cell_hi = std::min(hi, detail::widen_up(leave, pad));
            if (cell_lo <= cell_hi && inner(i, cell_lo, cell_hi)) return true;
            if (g.forward ? i + 1 >= g.cells.n : i == 0) return false;
            i = g.forward ? i + 1 : i - 1;
            enter = detail::widen_down(leave, pad);
        }
    };
    // Triangles span about two cells each (docs/BASELINES.md): test each once per query.
    detail::Mailbox<16> mailbox;
    auto visit = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) {
        search.count_cell();
        const std::size_t c = cell_index(x, y, z);
        const std::uint32_t end = cell_offsets_[c + 1];
        for (std::uint32_t r = cell_offsets_[c]; r < end; ++r) {
            const std::uint32_t tri = refs_[r];
            if (!mailbox.seen(tri) && search.test(tri) && search.done()) return true;
        }
        return false;
    };
    (void)step(axes[0], t0, t1, [&](std::uint32_t x, float x0, float x1) {
        return step(axes[1], x0, x1, [&](std::uint32_t y, float y0, float y1) {
            return step(axes[2], y0, y1,
                        [&](std::uint32_t z, float, float) { return visit(x, y, z); });
        });
    });
}

}  // namespace sg
