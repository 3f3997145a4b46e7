// make_arena_scene: the copies are rigid, scaled copies of the model standing on the floor,
// apart from each other, and the scene depends only on its inputs.

#include "splitgrid/arena_scene.hpp"

#include <algorithm>
#include <cmath>

#include "splitgrid/error.hpp"
#include "support/random_scene.hpp"

#include <gtest/gtest.h>

namespace sg::test {
namespace {

double edge(const Mesh& m, std::size_t tri, int a, int b)
{
    const Vec3f p = m.vertices[m.triangles[tri].v[static_cast<std::size_t>(a)]];
    const Vec3f q = m.vertices[m.triangles[tri].v[static_cast<std::size_t>(b)]];
    return length(p - q);
}

TEST(ArenaScene, CopiesAreScaledRigidCopiesOnTheFloor)
{
    const Mesh model = uv_sphere({3.0f, 5.0f, -2.0f}, 1.0f, 8, 12);
    ArenaConfig config;
    config.copies = 10;
    const Mesh scene = make_arena_scene(model.view(), config);
    const std::size_t n = model.triangles.size();
    ASSERT_EQ(scene.triangles.size(), 10 * n + 2);

    float floor_y = scene.vertices[scene.triangles.back().v[0]].y;
    EXPECT_EQ(floor_y, 0.0f);
    std::vector<Aabb> boxes;
    for (std::size_t copy = 0; copy < 10; ++copy) {
        // One scale factor per copy, the same for every edge of every triangle.
        const double scale = edge(scene, copy * n, 0, 1) / edge(model, 0, 0, 1);
        EXPECT_GE(scale, 0.75 - 1e-4);
        EXPECT_LE(scale, 1.25 + 1e-4);
        Aabb box;
        for (std::size_t t = 0; t < n; ++t) {
            for (int e = 0; e < 3; ++e)
                EXPECT_NEAR(edge(scene, copy * n + t, e, (e + 1) % 3),
                            scale * edge(model, t, e, (e + 1) % 3), 1e-4);
            for (std::uint32_t v : scene.triangles[copy * n + t].v) box.extend(scene.vertices[v]);
        }
        EXPECT_NEAR(box.lower.y, 0.0f, 1e-4) << "copy " << copy << " stands on the floor";
        boxes.push_back(box);
    }
    for (std::size_t a = 0; a < boxes.size(); ++a)
        for (std::size_t b = a + 1; b < boxes.size(); ++b) {
            const bool apart = boxes[a].upper.x < boxes[b].lower.x ||
                               boxes[b].upper.x < boxes[a].lower.x ||
                               boxes[a].upper.z < boxes[b].lower.z ||
                               boxes[b].upper.z < boxes[a].lower.z;
            EXPECT_TRUE(apart) << "copies " << a << " and " << b << " overlap";
        }
}

TEST(ArenaScene, DependsOnlyOnItsInputs)
{
    const Mesh model = uv_sphere({0.0f, 0.0f, 0.0f}, 1.0f, 6, 8);
    ArenaConfig config;
    config.copies = 5;
    EXPECT_EQ(make_arena_scene(model.view(), config), make_arena_scene(model.view(), config));
    ArenaConfig other = config;
    other.seed = 2;
    EXPECT_NE(make_arena_scene(model.view(), config), make_arena_scene(model.view(), other));
    other = config;
    other.floor = false;
    EXPECT_EQ(make_arena_scene(model.view(), other).triangles.size(), 5 * model.triangles.size());
}

TEST(ArenaScene, RefusesBadConfigAndEmptyModel)
{
    const Mesh model = uv_sphere({0.0f, 0.0f, 0.0f}, 1.0f, 6, 8);
    ArenaConfig config;
    config.copies = 0;
    EXPECT_THROW((void)make_arena_scene(model.view(), config), ConfigError);
    config.copies = 1;
    config.spacing = 0.1;
    EXPECT_THROW((void)make_arena_scene(model.view(), config), ConfigError);
    EXPECT_THROW((void)make_arena_scene(Mesh{}.view(), ArenaConfig{}), InputError);
    config.spacing = 1.5;
    config.copies = 1u << 24;
    const Mesh big = uv_sphere({0.0f, 0.0f, 0.0f}, 1.0f, 9, 16);
    ASSERT_EQ(big.triangles.size(), 256u);
    EXPECT_THROW((void)make_arena_scene(big.view(), config), InputError) << "2^32 + 2 triangles";
}

}  // namespace
}  // namespace sg::test
