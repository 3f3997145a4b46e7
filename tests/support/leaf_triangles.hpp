#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "splitgrid/split_grid.hpp"

namespace sg::test {

/// The triangle ids of the leaf whose head is word `first`, read from the raw 16-bit words as
/// docs/FORMAT.md lays them out (a head pair: id, bit 30 wide, bit 31 last; then one word per
/// reference, offset and bit 15 last, or a pair per reference, id and bit 31 last), without the
/// library's own reader, so tests stay independent of it. `end` receives the word after the
/// leaf. Precondition: the leaf is well formed (the grid passes check_invariants).
[[nodiscard]] inline std::vector<std::uint32_t> leaf_at(const SplitGrid& grid, std::size_t first,
                                                        std::size_t* end = nullptr)
{
    const std::vector<std::uint16_t>& w = grid.leaf_words;
    const auto pair = [&](std::size_t at) {
        return static_cast<std::uint32_t>(w.at(at)) | (static_cast<std::uint32_t>(w.at(at + 1)) << 16);
    };
    const std::uint32_t head = pair(first);
    const std::uint32_t base = head % (1u << 30);
    std::vector<std::uint32_t> ids{base};
    std::size_t at = first + 2;
    const bool wide = (head >> 30) % 2 == 1;
    bool last = (head >> 31) == 1;
    while (!last) {
        if (wide) {
            const std::uint32_t ref = pair(at);
            ids.push_back(ref % (1u << 30));
            last = (ref >> 31) == 1;
            at += 2;
        } else {
            ids.push_back(base + w.at(at) % (1u << 15));
            last = w.at(at) >= (1u << 15);
            at += 1;
        }
    }
    if (end != nullptr) *end = at;
    return ids;
}

/// The triangle ids of a leaf cell. Precondition: as leaf_at.
[[nodiscard]] inline std::vector<std::uint32_t> leaf_triangles(const SplitGrid& grid,
                                                               const CellRef& cell)
{
    return leaf_at(grid, cell.first_word());
}

/// Every leaf's ids, the leaves as they follow each other in the word array.
[[nodiscard]] inline std::vector<std::vector<std::uint32_t>> all_leaves(const SplitGrid& grid)
{
    std::vector<std::vector<std::uint32_t>> leaves;
    for (std::size_t at = 0; at < grid.leaf_words.size();)
        leaves.push_back(leaf_at(grid, at, &at));
    return leaves;
}

/// Makes the head of the leaf at word `first` name triangle `id` (its wide and last bits kept),
/// as a forged file would; the leaf's other ids move with it if it is narrow.
inline void set_leaf_head(SplitGrid& grid, std::size_t first, std::uint32_t id)
{
    std::vector<std::uint16_t>& w = grid.leaf_words;
    w.at(first) = static_cast<std::uint16_t>(id % 65536u);
    w.at(first + 1) = static_cast<std::uint16_t>(w.at(first + 1) / 16384u * 16384u + id / 65536u);
}

/// The first leaf among `grid.cells` (the cells of nodes of two or more cells), or nullptr.
[[nodiscard]] inline const CellRef* first_leaf_cell(const SplitGrid& grid)
{
    for (const CellRef& cell : grid.cells)
        if (cell.is_leaf()) return &cell;
    return nullptr;
}

/// Number of triangle references in all leaves.
[[nodiscard]] inline std::size_t counted_references(const SplitGrid& grid)
{
    std::size_t n = 0;
    for (const auto& leaf : all_leaves(grid)) n += leaf.size();
    return n;
}

/// How many references name triangle `tri`.
[[nodiscard]] inline std::size_t references_to(const SplitGrid& grid, std::uint32_t tri)
{
    std::size_t n = 0;
    for (const auto& leaf : all_leaves(grid))
        for (std::uint32_t id : leaf) n += id == tri ? 1 : 0;
    return n;
}

}  // namespace sg::test
