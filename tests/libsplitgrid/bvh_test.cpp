// The BVH: brute-force oracle cases (baseline_oracle_cases.hpp), its box invariants, the SAH's
// choices on simple scenes, termination on inseparable triangles, config checks.

#include "splitgrid/baselines/bvh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "baseline_oracle_cases.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"

namespace sg::test {

template <>
struct BaselineTraits<Bvh> {
    // Every triangle is referenced exactly once; every node's box holds its children's boxes,
    // and every leaf's box holds its triangles' bounding boxes padded by boundary_pad.
    static void check(const Bvh& bvh, const MeshView& mesh)
    {
        ASSERT_EQ(bvh.triangle_count(), mesh.triangle_count());
        if (mesh.triangle_count() == 0) {
            ASSERT_EQ(bvh.node_count(), 0u);
            return;
        }
        const auto nodes = bvh.nodes();
        const auto refs = bvh.refs();
        ASSERT_EQ(refs.size(), mesh.triangle_count());
        std::vector<int> seen(mesh.triangle_count(), 0);
        const double pad = boundary_pad(bounds(mesh));
        std::vector<std::uint32_t> depth(nodes.size(), 0);
        std::size_t leaves = 0;
        for (std::size_t i = 0; i < nodes.size(); ++i) {
            const BvhNode& n = nodes[i];
            if (!n.is_leaf()) {
                ASSERT_GT(n.first_child(), i);
                ASSERT_LT(n.first_child() + 1u, nodes.size());
                for (std::uint32_t c = n.first_child(); c <= n.first_child() + 1; ++c) {
                    ASSERT_TRUE(n.bounds.contains(nodes[c].bounds)) << "node " << c;
                    depth[c] = depth[i] + 1;
                }
                continue;
            }
            ++leaves;
            ASSERT_GE(n.ref_count(), 1u);
            ASSERT_LE(std::size_t{n.first_ref()} + n.ref_count(), refs.size());
            ASSERT_LE(depth[i], bvh.depth());
            for (std::uint32_t r = n.first_ref(); r < n.first_ref() + n.ref_count(); ++r) {
                const std::uint32_t t = refs[r];
                ASSERT_LT(t, mesh.triangle_count());
                ++seen[t];
                for (int corner = 0; corner < 3; ++corner)
                    for (int k = 0; k < 3; ++k) {
                        const double v = mesh.vertex(t, corner)[k];
                        ASSERT_LE(double(n.bounds.lower[k]), v - pad) << "triangle " << t;
                        ASSERT_GE(double(n.bounds.upper[k]), v + pad) << "triangle " << t;
                    }
            }
        }
        ASSERT_EQ(leaves, bvh.leaf_count());
        for (std::size_t t = 0; t < seen.size(); ++t) ASSERT_EQ(seen[t], 1) << "triangle " << t;
        ASSERT_NO_FATAL_FAILURE(check_wide(bvh, mesh, pad));
    }
    // The tree the traversal walks, checked against the mesh alone: from the root, every wide
    // node is reached once, every triangle once through a leaf slot whose box holds its
    // padded box, every inner slot's box holds its wide node's boxes, and unused slots are
    // empty and last.
    static void check_wide(const Bvh& bvh, const MeshView& mesh, double pad)
    {
        const auto wide = bvh.wide_nodes();
        if (bvh.nodes()[0].is_leaf()) {
            ASSERT_TRUE(wide.empty());
            return;
        }
        ASSERT_FALSE(wide.empty());
        std::vector<int> reached(wide.size(), 0);
        std::vector<int> seen(mesh.triangle_count(), 0);
        std::vector<std::uint32_t> todo{0};
        reached[0] = 1;
        while (!todo.empty()) {
            const BvhWideNode& w = wide[todo.back()];
            todo.pop_back();
            int used = 0;
            for (int i = 0; i < BvhWideNode::width; ++i) {
                if (!w.is_used(i)) {
                    EXPECT_EQ(w.count[i], 0u);
                    for (int k = 0; k < 3; ++k) EXPECT_GT(w.lower[k][i], w.upper[k][i]);
                    continue;
                }
                ASSERT_EQ(used++, i) << "a used slot after an unused one";
                if (w.is_leaf(i)) {
                    ASSERT_LE(std::size_t{w.child[i]} + w.count[i], bvh.refs().size());
                    for (std::uint32_t r = w.child[i]; r < w.child[i] + w.count[i]; ++r) {
                        const std::uint32_t t = bvh.refs()[r];
                        ASSERT_LT(t, mesh.triangle_count());
                        ++seen[t];
                        for (int corner = 0; corner < 3; ++corner)
                            for (int k = 0; k < 3; ++k) {
                                const double v = mesh.vertex(t, corner)[k];
                                ASSERT_LE(double(w.lower[k][i]), v - pad) << "triangle " << t;
                                ASSERT_GE(double(w.upper[k][i]), v + pad) << "triangle " << t;
                            }
                    }
                    continue;
                }
                ASSERT_LT(w.child[i], wide.size());
                ASSERT_EQ(reached[w.child[i]]++, 0) << "wide node " << w.child[i];
                const BvhWideNode& c = wide[w.child[i]];
                for (int j = 0; j < BvhWideNode::width; ++j)
                    for (int k = 0; k < 3; ++k)
                        if (c.is_used(j)) {
                            ASSERT_LE(w.lower[k][i], c.lower[k][j]);
                            ASSERT_GE(w.upper[k][i], c.upper[k][j]);
                        }
                todo.push_back(w.child[i]);
            }
            ASSERT_GE(used, 2);
        }
        for (std::size_t w = 0; w < wide.size(); ++w) ASSERT_EQ(reached[w], 1) << "wide node " << w;
        for (std::size_t t = 0; t < seen.size(); ++t) ASSERT_EQ(seen[t], 1) << "triangle " << t;
    }
    static std::vector<std::pair<int, float>> planes(const Bvh& bvh)
    {
        std::vector<std::pair<int, float>> p;
        for (const BvhNode& n : bvh.nodes())
            for (int k = 0; k < 3; ++k) {
                p.emplace_back(k, n.bounds.lower[k]);
                p.emplace_back(k, n.bounds.upper[k]);
            }
        return p;
    }
    static BvhConfig stable_planes_config() { return {}; }
    static std::uint32_t depth(const Bvh& bvh) { return bvh.depth(); }
    static std::uint32_t depth_limit(std::size_t) { return BvhConfig{}.max_depth; }
};

INSTANTIATE_TYPED_TEST_SUITE_P(Bvh, BaselineOracle, ::testing::Types<Bvh>);

namespace {

// Copies of one triangle cannot be told apart by their centroids: the builder halves them
// until leaves are small, so the depth is logarithmic, not linear.
TEST(BvhBuild, IdenticalTrianglesGiveABalancedTree)
{
    Mesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.triangles.assign(1000, Triangle{{0, 1, 2}});
    const Bvh bvh = build_checked_baseline<Bvh>(mesh);
    EXPECT_LE(bvh.depth(), 8u);  // ceil(log2(1000 / 8)) + 1
    for (const BvhNode& n : bvh.nodes())
        if (n.is_leaf()) {
            EXPECT_LE(n.ref_count(), BvhConfig{}.max_leaf_size);
        }
}

TEST(BvhBuild, FirstSplitSeparatesDistantClusters)
{
    Mesh mesh = random_triangles(3, 500, Aabb{{0, 0, 0}, {1, 1, 1}}, 0.1f);
    append(mesh, random_triangles(4, 700, Aabb{{0, 0, 9}, {1, 1, 10}}, 0.1f));
    const Bvh bvh = build_checked_baseline<Bvh>(mesh);
    const BvhNode root = bvh.nodes()[0];
    ASSERT_FALSE(root.is_leaf());
    EXPECT_EQ(root.axis(), 2);
    const BvhNode low = bvh.nodes()[root.first_child()];
    const BvhNode high = bvh.nodes()[root.first_child() + 1];
    EXPECT_LT(low.bounds.upper.z, 1.2f);
    EXPECT_GT(high.bounds.lower.z, 8.8f);
}

TEST(BvhBuild, LeavesRespectTheSizeLimits)
{
    const Mesh mesh = random_triangles(5, 5000, baseline_scene_box, 0.5f);
    BvhConfig config;
    config.leaf_size = 2;
    config.max_leaf_size = 4;
    const Bvh bvh = build_checked_baseline<Bvh>(mesh, config);
    for (const BvhNode& n : bvh.nodes())
        if (n.is_leaf()) {
            EXPECT_LE(n.ref_count(), 4u);
        }
    // What a traversal reads: the wide nodes, the references and the root's box.
    EXPECT_EQ(bvh.memory_bytes(),
              4u + 32u + bvh.wide_nodes().size() * (32u * BvhWideNode::width) + 5000u * 4u);
    EXPECT_EQ(bvh.node_count(), 2 * bvh.leaf_count() - 1);
}

TEST(BvhBuild, MaxDepthBoundsTheTree)
{
    const Mesh mesh = random_triangles(8, 3000, baseline_scene_box, 0.5f);
    BvhConfig config;
    config.max_depth = 3;
    const Bvh bvh = Bvh::build(mesh.view(), config);
    EXPECT_LE(bvh.depth(), 3u);
    EXPECT_LE(bvh.leaf_count(), 8u);
    expect_baseline_agrees(bvh, mesh, rays_at_triangles(9, 1000, baseline_scene_box, mesh.view()), 800);
}

TEST(BvhConfig, BadValuesNameTheField)
{
    EXPECT_EQ(config_error(BvhConfig{}), "");
    BvhConfig c;
    c.bins = 1;
    EXPECT_NE(config_error(c).find("BvhConfig.bins = 1"), std::string::npos);
    c = {};
    c.bins = 65;
    EXPECT_NE(config_error(c).find("bins"), std::string::npos);
    c = {};
    c.leaf_size = 9;  // above max_leaf_size
    EXPECT_NE(config_error(c).find("leaf_size"), std::string::npos);
    c = {};
    c.traversal_cost = std::nan("");
    EXPECT_NE(config_error(c).find("traversal_cost"), std::string::npos);
    c = {};
    c.max_depth = 0;
    EXPECT_NE(config_error(c).find("max_depth"), std::string::npos);
    c = {};
    c.threads = 1025;
    EXPECT_NE(config_error(c).find("threads"), std::string::npos);
    const Mesh mesh = random_triangles(1, 10, baseline_scene_box, 1.0f);
    EXPECT_THROW((void)Bvh::build(mesh.view(), c), ConfigError);
}

TEST(BvhBuild, BadMeshIsAnInputError)
{
    Mesh mesh = random_triangles(1, 10, baseline_scene_box, 1.0f);
    mesh.vertices[0].z = std::numeric_limits<float>::infinity();
    EXPECT_THROW((void)Bvh::build(mesh.view()), InputError);
}

// Moves every vertex of `mesh` smoothly: a twist about the y axis plus a wave, as a
// deforming scene would (and far enough that the refitted boxes differ from the built ones).
void deform(Mesh& mesh, float amount)
{
    for (Vec3f& v : mesh.vertices) {
        const float angle = amount * (v.y - 5.0f) * 0.15f;
        const float x = v.x - 5.0f, z = v.z - 5.0f;
        v = Vec3f{5.0f + x * std::cos(angle) - z * std::sin(angle),
                  v.y + amount * std::sin(v.x * 0.7f),
                  5.0f + x * std::sin(angle) + z * std::cos(angle)};
    }
}

TEST(BvhRefit, RefittedBvhAnswersLikeBruteForceOnTheMovedMesh)
{
    Mesh mesh = random_triangles(21, 3000, baseline_scene_box, 0.8f);
    mesh.vertices.push_back(Vec3f{40.0f, 40.0f, 40.0f});  // unreferenced: never in a box
    Bvh bvh = Bvh::build(mesh.view());
    const Bvh built = bvh;
    // Nothing moved: the refit computes the very boxes the build did.
    bvh.refit(mesh.view(), 1);
    EXPECT_EQ(bvh, built);
    for (const float amount : {0.5f, 1.5f, -3.0f}) {
        deform(mesh, amount);
        bvh.refit(mesh.view(), 1);
        ASSERT_NO_FATAL_FAILURE(BaselineTraits<Bvh>::check(bvh, mesh.view()));
        // Same tree, same triangle order: only the boxes moved.
        ASSERT_EQ(bvh.node_count(), built.node_count());
        EXPECT_TRUE(std::equal(bvh.refs().begin(), bvh.refs().end(), built.refs().begin()));
        const Aabb box = bounds(mesh.view());
        auto rays = random_rays(22, 2000, box);
        const auto at = rays_at_triangles(23, 2000, box, mesh.view());
        rays.insert(rays.end(), at.begin(), at.end());
        const OracleReport report = compare_structure_with_brute_force(bvh, mesh.view(), rays);
        EXPECT_EQ(report.closest_disagreements, 0u) << report.first_failure;
        EXPECT_EQ(report.any_hit_disagreements, 0u) << report.first_failure;
        EXPECT_GT(report.hits, 1000u);
    }
    // The refit with all threads gives the same boxes as with one.
    Bvh again = built;
    again.refit(mesh.view(), 0);
    EXPECT_EQ(again, bvh);
}

TEST(BvhRefit, RefusesAnotherMeshOrABadOne)
{
    Mesh mesh = random_triangles(24, 100, baseline_scene_box, 1.0f);
    Bvh bvh = Bvh::build(mesh.view());
    Mesh fewer = mesh;
    fewer.triangles.pop_back();
    const Bvh before = bvh;
    EXPECT_THROW(bvh.refit(fewer.view()), InputError);
    mesh.vertices[3].x = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(bvh.refit(mesh.view()), InputError);
    EXPECT_EQ(bvh, before);  // a refused refit leaves the BVH as it was
}

}  // namespace
}  // namespace sg::test
