#pragma once

// Shared pieces of the robustness suite (docs/ROBUSTNESS.md): the size switch, parallel loops
// over rays, the brute-force comparison run in parallel, rays whose line passes exactly through
// a chosen point, the boxes of a grid's nodes, the per-ray work bound of the traversal, and
// the build settings that split hardest.
// Header-only because tests/CMakeLists.txt compiles only tests/robustness/*_test.cpp.

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "splitgrid/build_config.hpp"
#include "splitgrid/cell_math.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/traverse.hpp"
#include "support/leaf_triangles.hpp"
#include "support/oracle.hpp"

namespace sg::test {

/// True when the environment variable SG_ROBUSTNESS_FULL is set to anything but "" or "0":
/// the tests then run at the full sizes of the robustness issue instead of the CI sizes.
inline bool full_size()
{
    const char* value = std::getenv("SG_ROBUSTNESS_FULL");
    return value != nullptr && *value != '\0' && std::string(value) != "0";
}

/// `ci` normally, `full` under SG_ROBUSTNESS_FULL.
inline std::size_t pick_size(std::size_t ci, std::size_t full) { return full_size() ? full : ci; }

/// Sum of body(i) over i in [0, n), on oneTBB's threads. The sum does not depend on the
/// thread count.
template <class Body>
std::size_t parallel_count(std::size_t n, const Body& body)
{
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, n, 1024), std::size_t{0},
        [&](const tbb::blocked_range<std::size_t>& r, std::size_t sum) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) sum += body(i) ? 1 : 0;
            return sum;
        },
        [](std::size_t a, std::size_t b) { return a + b; });
}

/// `compare` (a function of a vector of rays returning an OracleReport) over blocks of 1024
/// rays on oneTBB's threads. The counts are summed and the first failure is that of the
/// lowest block that has one, so the report does not depend on the thread count.
template <class Compare>
OracleReport compare_in_blocks(const std::vector<Ray>& rays, const Compare& compare)
{
    constexpr std::size_t block = 1024;
    const std::size_t blocks = (rays.size() + block - 1) / block;
    std::vector<OracleReport> parts(blocks);
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
        const auto first = rays.begin() + static_cast<std::ptrdiff_t>(b * block);
        const auto last = rays.begin() +
                          static_cast<std::ptrdiff_t>(std::min(rays.size(), (b + 1) * block));
        parts[b] = compare(std::vector<Ray>(first, last));
    });
    OracleReport total;
    for (const OracleReport& p : parts) total += p;
    return total;
}

/// compare_with_brute_force on oneTBB's threads.
inline OracleReport parallel_compare(const SplitGrid& grid, const MeshView& mesh,
                                     const std::vector<Ray>& rays)
{
    return compare_in_blocks(rays, [&](const std::vector<Ray>& part) {
        return compare_with_brute_force(grid, mesh, part);
    });
}

/// A ray from `origin` (moved by at most a few ulps, or onto the target's plane on an axis)
/// whose line passes exactly through `target`: origin + 1 * direction == target in exact
/// arithmetic. Each direction component must be an exact float difference target - origin;
/// that holds when the origin component is a multiple of the target's ulp and close enough
/// to it, so the origin is rounded to that grid; where that is not enough the origin takes
/// the target's coordinate (a zero direction component). Returns nothing when the direction
/// would be zero.
inline std::optional<Ray> ray_through(Vec3f origin, Vec3f target)
{
    Ray ray;
    for (int k = 0; k < 3; ++k) {
        const float t = target[k];
        // Spacing of the floats at t (the smallest normal spacing for tiny t).
        const double ulp =
            std::max(double(std::nextafter(std::fabs(t), INFINITY)) - std::fabs(t),
                     double(std::numeric_limits<float>::denorm_min()));
        auto o = static_cast<float>(std::round(double(origin[k]) / ulp) * ulp);
        float d = t - o;
        if (double(o) + double(d) != double(t)) {
            o = t;
            d = 0.0f;
        }
        ray.origin[k] = o;
        ray.direction[k] = d;
    }
    if (ray.direction == Vec3f{}) return std::nullopt;
    return ray;
}

/// The build settings that split hardest: leaf size 1, the deepest trees, no cost test, no
/// cell-width cap, and a no-progress fraction of 1.
inline BuildConfig hardest_splitting()
{
    BuildConfig c;
    c.leaf_size = 1;
    c.max_depth = max_supported_depth;
    c.no_progress_fraction = 1.0;
    c.stop_by_cost = false;
    c.min_cell_width = 0.0;
    return c;
}

/// A node of a grid with the box it covers (not stored in the grid: the root box narrowed
/// on each ancestor's axis to the ancestor's cell) and its depth (the root node is 0).
struct NodeBox {
    std::uint32_t node = 0;
    std::uint32_t depth = 0;
    Aabb box;
};

/// Every node of the grid with its box, in depth-first pre-order.
inline std::vector<NodeBox> node_boxes(const SplitGrid& grid)
{
    std::vector<NodeBox> out;
    if (!grid.root.is_inner()) return out;
    std::vector<NodeBox> pending{{grid.root.child(), 0, grid.root_box}};
    while (!pending.empty()) {
        const NodeBox nb = pending.back();
        pending.pop_back();
        out.push_back(nb);
        const GridNode& node = grid.nodes[nb.node];
        const CellMath cm(node.lo, node.hi, node.resolution());
        for (std::uint32_t i = node.resolution(); i-- > 0;) {
            const CellRef cell = node_cell(grid, node, i);
            if (!cell.is_inner()) continue;
            pending.push_back({cell.child(), nb.depth + 1, cm.cell_box(nb.box, node.axis(), i)});
        }
    }
    return out;
}

/// The work bound of one query (docs/ROBUSTNESS.md, row 10), derived from the structure:
/// - a node is entered at most once per ray (each node is the child of one cell, and the walk
///   over a node's cells never visits a cell twice), so nodes_visited <= node count;
/// - a node's walk visits at most its resolution N of cells (one cell when the ray is
///   parallel to its axis), so cells_visited <= nodes_visited * N_max, and <= cell count;
/// - a leaf's references are tested once per visit, so triangles_tested <= (leaf cells
///   visited) * L_max <= cells_visited * L_max, and <= reference count (+1 root leaf).
/// N_max is the largest resolution and L_max the largest leaf of the grid.
struct WorkBound {
    std::size_t nodes = 0;
    std::size_t cells = 0;
    std::size_t references = 0;
    std::size_t max_resolution = 1;
    std::size_t max_leaf = 0;

    explicit WorkBound(const SplitGrid& grid)
        : nodes(grid.nodes.size()), references(counted_references(grid))
    {
        for (const GridNode& n : grid.nodes) {
            max_resolution = std::max<std::size_t>(max_resolution, n.resolution());
            cells += n.resolution();
            for (std::uint32_t i = 0; i < n.resolution(); ++i)
                if (const CellRef c = node_cell(grid, n, i); c.is_leaf())
                    max_leaf = std::max(max_leaf, leaf_triangles(grid, c).size());
        }
        if (grid.root.is_leaf())
            max_leaf = std::max(max_leaf, leaf_triangles(grid, grid.root).size());
    }

    /// The largest number of cells a ray can visit, and of triangle tests it can run.
    [[nodiscard]] std::size_t cell_limit(std::size_t nodes_visited) const
    {
        return std::min(cells, nodes_visited * max_resolution);
    }
    [[nodiscard]] std::size_t test_limit(std::size_t cells_visited) const
    {
        // A leaf root is tested without visiting a cell.
        return std::min(references, std::max<std::size_t>(cells_visited, 1) * max_leaf);
    }
    [[nodiscard]] bool holds(const TraversalCounters& c) const
    {
        return c.nodes_visited <= nodes && c.cells_visited <= cell_limit(c.nodes_visited) &&
               c.triangles_tested <= test_limit(c.cells_visited);
    }
};

/// Seconds taken by f().
template <class F>
double seconds_of(const F& f)
{
    const auto start = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace sg::test
