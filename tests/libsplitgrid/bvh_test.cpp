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

// Calls f(node, slot) for every used slot of every wide node.
template <class F>
void for_each_slot(const Bvh& bvh, const F& f)
{
    for (const BvhWideNode& node : bvh.wide_nodes())
        for (int i = 0; i < BvhWideNode::width; ++i)
            if (node.is_used(i)) f(node, i);
}

Aabb slot_box(const BvhWideNode& node, int i)
{
    return Aabb{{node.lower[0][i], node.lower[1][i], node.lower[2][i]},
                {node.upper[0][i], node.upper[1][i], node.upper[2][i]}};
}

template <>
struct BaselineTraits<Bvh> {
    // The tree against the mesh alone: from the root, every wide node is reached once and no
    // deeper than the build's depth, every triangle once through a leaf slot whose box holds
    // its padded box and is no more than one pad wider, every inner slot's box is the union
    // of its node's slot boxes exactly (as is the BVH's box of the root's), used slots come
    // first and unused ones are empty.
    static void check(const Bvh& bvh, const MeshView& mesh)
    {
        ASSERT_EQ(bvh.triangle_count(), mesh.triangle_count());
        const auto wide = bvh.wide_nodes();
        if (mesh.triangle_count() == 0) {
            ASSERT_TRUE(wide.empty());
            ASSERT_EQ(bvh.node_count(), 0u);
            return;
        }
        ASSERT_FALSE(wide.empty());
        ASSERT_EQ(bvh.refs().size(), mesh.triangle_count());
        const double pad = boundary_pad(bounds(mesh));
        auto union_of_slots = [](const BvhWideNode& w) {
            Aabb box;
            for (int j = 0; j < BvhWideNode::width; ++j)
                if (w.is_used(j)) box.extend(slot_box(w, j));
            return box;
        };
        ASSERT_EQ(bvh.box(), union_of_slots(wide[0]));
        std::vector<int> reached(wide.size(), 0);
        std::vector<std::uint32_t> depth(wide.size(), 0);
        std::vector<int> seen(mesh.triangle_count(), 0);
        std::size_t leaves = 0;
        std::vector<std::uint32_t> todo{0};
        reached[0] = 1;
        while (!todo.empty()) {
            const std::uint32_t index = todo.back();
            todo.pop_back();
            const BvhWideNode& w = wide[index];
            ASSERT_LE(depth[index], bvh.depth());
            int used = 0;
            for (int i = 0; i < BvhWideNode::width; ++i) {
                if (!w.is_used(i)) {
                    EXPECT_EQ(w.count[i], 0u);
                    for (int k = 0; k < 3; ++k) EXPECT_GT(w.lower[k][i], w.upper[k][i]);
                    continue;
                }
                ASSERT_EQ(used++, i) << "a used slot after an unused one";
                if (w.is_leaf(i)) {
                    ++leaves;
                    ASSERT_LE(std::size_t{w.child[i]} + w.count[i], bvh.refs().size());
                    Aabb tight;
                    for (std::uint32_t r = w.child[i]; r < w.child[i] + w.count[i]; ++r) {
                        const std::uint32_t t = bvh.refs()[r];
                        ASSERT_LT(t, mesh.triangle_count());
                        ++seen[t];
                        for (int corner = 0; corner < 3; ++corner) {
                            tight.extend(mesh.vertex(t, corner));
                            for (int k = 0; k < 3; ++k) {
                                const double v = mesh.vertex(t, corner)[k];
                                ASSERT_LE(double(w.lower[k][i]), v - pad) << "triangle " << t;
                                ASSERT_GE(double(w.upper[k][i]), v + pad) << "triangle " << t;
                            }
                        }
                    }
                    for (int k = 0; k < 3; ++k) {
                        ASSERT_GE(double(w.lower[k][i]), double(tight.lower[k]) - 2.0 * pad);
                        ASSERT_LE(double(w.upper[k][i]), double(tight.upper[k]) + 2.0 * pad);
                    }
                    continue;
                }
                ASSERT_LT(w.child[i], wide.size());
                ASSERT_EQ(reached[w.child[i]]++, 0) << "wide node " << w.child[i];
                ASSERT_GT(w.child[i], index) << "a child before its parent";
                ASSERT_EQ(slot_box(w, i), union_of_slots(wide[w.child[i]]));
                depth[w.child[i]] = depth[index] + 1;
                todo.push_back(w.child[i]);
            }
            // Two slots or more, but for a root that is a leaf.
            ASSERT_TRUE(used >= 2 || (index == 0 && used == 1 && w.is_leaf(0)));
        }
        for (std::size_t w = 0; w < wide.size(); ++w) ASSERT_EQ(reached[w], 1) << "wide node " << w;
        for (std::size_t t = 0; t < seen.size(); ++t) ASSERT_EQ(seen[t], 1) << "triangle " << t;
        ASSERT_EQ(leaves, bvh.leaf_count());
    }
    static std::vector<std::pair<int, float>> planes(const Bvh& bvh)
    {
        std::vector<std::pair<int, float>> p;
        for_each_slot(bvh, [&](const BvhWideNode& node, int i) {
            for (int k = 0; k < 3; ++k) {
                p.emplace_back(k, node.lower[k][i]);
                p.emplace_back(k, node.upper[k][i]);
            }
        });
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
    for_each_slot(bvh, [](const BvhWideNode& node, int i) {
        EXPECT_LE(node.count[i], BvhConfig{}.max_leaf_size);
    });
}

TEST(BvhBuild, FirstSplitSeparatesDistantClusters)
{
    Mesh mesh = random_triangles(3, 500, Aabb{{0, 0, 0}, {1, 1, 1}}, 0.1f);
    append(mesh, random_triangles(4, 700, Aabb{{0, 0, 9}, {1, 1, 10}}, 0.1f));
    const Bvh bvh = build_checked_baseline<Bvh>(mesh);
    // The first split separates the clusters, so every child of the root lies in one of them.
    int low = 0, high = 0;
    for (int i = 0; i < BvhWideNode::width; ++i) {
        if (!bvh.wide_nodes()[0].is_used(i)) continue;
        const Aabb box = slot_box(bvh.wide_nodes()[0], i);
        low += box.upper.z < 1.2f ? 1 : 0;
        high += box.lower.z > 8.8f ? 1 : 0;
        EXPECT_TRUE(box.upper.z < 1.2f || box.lower.z > 8.8f) << "slot " << i;
    }
    EXPECT_GT(low, 0);
    EXPECT_GT(high, 0);
}

TEST(BvhBuild, LeavesRespectTheSizeLimits)
{
    const Mesh mesh = random_triangles(5, 5000, baseline_scene_box, 0.5f);
    BvhConfig config;
    config.leaf_size = 2;
    config.max_leaf_size = 4;
    const Bvh bvh = build_checked_baseline<Bvh>(mesh, config);
    for_each_slot(bvh, [](const BvhWideNode& node, int i) { EXPECT_LE(node.count[i], 4u); });
    // Three counts and the root's box, the wide nodes, the references.
    EXPECT_EQ(bvh.memory_bytes(),
              12u + 24u + bvh.wide_nodes().size() * (32u * BvhWideNode::width) + 5000u * 4u);
    // A wide node per binary inner node at most, and at most width slots each.
    EXPECT_LE(bvh.node_count(), bvh.leaf_count() - 1);
    EXPECT_LE(bvh.leaf_count(), bvh.node_count() * (BvhWideNode::width - 1) + 1);
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
