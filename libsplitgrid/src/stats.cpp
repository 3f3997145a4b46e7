#include "splitgrid/stats.hpp"

#include <algorithm>
#include <bit>
#include <limits>

#include "splitgrid/cell_math.hpp"

namespace sg {
namespace {

std::size_t log2_bucket(std::uint32_t value) noexcept
{
    return value == 0 ? 0 : static_cast<std::size_t>(std::bit_width(value) - 1);
}

void bump(std::vector<std::size_t>& histogram, std::size_t bucket)
{
    if (histogram.size() <= bucket) histogram.resize(bucket + 1, 0);
    ++histogram[bucket];
}

}  // namespace

double expected_cells_crossed(const Aabb& slab, int axis, std::uint32_t resolution) noexcept
{
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    const double plane_area = double(slab.extent(a1)) * slab.extent(a2);
    const double slab_area = slab.surface_area();
    return 1.0 + (slab_area > 0.0 ? (resolution - 1) * 2.0 * plane_area / slab_area : 0.0);
}

GridStats compute_stats(const SplitGrid& grid, const CostModel& model)
{
    GridStats s;
    s.cost_model = model;
    s.triangle_count = grid.triangle_count;
    s.node_count = grid.nodes.size();
    s.node_bytes = grid.nodes.size() * sizeof(GridNode);
    s.cell_bytes = grid.cells.size() * sizeof(CellRef);
    s.reference_bytes = grid.leaf_words.size() * sizeof(std::uint16_t);
    s.structure_bytes = grid.memory_bytes();
    {
        // One pass over the leaves for both counts.
        std::vector<bool> seen(grid.triangle_count, false);
        (void)for_each_leaf(grid.leaf_words, [&](std::size_t, std::size_t,
                                                 std::span<const std::uint32_t> ids) {
            s.reference_count += ids.size();
            for (const std::uint32_t id : ids)
                if (id < seen.size() && !seen[id]) {
                    seen[id] = true;
                    ++s.referenced_triangles;
                }
        });
    }
    if (grid.triangle_count > 0) {
        s.structure_bytes_per_triangle =
            static_cast<double>(s.structure_bytes) / grid.triangle_count;
        s.duplication_factor = static_cast<double>(s.reference_count) / grid.triangle_count;
    }

    const double root_area = grid.root_box.surface_area();
    auto probability = [&](const Aabb& box) {
        return root_area > 0.0 ? box.surface_area() / root_area : 0.0;
    };
    double leaf_depth_sum = 0.0;
    std::uint64_t leaf_ref_total = 0;
    s.leaf_size_min = std::numeric_limits<std::uint32_t>::max();
    auto add_leaf = [&](const CellRef& cell, const Aabb& box, std::uint32_t depth) {
        ++s.leaf_cells;
        const auto size = static_cast<std::uint32_t>(leaf_size(grid, cell));
        s.leaf_size_min = std::min(s.leaf_size_min, size);
        s.leaf_size_max = std::max(s.leaf_size_max, size);
        leaf_ref_total += size;
        leaf_depth_sum += depth;
        bump(s.leaf_size_histogram, log2_bucket(size));
        s.sah_cost += probability(box) * model.triangle_cost * size;
    };

    struct Pending {
        std::uint32_t node;
        std::uint32_t depth;
        Aabb box;
    };
    std::vector<Pending> pending;
    if (grid.root.is_leaf()) add_leaf(grid.root, grid.root_box, 0);
    if (grid.root.is_inner()) pending.push_back({grid.root.child(), 0, grid.root_box});
    while (!pending.empty()) {
        const Pending p = pending.back();
        pending.pop_back();
        const GridNode& node = grid.nodes[p.node];
        const std::uint32_t n = node.resolution();
        const int axis = node.axis();
        s.max_depth = std::max(s.max_depth, p.depth);
        if (s.nodes_per_depth.size() <= p.depth) {
            s.nodes_per_depth.resize(p.depth + 1, 0);
            s.mean_resolution_per_depth.resize(p.depth + 1, 0.0);
            s.resolution_histogram.resize(p.depth + 1);
        }
        ++s.nodes_per_depth[p.depth];
        s.cell_count += n;
        s.mean_resolution_per_depth[p.depth] += n;  // divided by the node count below
        bump(s.resolution_histogram[p.depth], log2_bucket(n));

        Aabb slab = p.box;
        slab.lower[axis] = node.lo;
        slab.upper[axis] = node.hi;
        s.sah_cost += probability(p.box) * model.node_cost +
                      probability(slab) * model.cell_cost * expected_cells_crossed(slab, axis, n);

        const CellMath cm(node.lo, node.hi, n);
        for (std::uint32_t i = 0; i < n; ++i) {
            const CellRef cell = node_cell(grid, node, i);
            const Aabb box = cm.cell_box(p.box, axis, i);
            if (cell.is_empty()) ++s.empty_cells;
            if (cell.is_leaf()) add_leaf(cell, box, p.depth + 1);
            if (cell.is_inner()) {
                ++s.inner_cells;
                pending.push_back({cell.child(), p.depth + 1, box});
            }
        }
    }
    for (std::size_t d = 0; d < s.nodes_per_depth.size(); ++d)
        if (s.nodes_per_depth[d] > 0)
            s.mean_resolution_per_depth[d] /= static_cast<double>(s.nodes_per_depth[d]);
    if (s.leaf_cells > 0) {
        s.mean_leaf_depth = leaf_depth_sum / static_cast<double>(s.leaf_cells);
        s.leaf_size_mean = static_cast<double>(leaf_ref_total) / static_cast<double>(s.leaf_cells);
    } else {
        s.leaf_size_min = 0;
    }
    if (s.cell_count > 0)
        s.empty_cell_fraction = static_cast<double>(s.empty_cells) / static_cast<double>(s.cell_count);
    return s;
}

}  // namespace sg
