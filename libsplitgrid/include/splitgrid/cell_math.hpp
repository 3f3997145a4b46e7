#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "splitgrid/aabb.hpp"

namespace sg {

/// The single mapping between cell indices and coordinates along a node's axis. The builder
/// assigns triangles to cells and the traverser steps through cells with these functions
/// only, so both see exactly the same float boundaries (compiled with -ffp-contract=off so
/// no FMA changes a rounding in one of them).
///
/// Cell i of a node with slab [lo, hi] and resolution n covers the closed interval
/// [cell_boundary(i), cell_boundary(i + 1)]. Boundaries are non-decreasing in i, start at
/// exactly lo and end at exactly hi.
struct CellMath {
    float lo;
    float hi;
    std::uint32_t n;
    float width;  ///< (hi - lo) / n, rounded once

    /// Uninitialised (trivial, so arrays of it cost nothing until written).
    CellMath() = default;
    constexpr CellMath(float lo_, float hi_, std::uint32_t n_) noexcept
        : lo(lo_), hi(hi_), n(n_), width((hi_ - lo_) / static_cast<float>(n_))
    {
    }

    /// Coordinate of the plane between cell i - 1 and cell i (0 <= i <= n).
    [[nodiscard]] constexpr float boundary(std::uint32_t i) const noexcept
    {
        if (i == 0) return lo;
        if (i >= n) return hi;
        return std::min(hi, lo + static_cast<float>(i) * width);
    }

    /// Box of cell i of a node whose box is `node_box` and whose axis is `axis`: the node box
    /// narrowed on that axis to [boundary(i), boundary(i + 1)].
    [[nodiscard]] constexpr Aabb cell_box(const Aabb& node_box, int axis,
                                          std::uint32_t i) const noexcept
    {
        Aabb box = node_box;
        box.lower[axis] = boundary(i);
        box.upper[axis] = boundary(i + 1);
        return box;
    }

    /// A guess of the cell holding coordinate x, clamped to [0, n - 1]. Exact callers correct
    /// it against boundary(); see locate().
    [[nodiscard]] std::uint32_t guess(float x) const noexcept
    {
        if (!(width > 0.0f)) return 0;
        const float f = (x - lo) / width;
        if (!(f > 0.0f)) return 0;
        if (f >= static_cast<float>(n - 1)) return n - 1;
        return static_cast<std::uint32_t>(f);
    }

    /// The lowest cell i whose closed interval contains x (x clamped to [lo, hi]).
    [[nodiscard]] std::uint32_t locate_lowest(float x) const noexcept
    {
        std::uint32_t i = guess(x);
        while (i > 0 && x <= boundary(i)) --i;
        while (i + 1 < n && x > boundary(i + 1)) ++i;
        return i;
    }
    /// The highest cell i whose closed interval contains x (x clamped to [lo, hi]).
    [[nodiscard]] std::uint32_t locate_highest(float x) const noexcept
    {
        std::uint32_t i = guess(x);
        while (i + 1 < n && x >= boundary(i + 1)) ++i;
        while (i > 0 && x < boundary(i)) --i;
        return i;
    }
};

/// For each i < count: first[i] = cm.locate_lowest(lower[i]) and last[i] =
/// cm.locate_highest(upper[i]). Four at a time where the guesses and their corrections run as
/// one vector each (SSE2, part of every x86-64 target), with the same float operations lane by
/// lane, so the same cells; the builder locates every triangle of a node this way
/// (docs/notebook/build.md, "Locating four triangles at once").
void locate_cells(const CellMath& cm, const float* lower, const float* upper, std::size_t count,
                  std::uint32_t* first, std::uint32_t* last) noexcept;

}  // namespace sg
