#pragma once

#include <cstddef>

#include "splitgrid/split_grid.hpp"

namespace sg::test {

/// The number of one-cell nodes (resolution 1: the bounding nodes of BuildConfig::bounding_nodes;
/// the split rule alone makes nodes of two cells or more), counted from the node records.
[[nodiscard]] inline std::size_t one_cell_node_count(const SplitGrid& grid)
{
    std::size_t count = 0;
    for (const GridNode& node : grid.nodes) count += node.resolution() == 1u ? 1 : 0;
    return count;
}

}  // namespace sg::test
