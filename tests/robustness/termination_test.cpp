// Row 10 of docs/ROBUSTNESS.md: termination and the explicit stack. Over random and
// adversarial rays (on and along cell planes, along the axes through vertices, zero and
// denormal direction components, huge and tiny directions, rays aimed into the deepest
// leaves) every query's work stays within the bound derived from the structure
// (robustness_support.hpp, WorkBound: every node entered at most once, at most N cells per
// node, each leaf's references tested once per visit), on ordinary grids and on the deepest
// tree the builder makes (max_depth 64: 65 nested nodes, exactly the stack's 65 entries).
// A chain of 65 nodes written by hand, the deepest grid check_invariants accepts, is traced
// to its leaf. The stack cannot overflow silently: rays into the deepest leaves must find
// brute force's hits there (a dropped node would lose them; builds with assertions abort).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "adversarial_rays.hpp"
#include "robustness_support.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/stats.hpp"
#include "splitgrid/validate.hpp"
#include "support/random_scene.hpp"

namespace sg::test {
namespace {

// The six faces of a cube of side 6, each 6 x 6 quads: triangles sharing edges and corners,
// which the settings that split hardest slice as finely as the builder allows.
Mesh box_of_planes()
{
    Mesh mesh;
    for (int axis = 0; axis < 3; ++axis) {
        append(mesh, axis_plane(axis, 0.0f, 6));
        append(mesh, axis_plane(axis, 6.0f, 6));
    }
    return mesh;
}

// 60 small triangles, each half the size of the last and half as far from the origin: a
// chain the builder can follow down to its depth limit, 64, when every node has two cells,
// since each level leaves the smallest triangles in one cell without leaving all of them.
// (Triangles that share a corner do not make such a chain: a cell that keeps all of its
// parent's triangles twice in a row becomes a leaf.)
Mesh shrinking_triangles()
{
    Mesh mesh;
    for (int k = 0; k < 60; ++k) {
        const float s = std::ldexp(1.0f, -k);
        const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
        mesh.vertices.push_back({s, s, s});
        mesh.vertices.push_back({1.3f * s, s, 1.1f * s});
        mesh.vertices.push_back({s, 1.3f * s, 1.2f * s});
        mesh.triangles.push_back(Triangle{{base, base + 1, base + 2}});
    }
    return mesh;
}

// Rays from random points of the scene box towards random points of the boxes of the
// deepest nodes, so that they walk the longest paths of the tree.
std::vector<Ray> rays_into_deepest_nodes(const SplitGrid& grid, const Aabb& box,
                                         std::uint32_t seed, std::size_t count)
{
    std::vector<NodeBox> nodes = node_boxes(grid);
    const std::uint32_t deepest =
        std::max_element(nodes.begin(), nodes.end(), [](const NodeBox& a, const NodeBox& b) {
            return a.depth < b.depth;
        })->depth;
    std::erase_if(nodes, [&](const NodeBox& n) { return n.depth + 2 < deepest; });
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> pick(0, nodes.size() - 1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Ray> rays;
    for (std::size_t k = 0; k < count; ++k) {
        const Aabb& target = nodes[pick(rng)].box;
        Vec3f from, to;
        for (int a = 0; a < 3; ++a) {
            from[a] = box.lower[a] + u(rng) * box.extent(a);
            to[a] = target.lower[a] + u(rng) * target.extent(a);
        }
        if (from == to) continue;
        rays.push_back(Ray{from, to - from});
    }
    return rays;
}

// Everything adversarial at once, `count` rays in all.
std::vector<Ray> adversarial_rays(const Mesh& mesh, const SplitGrid& grid, std::uint32_t seed,
                                  std::size_t count)
{
    Aabb box = grid.root_box;
    for (int k = 0; k < 3; ++k) {
        const float margin = 0.2f * box.extent(k) + 1.0f;
        box.lower[k] -= margin;
        box.upper[k] += margin;
    }
    std::vector<Ray> rays = random_rays(seed, count / 6, box);
    auto add = [&](const std::vector<Ray>& more) {
        rays.insert(rays.end(), more.begin(), more.end());
    };
    if (!grid.nodes.empty()) {
        PlaneRays planes = rays_on_planes(grid, seed + 1, count / 6 / 24 + 1);
        add(planes.rays);
        add(rays_into_deepest_nodes(grid, box, seed + 2, count / 6));
    }
    add(axis_rays_through_vertices(mesh, grid.root_box, seed + 3, count / 6));
    add(zero_direction_rays(seed + 4, count / 6, box, mesh));
    // Huge, tiny and denormal-tipped directions on rays aimed at triangles.
    std::vector<Ray> scaled = rays_at_triangles(seed + 5, count / 6, box, mesh.view());
    for (std::size_t i = 0; i < scaled.size(); ++i) {
        Ray& r = scaled[i];
        const float s = i % 3 == 0 ? 1e30f : (i % 3 == 1 ? 1e-30f : 1.0f);
        r.direction = r.direction * s;
        if (i % 3 == 2) r.direction[static_cast<int>(i % 5 % 3)] = 1e-40f;
    }
    add(scaled);
    rays.resize(std::min(rays.size(), count));
    return rays;
}

struct WorkSummary {
    std::size_t rays = 0;
    std::size_t over_bound = 0;
    TraversalCounters most;  // the largest of each counter over all rays
    double worst_cell_share = 0.0;  // cells_visited / cell_limit(nodes_visited), largest
};

WorkSummary trace_within_bound(const SplitGrid& grid, const Mesh& mesh,
                               const std::vector<Ray>& rays)
{
    const WorkBound bound(grid);
    const MeshView view = mesh.view();
    struct Part {
        std::size_t over = 0;
        TraversalCounters most;
        double share = 0.0;
    };
    const Part total = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, rays.size(), 4096), Part{},
        [&](const tbb::blocked_range<std::size_t>& r, Part p) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                TraversalCounters closest, any;
                (void)intersect(grid, view, rays[i], &closest);
                (void)occluded(grid, view, rays[i], &any);
                for (const TraversalCounters& c : {closest, any}) {
                    p.over += bound.holds(c) ? 0 : 1;
                    p.most.nodes_visited = std::max(p.most.nodes_visited, c.nodes_visited);
                    p.most.cells_visited = std::max(p.most.cells_visited, c.cells_visited);
                    p.most.triangles_tested =
                        std::max(p.most.triangles_tested, c.triangles_tested);
                    const std::size_t limit = bound.cell_limit(c.nodes_visited);
                    if (limit > 0)
                        p.share = std::max(p.share, double(c.cells_visited) / double(limit));
                }
            }
            return p;
        },
        [](Part a, const Part& b) {
            a.over += b.over;
            a.most.nodes_visited = std::max(a.most.nodes_visited, b.most.nodes_visited);
            a.most.cells_visited = std::max(a.most.cells_visited, b.most.cells_visited);
            a.most.triangles_tested = std::max(a.most.triangles_tested, b.most.triangles_tested);
            a.share = std::max(a.share, b.share);
            return a;
        });
    return {rays.size(), total.over, total.most, total.share};
}

void check_termination(const char* name, const Mesh& mesh, const BuildConfig& config,
                       std::uint32_t seed, std::size_t ray_count)
{
    const SplitGrid grid = build_checked(mesh, config);
    const GridStats stats = compute_stats(grid);
    const std::vector<Ray> rays = adversarial_rays(mesh, grid, seed, ray_count);
    const WorkSummary w = trace_within_bound(grid, mesh, rays);
    const WorkBound bound(grid);
    std::printf("[ steps    ] %-16s depth %2u, %7zu nodes, N_max %3zu, L_max %5zu: %8zu rays x 2 "
                "queries, most nodes %u, cells %u, tests %u; largest share of the cell bound "
                "%.3f; over the bound: %zu\n",
                name, stats.max_depth, grid.nodes.size(), bound.max_resolution, bound.max_leaf,
                w.rays, w.most.nodes_visited, w.most.cells_visited, w.most.triangles_tested,
                w.worst_cell_share, w.over_bound);
    EXPECT_EQ(w.over_bound, 0u) << name;
    EXPECT_GE(w.rays, ray_count * 9 / 10) << name;
    // A sample against brute force, the rays into the deepest nodes included.
    const std::vector<Ray> sample(rays.begin(),
                                  rays.begin() + static_cast<std::ptrdiff_t>(rays.size() / 50));
    const OracleReport r = parallel_compare(grid, mesh.view(), sample);
    EXPECT_EQ(r.closest_disagreements + r.any_hit_disagreements, 0u) << r.first_failure;
}

TEST(Termination, WorkPerRayStaysWithinTheBoundOnOrdinaryAndDeepestGrids)
{
    // 5 * 10^5 rays in CI, 10^7 in full (each traced closest-hit and any-hit), over 5 scenes.
    const std::size_t n = pick_size(500000, 10000000);
    const Aabb box{{0, 0, 0}, {10, 10, 10}};
    check_termination("soup", random_triangles(111, 5000, box, 1.0f), {}, 112, n / 5);
    check_termination("sphere", uv_sphere({1, 2, 3}, 5.0f, 48, 96), {}, 113, n / 5);
    check_termination("cube faces", box_of_planes(), {}, 114, n / 5);
    check_termination("cube, hardest", box_of_planes(), hardest_splitting(), 115, n / 5);
    const Mesh deep = shrinking_triangles();
    BuildConfig deepest = hardest_splitting();
    deepest.resolution_max = 2;
    const SplitGrid grid = build_split_grid(deep.view(), deepest);
    ASSERT_EQ(compute_stats(grid).max_depth, max_supported_depth)
        << "the deepest tree the builder can make must reach the depth limit";
    check_termination("shrinking, deepest", deep, deepest, 117, n / 5);
}

TEST(Termination, RaysThroughTheDeepestAcceptedChainReachItsLeaf)
{
    // 65 nested nodes of one cell each (depths 0 to 64), alternating axes, and a triangle
    // across the box in the leaf under the deepest: the deepest grid check_invariants
    // accepts. (The walk keeps no cursor for a one-cell node: this tests depth, not the
    // stack.)
    SplitGrid g;
    g.root_box = Aabb{{0, 0, 0}, {1, 1, 1}};
    g.triangle_count = 1;
    g.root = CellRef::make_inner(0, 1);
    for (std::uint32_t d = 0; d <= max_supported_depth; ++d) {
        g.nodes.push_back(GridNode::make_one_cell(static_cast<int>(d % 3), 0.0f, 1.0f,
                                                  d == max_supported_depth
                                                      ? CellRef::make_leaf(0)
                                                      : CellRef::make_inner(d + 1, 1)));
    }
    g.leaf_words = {0x0000, 0x8000};  // one leaf: triangle 0, marked last
    Mesh mesh;
    mesh.vertices = {{0.0f, 0.0f, 0.5f}, {1.0f, 0.0f, 0.5f}, {0.0f, 1.0f, 0.5f}};
    mesh.triangles = {Triangle{{0, 1, 2}}};
    check_invariants(g);
    check_coverage(g, mesh.view());
    const std::vector<Ray> rays = rays_at_triangles(116, 2000, Aabb{{-1, -1, -1}, {2, 2, 2}},
                                                    mesh.view());
    std::size_t deep_hits = 0;
    for (const Ray& r : rays) {
        TraversalCounters c;
        const Hit hit = intersect(g, mesh.view(), r, &c);
        const Hit truth = intersect_brute_force(mesh.view(), r);
        ASSERT_EQ(hit.is_hit(), truth.is_hit());
        if (!hit.is_hit()) continue;
        EXPECT_EQ(hit.t, truth.t);
        EXPECT_EQ(c.nodes_visited, max_supported_depth + 1);
        ++deep_hits;
    }
    EXPECT_GT(deep_hits, 1000u);
}

}  // namespace
}  // namespace sg::test
