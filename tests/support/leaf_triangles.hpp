#pragma once

#include <cstdint>
#include <vector>

#include "splitgrid/split_grid.hpp"

namespace sg::test {

/// The triangle ids of a leaf cell, read from the raw reference words (bit 31 marks the last
/// one, grid_node.hpp) without the library's own leaf_refs, so tests stay independent of it.
/// Precondition: `cell` is a leaf of a grid that passes check_invariants.
[[nodiscard]] inline std::vector<std::uint32_t> leaf_triangles(const SplitGrid& grid,
                                                               const CellRef& cell)
{
    std::vector<std::uint32_t> ids;
    for (std::size_t r = cell.first_ref();; ++r) {
        const std::uint32_t word = grid.triangle_refs.at(r).raw_bits();
        ids.push_back(word & 0x7FFFFFFFu);
        if (word & 0x80000000u) return ids;
    }
}

}  // namespace sg::test
