// The kd-tree: brute-force oracle cases (baseline_oracle_cases.hpp), leaf coverage checked with
// an independent separating-axis test, the SAH's choices on simple scenes, config checks.

#include "splitgrid/baselines/kd_tree.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "baseline_oracle_cases.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/clip.hpp"
#include "splitgrid/error.hpp"

namespace sg::test {

template <>
struct BaselineTraits<KdTree> {
    // Structure: split planes strictly inside their node's box, leaves' references in range,
    // depth within the limit. Coverage: every triangle is referenced by each leaf whose box it
    // overlaps (separating-axis test, independent of the builder's clipping), by no leaf
    // farther than the pad, and the references so found are all there are.
    static void check(const KdTree& tree, const MeshView& mesh)
    {
        ASSERT_EQ(tree.triangle_count(), mesh.triangle_count());
        if (mesh.triangle_count() == 0) {
            ASSERT_EQ(tree.node_count(), 0u);
            return;
        }
        ASSERT_LE(tree.depth(), KdTreeConfig{}.depth_limit(mesh.triangle_count()));
        const auto nodes = tree.nodes();
        const auto refs = tree.refs();
        // Leaf boxes by a walk from the root.
        std::vector<Aabb> boxes(nodes.size());
        boxes[0] = tree.box();
        for (std::size_t i = 0; i < nodes.size(); ++i) {
            const KdNode& n = nodes[i];
            if (n.is_leaf()) {
                ASSERT_LE(std::size_t{n.first_ref()} + n.ref_count(), refs.size());
                continue;
            }
            const int a = n.axis();
            ASSERT_GT(n.split(), boxes[i].lower[a]);
            ASSERT_LT(n.split(), boxes[i].upper[a]);
            ASSERT_LT(n.above_child(), nodes.size());
            ASSERT_GT(n.above_child(), i + 1);
            boxes[i + 1] = boxes[i];
            boxes[i + 1].upper[a] = n.split();
            boxes[n.above_child()] = boxes[i];
            boxes[n.above_child()].lower[a] = n.split();
        }
        const double pad = boundary_pad(bounds(mesh));
        std::size_t found = 0;
        for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
            const Vec3d a(mesh.vertex(t, 0)), b(mesh.vertex(t, 1)), c(mesh.vertex(t, 2));
            const Aabbd near{{std::min({a.x, b.x, c.x}) - 2 * pad, std::min({a.y, b.y, c.y}) - 2 * pad,
                              std::min({a.z, b.z, c.z}) - 2 * pad},
                             {std::max({a.x, b.x, c.x}) + 2 * pad, std::max({a.y, b.y, c.y}) + 2 * pad,
                              std::max({a.z, b.z, c.z}) + 2 * pad}};
            std::vector<std::uint32_t> pending{0};
            while (!pending.empty()) {
                const std::uint32_t i = pending.back();
                pending.pop_back();
                const KdNode& n = nodes[i];
                if (!n.is_leaf()) {
                    const int ax = n.axis();
                    if (near.lower[ax] <= n.split()) pending.push_back(i + 1);
                    if (near.upper[ax] >= n.split()) pending.push_back(n.above_child());
                    continue;
                }
                const auto leaf = refs.subspan(n.first_ref(), n.ref_count());
                const bool referenced = std::find(leaf.begin(), leaf.end(), t) != leaf.end();
                found += referenced ? 1 : 0;
                const Aabbd box = Aabbd::from(boxes[i]);
                if (triangle_overlaps_box(a, b, c, box)) {
                    ASSERT_TRUE(referenced) << "triangle " << t << " overlaps leaf " << i
                                            << " that misses it";
                }
                if (referenced) {
                    ASSERT_TRUE(triangle_overlaps_box(a, b, c, box.padded(2.0 * pad)))
                        << "triangle " << t << " is referenced by leaf " << i << " it does not touch";
                }
            }
        }
        ASSERT_EQ(found, tree.reference_count()) << "references far from their triangles";
    }
    static std::vector<std::pair<int, float>> planes(const KdTree& tree)
    {
        std::vector<std::pair<int, float>> p;
        for (const KdNode& n : tree.nodes())
            if (!n.is_leaf()) p.emplace_back(n.axis(), n.split());
        return p;
    }
    static KdTreeConfig stable_planes_config() { return {}; }
    static std::uint32_t depth(const KdTree& tree) { return tree.depth(); }
    static std::uint32_t depth_limit(std::size_t n) { return KdTreeConfig{}.depth_limit(n); }
};

INSTANTIATE_TYPED_TEST_SUITE_P(KdTree, BaselineOracle, ::testing::Types<KdTree>);

namespace {

TEST(KdTreeBuild, AutomaticDepthFollowsHavransRule)
{
    const KdTreeConfig config;
    EXPECT_EQ(config.depth_limit(1), 8u);
    EXPECT_EQ(config.depth_limit(1024), 21u);         // 8 + 1.3 * 10
    EXPECT_EQ(config.depth_limit(871414), 34u);       // the Stanford dragon
    EXPECT_EQ(config.depth_limit(std::size_t{1} << 60), 64u);
    KdTreeConfig fixed;
    fixed.max_depth = 5;
    EXPECT_EQ(fixed.depth_limit(1000000), 5u);
}

// Two clusters far apart: the SAH's first plane must cut the empty space between them, in
// both the binned (large node) and the exact (small node) evaluation.
TEST(KdTreeBuild, FirstSplitSeparatesDistantClusters)
{
    Mesh mesh = random_triangles(3, 600, Aabb{{0, 0, 0}, {1, 1, 1}}, 0.1f);
    append(mesh, random_triangles(4, 600, Aabb{{9, 0, 0}, {10, 1, 1}}, 0.1f));
    for (std::uint32_t exact_below : {0u, 100000u}) {
        KdTreeConfig config;
        config.exact_below = exact_below;
        const KdTree tree = build_checked_baseline<KdTree>(mesh, config);
        const KdNode root = tree.nodes()[0];
        ASSERT_FALSE(root.is_leaf());
        EXPECT_EQ(root.axis(), 0);
        EXPECT_GT(root.split(), 1.05f);
        EXPECT_LT(root.split(), 8.95f);
    }
}

TEST(KdTreeBuild, MaxDepthBoundsTheTree)
{
    const Mesh mesh = random_triangles(8, 3000, baseline_scene_box, 0.5f);
    KdTreeConfig config;
    config.max_depth = 4;
    const KdTree tree = KdTree::build(mesh.view(), config);
    EXPECT_LE(tree.depth(), 4u);
    EXPECT_LE(tree.leaf_count(), 16u);
    expect_baseline_agrees(tree, mesh, rays_at_triangles(9, 2000, baseline_scene_box, mesh.view()), 1500);
}

TEST(KdTreeBuild, MemoryIsNodesAndReferences)
{
    const Mesh mesh = random_triangles(10, 1000, baseline_scene_box, 1.0f);
    const KdTree tree = KdTree::build(mesh.view());
    EXPECT_EQ(tree.memory_bytes(), sizeof(Aabb) + 4u + tree.node_count() * 8u + tree.reference_count() * 4u);
    EXPECT_GE(tree.reference_count(), mesh.triangles.size());
    EXPECT_EQ(tree.node_count(), 2 * tree.leaf_count() - 1);
}

TEST(KdTreeConfig, BadValuesNameTheField)
{
    EXPECT_EQ(config_error(KdTreeConfig{}), "");
    KdTreeConfig c;
    c.traversal_cost = 0.0;
    EXPECT_NE(config_error(c).find("KdTreeConfig.traversal_cost = 0"), std::string::npos);
    c = {};
    c.intersection_cost = std::nan("");
    EXPECT_NE(config_error(c).find("intersection_cost"), std::string::npos);
    c = {};
    c.empty_bonus = 1.0;
    EXPECT_NE(config_error(c).find("empty_bonus"), std::string::npos);
    c = {};
    c.max_depth = 65;
    EXPECT_NE(config_error(c).find("max_depth = 65"), std::string::npos);
    c = {};
    c.leaf_size = 0;
    EXPECT_NE(config_error(c).find("leaf_size"), std::string::npos);
    c = {};
    c.bins = 1;
    EXPECT_NE(config_error(c).find("bins"), std::string::npos);
    c = {};
    c.threads = 2000;
    EXPECT_NE(config_error(c).find("threads"), std::string::npos);
    const Mesh mesh = random_triangles(1, 10, baseline_scene_box, 1.0f);
    EXPECT_THROW((void)KdTree::build(mesh.view(), c), ConfigError);
}

TEST(KdTreeBuild, BadMeshIsAnInputError)
{
    Mesh mesh = random_triangles(1, 10, baseline_scene_box, 1.0f);
    mesh.triangles[2].v[0] = 77;
    EXPECT_THROW((void)KdTree::build(mesh.view()), InputError);
}

}  // namespace
}  // namespace sg::test
