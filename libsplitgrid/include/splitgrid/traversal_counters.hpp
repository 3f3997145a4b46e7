#pragma once

#include <cstdint>

namespace sg {

/// Work done by one query, for heat maps and the cost statistics. Every traversal in
/// splitgrid (the Split Grid's and the comparison structures') fills it when given one; each
/// structure's header says what its node and cell counts mean.
struct TraversalCounters {
    std::uint32_t nodes_visited = 0;     ///< inner nodes whose slab the ray was clipped to
    std::uint32_t cells_visited = 0;     ///< cells stepped through (empty ones included)
    std::uint32_t triangles_tested = 0;  ///< ray/triangle tests run
};

}  // namespace sg
