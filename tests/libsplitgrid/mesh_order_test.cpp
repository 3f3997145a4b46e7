// morton_order, checked against a Z-order worked out cell by cell, and reorder_triangles,
// checked against the input mesh: the same triangles with the same corners, under new ids.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include "splitgrid/error.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/mesh_order.hpp"

namespace sg {
namespace {

bool same_bits(Vec3f a, Vec3f b)
{
    return std::bit_cast<std::uint32_t>(a.x) == std::bit_cast<std::uint32_t>(b.x) &&
           std::bit_cast<std::uint32_t>(a.y) == std::bit_cast<std::uint32_t>(b.y) &&
           std::bit_cast<std::uint32_t>(a.z) == std::bit_cast<std::uint32_t>(b.z);
}

/// Every triangle of `after` is triangle original[i] of `before`, corner for corner, and
/// `original` names each triangle of `before` once.
void expect_same_triangles(const Mesh& before, const Mesh& after,
                           const std::vector<std::uint32_t>& original)
{
    ASSERT_EQ(after.triangles.size(), before.triangles.size());
    ASSERT_EQ(original.size(), before.triangles.size());
    std::vector<std::uint32_t> sorted = original;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i);
    for (std::size_t t = 0; t < after.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k)
            EXPECT_TRUE(same_bits(after.view().vertex(static_cast<std::uint32_t>(t), k),
                                  before.view().vertex(original[t], k)))
                << "triangle " << t << " corner " << k;
}

TEST(MeshOrder, FollowsTheZOrderOfACellGrid)
{
    // One small triangle centred in each cell of a 4 x 4 x 4 grid, listed in a shuffled order.
    // The mesh's box runs from 0.4 to 3.6 (3.7 in y), so cell i of an axis is the i-th quarter
    // of the box on that axis: the triangle's two highest bits per axis are its cell's.
    struct Cell {
        std::uint32_t x, y, z;
    };
    std::vector<Cell> cells;
    for (std::uint32_t z = 0; z < 4; ++z)
        for (std::uint32_t y = 0; y < 4; ++y)
            for (std::uint32_t x = 0; x < 4; ++x) cells.push_back({x, y, z});
    std::shuffle(cells.begin(), cells.end(), std::mt19937(7));
    Mesh mesh;
    for (const Cell& c : cells) {
        const Vec3f centre{static_cast<float>(c.x) + 0.5f, static_cast<float>(c.y) + 0.5f,
                           static_cast<float>(c.z) + 0.5f};
        const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
        // Corners centre + a, centre + b, centre - a - b: the centroid is the centre.
        mesh.vertices.push_back({centre.x - 0.1f, centre.y - 0.1f, centre.z - 0.1f});
        mesh.vertices.push_back({centre.x + 0.1f, centre.y - 0.1f, centre.z + 0.1f});
        mesh.vertices.push_back({centre.x, centre.y + 0.2f, centre.z});
        mesh.triangles.push_back(Triangle{{first, first + 1, first + 2}});
    }
    const Mesh before = mesh;
    const std::vector<std::uint32_t> original = morton_order(mesh.view());
    reorder_triangles(mesh, original);
    expect_same_triangles(before, mesh, original);
    // The Z-order of the 64 cells: bit b of x, y and z to bits 3b, 3b + 1 and 3b + 2.
    const auto z_order = [](const Cell& c) {
        std::uint32_t key = 0;
        for (std::uint32_t b = 0; b < 2; ++b)
            key |= (((c.x >> b) & 1u) << (3 * b)) | (((c.y >> b) & 1u) << (3 * b + 1)) |
                   (((c.z >> b) & 1u) << (3 * b + 2));
        return key;
    };
    for (std::size_t t = 0; t < cells.size(); ++t)
        EXPECT_EQ(z_order(cells[original[t]]), t) << "triangle " << t;
}

TEST(MeshOrder, KeepsEveryTriangleAndNumbersVerticesByFirstUse)
{
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    Mesh mesh;
    for (int k = 0; k < 3000; ++k) mesh.vertices.push_back({u(rng), u(rng), u(rng)});
    std::uniform_int_distribution<std::uint32_t> pick(0, 1999);  // vertices 2000.. unused
    for (int t = 0; t < 5000; ++t)
        mesh.triangles.push_back(Triangle{{pick(rng), pick(rng), pick(rng)}});
    // Two copies of one triangle: equal codes keep the input's order.
    mesh.triangles[4000] = mesh.triangles[100];
    const Mesh before = mesh;
    const std::vector<std::uint32_t> original = morton_order(mesh.view());
    reorder_triangles(mesh, original);
    expect_same_triangles(before, mesh, original);
    const auto first_copy = std::find(original.begin(), original.end(), 100u);
    const auto second_copy = std::find(original.begin(), original.end(), 4000u);
    EXPECT_LT(first_copy, second_copy);

    std::set<std::uint32_t> used;
    for (const Triangle& t : before.triangles) used.insert(t.v.begin(), t.v.end());
    EXPECT_EQ(mesh.vertices.size(), used.size());
    // Vertex k is first used before vertex k + 1, and every vertex is used.
    std::uint32_t next = 0;
    for (const Triangle& t : mesh.triangles)
        for (const std::uint32_t v : t.v) {
            ASSERT_LE(v, next);
            if (v == next) ++next;
        }
    EXPECT_EQ(next, mesh.vertices.size());
}

TEST(MeshOrder, RefusesABadMeshOrOrderAndLeavesTheMeshUnchanged)
{
    Mesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    mesh.triangles = {Triangle{{0, 1, 2}}, Triangle{{2, 1, 3}}};
    const Mesh good = mesh;
    for (const std::vector<std::uint32_t>& order :
         {std::vector<std::uint32_t>{0}, {0, 0}, {1, 2}, {0, 1, 1}}) {
        EXPECT_THROW(reorder_triangles(mesh, order), ConfigError);
        EXPECT_EQ(mesh, good);
    }
    mesh.triangles[1].v[2] = 4;  // past the vertex array
    const Mesh bad = mesh;
    EXPECT_THROW((void)morton_order(mesh.view()), InputError);
    EXPECT_THROW(reorder_triangles(mesh, std::vector<std::uint32_t>{1, 0}), InputError);
    EXPECT_EQ(mesh, bad);

    Mesh empty;
    EXPECT_TRUE(morton_order(empty.view()).empty());
    reorder_triangles(empty, {});
    EXPECT_TRUE(empty.vertices.empty());
}

}  // namespace
}  // namespace sg
