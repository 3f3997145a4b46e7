#include "splitgrid/stats.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "splitgrid/builder.hpp"
#include "support/leaf_triangles.hpp"
#include "support/random_scene.hpp"

namespace sg {
namespace {

TEST(Stats, CountsMatchAnIndependentWalk)
{
    const Mesh mesh = test::random_triangles(1, 8000, Aabb{{0, 0, 0}, {10, 10, 10}}, 0.4f);
    const SplitGrid grid = build_split_grid(mesh.view(), {});
    const GridStats s = compute_stats(grid);

    // Recount by a recursive walk of the records, independent of compute_stats' loop.
    std::size_t empty = 0, leaves = 0, inner = 0, refs = 0;
    std::uint32_t max_depth = 0, min_leaf = ~0u, max_leaf = 0;
    std::map<std::uint32_t, std::size_t> per_depth;
    std::set<std::uint32_t> distinct;
    auto walk = [&](auto&& self, std::uint32_t node, std::uint32_t depth) -> void {
        max_depth = std::max(max_depth, depth);
        ++per_depth[depth];
        const GridNode& n = grid.nodes[node];
        for (std::uint32_t i = 0; i < n.resolution(); ++i) {
            const CellRef c = node_cell(grid, n, i);
            if (c.is_empty()) ++empty;
            if (c.is_inner()) {
                ++inner;
                self(self, c.child(), depth + 1);
            }
            if (c.is_leaf()) {
                ++leaves;
                const std::vector<std::uint32_t> ids = test::leaf_triangles(grid, c);
                const auto size = static_cast<std::uint32_t>(ids.size());
                refs += size;
                min_leaf = std::min(min_leaf, size);
                max_leaf = std::max(max_leaf, size);
                distinct.insert(ids.begin(), ids.end());
            }
        }
    };
    ASSERT_TRUE(grid.root.is_inner());
    walk(walk, grid.root.child(), 0);

    EXPECT_EQ(s.empty_cells, empty);
    EXPECT_EQ(s.leaf_cells, leaves);
    EXPECT_EQ(s.inner_cells, inner);
    EXPECT_EQ(s.inner_cells + 1, s.node_count);
    EXPECT_EQ(s.reference_count, refs);
    EXPECT_EQ(s.referenced_triangles, distinct.size());
    EXPECT_EQ(s.referenced_triangles, mesh.triangles.size());
    EXPECT_EQ(s.max_depth, max_depth);
    EXPECT_EQ(s.leaf_size_min, min_leaf);
    EXPECT_EQ(s.leaf_size_max, max_leaf);
    for (const auto& [depth, count] : per_depth) EXPECT_EQ(s.nodes_per_depth[depth], count);
    EXPECT_DOUBLE_EQ(s.duplication_factor, double(refs) / 8000.0);
    EXPECT_EQ(s.structure_bytes, grid.nodes.size() * 16 + grid.cells.size() * 4 +
                                     grid.leaf_words.size() * 2 + 24 + 4);
    std::size_t hist_total = 0;
    for (std::size_t h : s.leaf_size_histogram) hist_total += h;
    EXPECT_EQ(hist_total, leaves);
    EXPECT_GT(s.sah_cost, 0.0);
}

TEST(Stats, CostModelOfASingleLeafIsItsTriangleCount)
{
    // A root leaf is visited by every ray that hits the root box: cost = triangles * cost.
    Mesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 1}};
    mesh.triangles = {Triangle{{0, 1, 2}}, Triangle{{0, 2, 1}}};
    const SplitGrid grid = build_split_grid(mesh.view(), {});
    ASSERT_TRUE(grid.root.is_leaf());
    CostModel model;
    model.triangle_cost = 3.0;
    EXPECT_DOUBLE_EQ(compute_stats(grid, model).sah_cost, 6.0);
}

}  // namespace
}  // namespace sg
