#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "splitgrid/split_grid.hpp"

namespace sg {

/// Constants of the surface-area cost model used by GridStats::sah_cost.
struct CostModel {
    double node_cost = 1.0;      ///< entering an inner node (slab clip, entry cell)
    double cell_cost = 1.0;      ///< stepping through one cell
    double triangle_cost = 1.0;  ///< one ray/triangle test
};

/// Statistics of a Split Grid, shared by sg-stats, sg-bench and the tests.
struct GridStats {
    std::size_t triangle_count = 0;   ///< triangles in the mesh
    std::size_t node_count = 0;       ///< inner nodes
    std::size_t cell_count = 0;       ///< cells of all nodes (the root cell not counted)
    std::size_t empty_cells = 0;
    std::size_t leaf_cells = 0;       ///< including a leaf root
    std::size_t inner_cells = 0;
    std::size_t reference_count = 0;  ///< triangle references in all leaves
    std::size_t referenced_triangles = 0;  ///< distinct triangles referenced at least once

    std::uint32_t max_depth = 0;      ///< deepest inner node (root node = depth 0)
    double mean_leaf_depth = 0.0;     ///< mean number of inner nodes above a leaf cell

    /// resolution_histogram[d][k]: number of nodes at depth d whose resolution is in
    /// [2^k, 2^(k+1)).
    std::vector<std::vector<std::size_t>> resolution_histogram;
    std::vector<std::size_t> nodes_per_depth;
    std::vector<double> mean_resolution_per_depth;

    std::uint32_t leaf_size_min = 0;
    std::uint32_t leaf_size_max = 0;
    double leaf_size_mean = 0.0;
    /// leaf_size_histogram[k]: leaves with a reference count in [2^k, 2^(k+1)).
    std::vector<std::size_t> leaf_size_histogram;

    double empty_cell_fraction = 0.0;  ///< empty_cells / cell_count
    double duplication_factor = 0.0;   ///< reference_count / triangle_count

    std::size_t node_bytes = 0;
    std::size_t cell_bytes = 0;
    std::size_t reference_bytes = 0;
    std::size_t structure_bytes = 0;   ///< SplitGrid::memory_bytes()
    double structure_bytes_per_triangle = 0.0;

    /// Expected cost of tracing a random ray that hits the root box (surface-area model):
    ///   sum over inner nodes    P(box) * node_cost
    /// + sum over inner nodes    P(slab) * cell_cost * (1 + (N - 1) * 2 A / SA(slab))
    /// + sum over leaf cells     P(cell box) * triangle_cost * references
    /// where P(X) = SA(X) / SA(root box), "slab" is the node's box narrowed to [lo, hi],
    /// and A the area of one cell plane inside the slab (a random ray crossing a convex
    /// body crosses a flat section of area A with probability 2A / SA(body)).
    double sah_cost = 0.0;
    CostModel cost_model;
};

/// Expected number of cells a random ray crossing `slab` steps through, for a node that cuts
/// the slab into `resolution` cells along `axis`: 1 + (N - 1) * 2A / SA(slab), A being the area
/// of one cell plane (see GridStats::sah_cost). 1 for a slab without surface area.
[[nodiscard]] double expected_cells_crossed(const Aabb& slab, int axis,
                                            std::uint32_t resolution) noexcept;

/// Walks the whole grid once. Precondition: check_invariants(grid) passes.
[[nodiscard]] GridStats compute_stats(const SplitGrid& grid, const CostModel& model = {});

}  // namespace sg
