#include "splitgrid/builder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "splitgrid/baselines/kd_tree.hpp"
#include "splitgrid/baselines/uniform_grid.hpp"
#include "splitgrid/cell_math.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/stats.hpp"
#include "splitgrid/traverse.hpp"
#include "splitgrid/validate.hpp"
#include "support/leaf_triangles.hpp"
#include "support/one_cell_nodes.hpp"
#include "support/oracle.hpp"
#include "support/random_scene.hpp"

namespace sg {
namespace {

const Aabb box10{{0, 0, 0}, {10, 10, 10}};

using test::build_checked;

TEST(Builder, OutputIsIdenticalForEveryThreadCount)
{
    // Large enough that the root's work and its children run in parallel.
    const Mesh mesh = test::random_triangles(1, 60000, box10, 0.3f);
    BuildConfig config;
    config.threads = 1;
    const SplitGrid one = build_checked(mesh, config);
    for (std::uint32_t threads : {2u, 4u, 0u}) {
        config.threads = threads;
        const SplitGrid other = build_split_grid(mesh.view(), config);
        EXPECT_TRUE(other == one) << "threads = " << threads;
    }
}

// The Split Grid, the kd-tree and the uniform grid are built in the same box: the scene's
// bounding box widened by its boundary_pad on each side, computed here from the corners, and
// kept finite where a coordinate lies at +-FLT_MAX (widened, it would round to an infinity).
// The expectation is the rule itself, so this guards the rule and its one implementation; the
// structures built in it must then give brute force's answers (at +-FLT_MAX: no crash, and
// the misses brute force gives).
TEST(Builder, GridsAndKdTreeAreBuiltInTheScenesBoxPaddedAndKeptFinite)
{
    constexpr float float_max = std::numeric_limits<float>::max();
    const Mesh huge{{{-float_max, 0.0f, 0.0f}, {float_max, 1.0f, 0.0f}, {0.0f, 2.0f, 3.0f}},
                    {Triangle{{0, 1, 2}}}};
    const Mesh ordinary = test::random_triangles(5, 2000, box10, 0.3f);
    for (const Mesh* each : {&ordinary, &huge}) {
        const Mesh& mesh = *each;
        Aabb scene;
        for (const Vec3f& v : mesh.vertices) scene.extend(v);
        const float pad = boundary_pad(scene);
        Aabb expected;
        for (int k = 0; k < 3; ++k) {
            const float lower = scene.lower[k] - pad;
            const float upper = scene.upper[k] + pad;
            expected.lower[k] = std::isinf(lower) ? -float_max : lower;
            expected.upper[k] = std::isinf(upper) ? float_max : upper;
        }
        const SplitGrid grid = build_checked(mesh, {});
        const KdTree tree = KdTree::build(mesh.view());
        const UniformGrid uniform = UniformGrid::build(mesh.view());
        for (const Aabb& box : {grid.root_box, tree.box(), uniform.box()})
            for (int k = 0; k < 3; ++k) {
                EXPECT_EQ(box.lower[k], expected.lower[k]) << "axis " << k;
                EXPECT_EQ(box.upper[k], expected.upper[k]) << "axis " << k;
            }
        // And they answer as brute force does.
        const auto rays = test::rays_at_triangles(6, 500, scene, mesh.view());
        const test::OracleReport reports[] = {
            test::compare_with_brute_force(grid, mesh.view(), rays),
            test::compare_structure_with_brute_force(tree, mesh.view(), rays),
            test::compare_structure_with_brute_force(uniform, mesh.view(), rays)};
        for (const test::OracleReport& r : reports) {
            EXPECT_EQ(r.closest_disagreements + r.any_hit_disagreements, 0u) << r.first_failure;
            // The ordinary mesh's rays reach its triangles; at +-FLT_MAX the triangle test's
            // products overflow, and brute force finds no hit either.
            if (each == &ordinary) {
                EXPECT_GT(r.hits, r.rays / 2);
            }
        }
    }
}

TEST(Builder, LeavesRespectTheLeafSizeUnlessSplittingStopped)
{
    const Mesh mesh = test::random_triangles(2, 5000, box10, 0.2f);
    BuildConfig config;
    config.leaf_size = 6;
    const SplitGrid grid = build_checked(mesh, config);
    const GridStats stats = compute_stats(grid);
    // Small triangles in a big box: splitting never stalls, so no leaf should be larger than
    // a handful over the limit.
    EXPECT_LE(stats.leaf_size_mean, 6.0);
    EXPECT_GT(stats.node_count, 100u);
}

TEST(Builder, DepthLimitIsHonoured)
{
    const Mesh mesh = test::random_triangles(3, 5000, box10, 0.2f);
    for (std::uint32_t depth : {0u, 1u, 3u}) {
        BuildConfig config;
        config.max_depth = depth;
        const SplitGrid grid = build_checked(mesh, config);
        EXPECT_LE(compute_stats(grid).max_depth, depth);
        const auto rays = test::rays_at_triangles(4, 2000, box10, mesh.view());
        const auto r = test::compare_with_brute_force(grid, mesh.view(), rays);
        EXPECT_EQ(r.closest_disagreements + r.any_hit_disagreements, 0u) << r.first_failure;
    }
}

TEST(Builder, RebuildGivesWhatABuildGivesAndReusesTheArrays)
{
    // A scene whose vertices move (a dynamic scene), then a smaller one, then an empty one,
    // rebuilt into the same grid each time; the poster preset in between changes the config.
    Mesh mesh = test::random_triangles(31, 20000, box10, 0.3f);
    SplitGrid grid = build_checked(mesh);
    // The same mesh again: the same sizes, so the very same arrays.
    const GridNode* nodes = grid.nodes.data();
    const CellRef* cells = grid.cells.data();
    const std::uint16_t* words = grid.leaf_words.data();
    rebuild_split_grid(grid, mesh.view(), BuildConfig{});
    EXPECT_TRUE(grid == build_split_grid(mesh.view(), BuildConfig{}));
    EXPECT_EQ(grid.nodes.data(), nodes);
    EXPECT_EQ(grid.cells.data(), cells);
    EXPECT_EQ(grid.leaf_words.data(), words);

    for (Vec3f& v : mesh.vertices) v = Vec3f{v.x + 0.3f * std::sin(v.y), v.y, v.z * 0.9f};
    rebuild_split_grid(grid, mesh.view(), BuildConfig{});
    EXPECT_TRUE(grid == build_split_grid(mesh.view(), BuildConfig{}));

    const BuildConfig poster = apply_build_preset(BuildConfig{}, "poster");
    rebuild_split_grid(grid, mesh.view(), poster);
    EXPECT_TRUE(grid == build_split_grid(mesh.view(), poster));

    const Mesh smaller = test::random_triangles(32, 500, box10, 1.0f);
    rebuild_split_grid(grid, smaller.view(), BuildConfig{});
    EXPECT_TRUE(grid == build_split_grid(smaller.view(), BuildConfig{}));
    const test::OracleReport report = test::compare_with_brute_force(
        grid, smaller.view(), test::random_rays(33, 2000, box10));
    EXPECT_EQ(report.closest_disagreements + report.any_hit_disagreements, 0u)
        << report.first_failure;

    rebuild_split_grid(grid, Mesh{}.view(), BuildConfig{});
    EXPECT_TRUE(grid == build_split_grid(Mesh{}.view(), BuildConfig{}));
    EXPECT_TRUE(grid.root.is_empty());
}

TEST(Builder, EmptyMeshGivesAnEmptyGrid)
{
    const Mesh mesh;
    const SplitGrid grid = build_checked(mesh);
    EXPECT_TRUE(grid.root.is_empty());
    EXPECT_TRUE(grid.nodes.empty());
    EXPECT_FALSE(intersect(grid, mesh.view(), Ray{{0, 0, 0}, {1, 0, 0}}).is_hit());
}

TEST(Builder, SingleTriangleIsALeafRoot)
{
    Mesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.triangles = {Triangle{{0, 1, 2}}};
    const SplitGrid grid = build_checked(mesh);
    ASSERT_TRUE(grid.root.is_leaf());
    const Hit hit = intersect(grid, mesh.view(), Ray{{0.25f, 0.25f, 1.0f}, {0, 0, -1}});
    ASSERT_TRUE(hit.is_hit());
    EXPECT_EQ(hit.t, 1.0f);
    EXPECT_EQ(hit.u, 0.25f);
    EXPECT_EQ(hit.v, 0.25f);
}

TEST(Builder, ManyCopiesOfOneTriangleStopSplitting)
{
    Mesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0.5f}};
    mesh.triangles.assign(100000, Triangle{{0, 1, 2}});
    const SplitGrid grid = build_checked(mesh);
    // Every cell would receive every copy, so the builder must give up at once.
    EXPECT_LE(grid.nodes.size(), 1u);
    EXPECT_LE(test::counted_references(grid), 200000u);
    const Hit hit = intersect(grid, mesh.view(), Ray{{0.1f, 0.1f, 5.0f}, {0, 0, -1}});
    EXPECT_TRUE(hit.is_hit());
}

TEST(Builder, AFanAroundAVertexEndsInALeafAndNotAtTheDepthLimit)
{
    // 48 long triangles around one vertex, on a wavy surface so the fan is not flat (and the
    // vertex off the middle, so that it lies inside a cell, not on a cell boundary). Every
    // cell holding the vertex holds all of them, so each split around it only repeats itself
    // at a smaller scale. Without the cost test and with every split counted as progress,
    // nothing else stops that chain before max_depth (depth 32 and 18,000 references
    // without the rule that ends it).
    Mesh mesh;
    mesh.vertices.push_back({5.3f, 4.6f, 5.2f});
    constexpr int spokes = 48;
    for (int k = 0; k < spokes; ++k) {
        const double a = 2.0 * 3.14159265358979 * k / spokes;
        mesh.vertices.push_back({static_cast<float>(5 + 4.5 * std::cos(a)),
                                 static_cast<float>(5 + 4.5 * std::sin(a)),
                                 static_cast<float>(5 + 2.0 * std::sin(3 * a))});
    }
    for (std::uint32_t k = 0; k < spokes; ++k)
        mesh.triangles.push_back(Triangle{{0, 1 + k, 1 + (k + 1) % spokes}});
    BuildConfig config;
    config.stop_by_cost = false;
    config.no_progress_fraction = 1.0;
    config.min_cell_width = 0.0;
    config.max_depth = max_supported_depth;
    for (bool bounding_nodes : {false, true}) {
        config.bounding_nodes = bounding_nodes;
        const SplitGrid grid = build_checked(mesh, config);
        const GridStats stats = compute_stats(grid);
        EXPECT_LE(stats.max_depth, 12u) << "bounding nodes " << bounding_nodes;
        EXPECT_LE(test::counted_references(grid), 10u * spokes) << "bounding nodes " << bounding_nodes;
        const auto rays = test::rays_at_triangles(6, 4000, box10, mesh.view());
        const auto r = test::compare_with_brute_force(grid, mesh.view(), rays);
        EXPECT_EQ(r.closest_disagreements + r.any_hit_disagreements, 0u) << r.first_failure;
    }
}

// 4000 small random triangles and, last, one long sliver along the box's diagonal.
Mesh small_triangles_and_a_diagonal_sliver()
{
    Mesh mesh = test::random_triangles(5, 4000, box10, 0.1f);
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back({0, 0, 0});
    mesh.vertices.push_back({10, 10, 10});
    mesh.vertices.push_back({10, 10.01f, 10});
    mesh.triangles.push_back(Triangle{{base, base + 1, base + 2}});
    return mesh;
}

TEST(Builder, TrianglesAreReferencedOnlyWhereTheyReallyAre)
{
    // A long diagonal sliver crosses many cells' bounding boxes but few cells; box-overlap
    // assignment would reference it in about resolution^2 cells of a 2-level grid.
    const Mesh mesh = small_triangles_and_a_diagonal_sliver();
    const auto sliver = static_cast<std::uint32_t>(mesh.triangles.size() - 1);
    const SplitGrid grid = build_checked(mesh);
    const std::size_t sliver_refs = test::references_to(grid, sliver);
    const GridStats stats = compute_stats(grid);
    EXPECT_GT(sliver_refs, 0u);
    // Clipping keeps the sliver to the cells along the diagonal: far fewer than the leaves.
    EXPECT_LT(sliver_refs * 10, stats.leaf_cells);
}

TEST(Builder, WithoutClippingTheSliverIsReferencedByItsBoundingBoxAndStillFound)
{
    // The same scene as above with clip_triangles off: the sliver's bounding box is the whole
    // scene, so it lands in far more cells; the grid stays exact.
    const Mesh mesh = small_triangles_and_a_diagonal_sliver();
    const auto sliver = static_cast<std::uint32_t>(mesh.triangles.size() - 1);
    auto refs_of_sliver = [&](const SplitGrid& g) { return test::references_to(g, sliver); };
    BuildConfig config;
    const std::size_t clipped = refs_of_sliver(build_checked(mesh, config));
    config.clip_triangles = false;
    const SplitGrid boxed = build_checked(mesh, config);
    EXPECT_GT(refs_of_sliver(boxed), 4 * clipped);
    const auto rays = test::rays_at_triangles(51, 4000, box10, mesh.view());
    const auto report = test::compare_with_brute_force(boxed, mesh.view(), rays);
    EXPECT_EQ(report.closest_disagreements, 0u) << report.first_failure;
    EXPECT_EQ(report.any_hit_disagreements, 0u) << report.first_failure;
}

// Every node's box, by walking down from the root box (cells narrow the parent's box).
void collect_node_boxes(const SplitGrid& grid, std::uint32_t node, const Aabb& box,
                        std::vector<Aabb>& boxes)
{
    boxes[node] = box;
    const GridNode& n = grid.nodes[node];
    const CellMath cm(n.lo, n.hi, n.resolution());
    for (std::uint32_t c = 0; c < n.resolution(); ++c) {
        const CellRef cell = node_cell(grid, n, c);
        if (cell.is_inner()) collect_node_boxes(grid, cell.child(), cm.cell_box(box, n.axis(), c), boxes);
    }
}

TEST(Builder, WithoutBoundingPlanesEveryNodeSpansItsBoxAndStaysExact)
{
    Mesh mesh = test::random_triangles(6, 3000, box10, 0.4f);
    test::append(mesh, test::uv_sphere({3, 3, 3}, 1.5f, 16, 24));
    BuildConfig config;
    config.bounding_planes = false;
    config.bounding_nodes = false;  // a plain nested grid: no planes on any axis
    const SplitGrid grid = build_checked(mesh, config);
    ASSERT_TRUE(grid.root.is_inner());
    std::vector<Aabb> boxes(grid.nodes.size());
    collect_node_boxes(grid, grid.root.child(), grid.root_box, boxes);
    for (std::size_t k = 0; k < grid.nodes.size(); ++k) {
        const int axis = grid.nodes[k].axis();
        EXPECT_EQ(grid.nodes[k].lo, boxes[k].lower[axis]) << "node " << k;
        EXPECT_EQ(grid.nodes[k].hi, boxes[k].upper[axis]) << "node " << k;
    }
    auto rays = test::random_rays(61, 3000, box10);
    const auto aimed = test::rays_at_triangles(62, 3000, box10, mesh.view());
    rays.insert(rays.end(), aimed.begin(), aimed.end());
    const auto report = test::compare_with_brute_force(grid, mesh.view(), rays);
    EXPECT_EQ(report.closest_disagreements, 0u) << report.first_failure;
    EXPECT_EQ(report.any_hit_disagreements, 0u) << report.first_failure;
    // With the planes, some node is narrower than its box: the option changes something.
    const SplitGrid tight = build_checked(mesh);
    std::vector<Aabb> tight_boxes(tight.nodes.size());
    collect_node_boxes(tight, tight.root.child(), tight.root_box, tight_boxes);
    std::size_t narrowed = 0;
    for (std::size_t k = 0; k < tight.nodes.size(); ++k) {
        const int axis = tight.nodes[k].axis();
        narrowed += tight.nodes[k].lo > tight_boxes[k].lower[axis] ||
                    tight.nodes[k].hi < tight_boxes[k].upper[axis];
    }
    EXPECT_GT(narrowed, tight.nodes.size() / 4);
}

// Three small clusters on a diagonal: every cell between them is mostly empty space on the
// axes the split did not cut, which is what bounding nodes are for.
Mesh diagonal_clusters()
{
    Mesh mesh;
    for (std::uint32_t k = 0; k < 3; ++k) {
        const float o = 1.0f + 3.5f * static_cast<float>(k);
        test::append(mesh, test::random_triangles(20 + k, 400, Aabb{{o, o, o}, {o + 1, o + 1, o + 1}}, 0.2f));
    }
    test::append(mesh, test::uv_sphere({8, 2, 8}, 0.7f, 12, 16));
    return mesh;
}

TEST(Builder, BoundingNodesAreOneCellNodesThatTraceExactly)
{
    const Mesh mesh = diagonal_clusters();
    BuildConfig off;
    off.bounding_nodes = false;
    const SplitGrid plain = build_checked(mesh, off);
    const SplitGrid bounded = build_checked(mesh);  // the default: bounding nodes on
    EXPECT_EQ(test::one_cell_node_count(plain), 0u)
        << "the split rule alone makes nodes of 2 cells or more";
    EXPECT_GT(test::one_cell_node_count(bounded), 10u);

    // Every one-cell node narrows its box. (build_checked has also checked, with a
    // separating-axis test independent of the clipper, that every triangle touching a cell's
    // box, narrowed by the one-cell nodes above it, is referenced there.)
    std::vector<Aabb> boxes(bounded.nodes.size());
    collect_node_boxes(bounded, bounded.root.child(), bounded.root_box, boxes);
    for (std::size_t k = 0; k < bounded.nodes.size(); ++k) {
        const GridNode& n = bounded.nodes[k];
        if (n.resolution() != 1) continue;
        EXPECT_TRUE(n.lo > boxes[k].lower[n.axis()] || n.hi < boxes[k].upper[n.axis()]) << "node " << k;
    }

    // Brute force agrees on random, aimed, axis-parallel and zero-component rays, closest and
    // any hit (the traversal enters one-cell nodes without a cursor).
    auto rays = test::random_rays(71, 4000, box10);
    for (auto extra : {test::rays_at_triangles(72, 4000, box10, mesh.view()),
                       test::zero_direction_rays(73, 4000, box10, mesh),
                       test::axis_rays_through_lattice(74, 4000, 10, true)})
        rays.insert(rays.end(), extra.begin(), extra.end());
    for (const SplitGrid* grid : {&plain, &bounded}) {
        const auto report = test::compare_with_brute_force(*grid, mesh.view(), rays);
        EXPECT_EQ(report.closest_disagreements, 0u) << report.first_failure;
        EXPECT_EQ(report.any_hit_disagreements, 0u) << report.first_failure;
    }
    // Same answers as without them: the closest hits are the same triangles at the same t.
    for (const Ray& ray : rays) {
        const Hit a = intersect(plain, mesh.view(), ray);
        const Hit b = intersect(bounded, mesh.view(), ray);
        ASSERT_TRUE(test::same_closest_hit(a, b));
    }
}

TEST(Builder, RejectsBadConfigAndBadMesh)
{
    const Mesh mesh = test::random_triangles(6, 10, box10, 1.0f);
    BuildConfig config;
    config.leaf_size = 0;
    try {
        (void)build_split_grid(mesh.view(), config);
        FAIL() << "leaf_size 0 accepted";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("leaf_size"), std::string::npos) << e.what();
    }
    config = {};
    config.resolution_min = 10;
    config.resolution_max = 5;
    EXPECT_THROW((void)build_split_grid(mesh.view(), config), ConfigError);
    config = {};
    config.resolution_sigma = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW((void)build_split_grid(mesh.view(), config), ConfigError);
    config = {};
    config.max_depth = max_supported_depth + 1;
    EXPECT_THROW((void)build_split_grid(mesh.view(), config), ConfigError);

    Mesh bad = mesh;
    bad.triangles[3].v[1] = 999;
    EXPECT_THROW((void)build_split_grid(bad.view(), {}), InputError);
    bad = mesh;
    bad.vertices[4].y = std::numeric_limits<float>::infinity();
    EXPECT_THROW((void)build_split_grid(bad.view(), {}), InputError);
}

TEST(Builder, FarFromTheOriginStaysExact)
{
    // Embree's watertightness position; triangles span thousands of ulps there.
    const Mesh mesh = test::uv_sphere({148376.0f, 1234.0f, -223423.0f}, 400.0f, 48, 96);
    const SplitGrid grid = build_checked(mesh);
    const Aabb inside{{148376.0f - 200, 1234.0f - 200, -223423.0f - 200},
                      {148376.0f + 200, 1234.0f + 200, -223423.0f + 200}};
    const auto rays = test::random_rays(7, 20000, inside);
    std::size_t misses = 0;
    for (const Ray& r : rays) misses += intersect(grid, mesh.view(), r).is_hit() ? 0 : 1;
    EXPECT_EQ(misses, 0u);
    const auto r = test::compare_with_brute_force(grid, mesh.view(), rays);
    EXPECT_EQ(r.closest_disagreements + r.any_hit_disagreements, 0u) << r.first_failure;
}

TEST(Builder, HugeCoordinatesStillSplitAndAgree)
{
    // 1e15: near the top of the range the float triangle test supports (products of two
    // coordinate differences must stay below FLT_MAX).
    const float big = 1e15f;
    const Mesh mesh = test::random_triangles(9, 3000, Aabb{{-big, -big, -big}, {big, big, big}},
                                            big / 20.0f);
    const SplitGrid grid = build_checked(mesh);
    EXPECT_GT(grid.nodes.size(), 10u);
    const Aabb inner{{-big / 2, -big / 2, -big / 2}, {big / 2, big / 2, big / 2}};
    const auto rays = test::rays_at_triangles(10, 3000, inner, mesh.view());
    const auto r = test::compare_with_brute_force(grid, mesh.view(), rays);
    EXPECT_EQ(r.closest_disagreements + r.any_hit_disagreements, 0u) << r.first_failure;
    EXPECT_GT(r.hits, 1000u);
}

TEST(Builder, ProgressReachesOneAndNeverGoesBack)
{
    const Mesh mesh = test::random_triangles(8, 20000, box10, 0.2f);
    std::vector<double> seen;
    (void)build_split_grid(mesh.view(), {}, [&](double f) { seen.push_back(f); });
    ASSERT_FALSE(seen.empty());
    for (std::size_t k = 1; k < seen.size(); ++k) EXPECT_GE(seen[k], seen[k - 1]);
    EXPECT_NEAR(seen.back(), 1.0, 1e-6);
}

}  // namespace
}  // namespace sg
