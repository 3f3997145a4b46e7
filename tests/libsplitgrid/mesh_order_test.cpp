// morton_order, checked against a Z-order worked out cell by cell, and reorder_triangles,
// checked against the input mesh: the same triangles with the same corners, under new ids.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
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

TEST(MeshOrder, FollowsTheZOrderOfEveryBit)
{
    // A box from 0 to 2^21 on every axis, so that a centroid's step on an axis is its integer
    // part: random triangles centred at integer + 1/2 (corners multiples of 1/4, exact in
    // float), one triangle at the box's lower corner and one in its upper z plane (a centroid
    // on the box's edge: the last step, not one past it). Their order must be that of the
    // steps' bits interleaved one by one (x to bit 3b, y to 3b + 1, z to 3b + 2), ties by id.
    constexpr std::uint32_t top = 1u << 21;
    const auto f = [](std::uint64_t v) { return static_cast<float>(v); };
    std::vector<std::array<std::uint64_t, 3>> steps;
    Mesh mesh;
    const auto add = [&](std::array<Vec3f, 3> corners, std::array<std::uint64_t, 3> step) {
        const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
        for (const Vec3f& c : corners) mesh.vertices.push_back(c);
        mesh.triangles.push_back(Triangle{{first, first + 1, first + 2}});
        steps.push_back(step);
    };
    add({Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}}, {0, 0, 0});
    add({Vec3f{f(top), f(top), f(top)}, Vec3f{f(top - 1), f(top), f(top)},
         Vec3f{f(top), f(top - 1), f(top)}},
        {top - 1, top - 1, top - 1});
    const auto add_centred = [&](const std::array<std::uint64_t, 3>& q) {
        const Vec3f c{f(q[0]) + 0.5f, f(q[1]) + 0.5f, f(q[2]) + 0.5f};
        // Corners c + a, c + b, c - a - b: the centroid is c.
        add({Vec3f{c.x - 0.25f, c.y - 0.25f, c.z}, Vec3f{c.x + 0.25f, c.y - 0.25f, c.z + 0.25f},
             Vec3f{c.x, c.y + 0.5f, c.z - 0.25f}},
            q);
    };
    std::mt19937 rng(5);
    std::uniform_int_distribution<std::uint64_t> cell(0, top - 1);
    for (int t = 0; t < 2000; ++t)
        add_centred({cell(rng), cell(rng), t % 7 == 0 ? 5 : cell(rng)});
    // For every bit of every axis, two triangles whose steps differ in that bit alone, the
    // one with the bit set first: only that bit orders them.
    for (unsigned a = 0; a < 3; ++a)
        for (unsigned b = 0; b < 21; ++b) {
            std::array<std::uint64_t, 3> q = {cell(rng), cell(rng), cell(rng)};
            q[a] |= std::uint64_t{1} << b;
            add_centred(q);
            q[a] &= ~(std::uint64_t{1} << b);
            add_centred(q);
        }
    const auto key = [](const std::array<std::uint64_t, 3>& q) {
        std::uint64_t k = 0;
        for (unsigned b = 0; b < 21; ++b)
            for (unsigned a = 0; a < 3; ++a) k |= ((q[a] >> b) & 1u) << (3 * b + a);
        return k;
    };
    std::vector<std::uint32_t> expected(steps.size());
    for (std::uint32_t t = 0; t < expected.size(); ++t) expected[t] = t;
    std::stable_sort(expected.begin(), expected.end(), [&](std::uint32_t a, std::uint32_t b) {
        return key(steps[a]) < key(steps[b]);
    });
    EXPECT_EQ(morton_order(mesh.view()), expected);
}

TEST(MeshOrder, EqualCodesKeepTheInputsOrder)
{
    // Every triangle in the plane z = 1 (an axis of zero extent) and centred on one point:
    // one code for all, so the order is the input's.
    Mesh mesh;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.5f, 2.0f);
    for (std::uint32_t t = 0; t < 500; ++t) {
        const float a = u(rng);
        const float b = u(rng);
        mesh.vertices.push_back({-a, -b, 1.0f});
        mesh.vertices.push_back({a, -b, 1.0f});
        mesh.vertices.push_back({0.0f, 2.0f * b, 1.0f});
        mesh.triangles.push_back(Triangle{{3 * t, 3 * t + 1, 3 * t + 2}});
    }
    const std::vector<std::uint32_t> order = morton_order(mesh.view());
    ASSERT_EQ(order.size(), mesh.triangles.size());
    for (std::uint32_t t = 0; t < order.size(); ++t) EXPECT_EQ(order[t], t);
}

TEST(MeshOrder, ExtractedTrianglesKeepTheirCornersAndOnlyTheirVertices)
{
    Mesh mesh;
    for (std::uint32_t k = 0; k < 10; ++k)
        mesh.vertices.push_back({static_cast<float>(k), static_cast<float>(k * k), 1.0f});
    mesh.triangles = {Triangle{{0, 1, 2}}, Triangle{{2, 3, 4}}, Triangle{{5, 6, 7}},
                      Triangle{{7, 8, 9}}};
    const std::vector<std::uint32_t> ids = {3, 1};
    const Mesh part = extract_triangles(mesh.view(), ids);
    ASSERT_EQ(part.triangles.size(), 2u);
    EXPECT_EQ(part.vertices.size(), 6u);
    for (std::size_t t = 0; t < ids.size(); ++t)
        for (int k = 0; k < 3; ++k)
            EXPECT_TRUE(same_bits(part.view().vertex(static_cast<std::uint32_t>(t), k),
                                  mesh.view().vertex(ids[t], k)));
    EXPECT_EQ(part.triangles[0], (Triangle{{0, 1, 2}}));
    EXPECT_THROW((void)extract_triangles(mesh.view(), std::vector<std::uint32_t>{4}),
                 ConfigError);
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

TEST(MeshOrder, PointsFollowTheZOrderOfTheBoxAndOutsidersClampToIt)
{
    // The centres of a 4 x 4 x 4 grid of cells over the box [0, 4]^3, shuffled: the order is
    // the cells' Z-order (bit b of x, y, z to bits 3b, 3b + 1, 3b + 2). A point below the box
    // and a NaN point come first (clamped to the lower corner), one above it last.
    std::vector<Vec3f> points;
    for (std::uint32_t z = 0; z < 4; ++z)
        for (std::uint32_t y = 0; y < 4; ++y)
            for (std::uint32_t x = 0; x < 4; ++x)
                points.push_back({float(x) + 0.5f, float(y) + 0.5f, float(z) + 0.5f});
    std::shuffle(points.begin(), points.end(), std::mt19937(9));
    points.push_back({-5.0f, -1.0f, -2.0f});
    points.push_back({std::nanf(""), std::nanf(""), std::nanf("")});
    points.push_back({9.0f, 9.0f, 9.0f});
    const std::vector<std::uint32_t> order = morton_order(points, Aabb{{0, 0, 0}, {4, 4, 4}});
    ASSERT_EQ(order.size(), points.size());
    EXPECT_EQ(order[0], 64u);  // equal codes keep their order: the outsider before the NaN
    EXPECT_EQ(order[1], 65u);
    EXPECT_EQ(order.back(), 66u);
    auto key = [](Vec3f p) {
        std::uint32_t k = 0;
        for (int b = 0; b < 2; ++b)
            for (int a = 0; a < 3; ++a)
                k |= ((static_cast<std::uint32_t>(p[a]) >> b) & 1u) << (3 * b + a);
        return k;
    };
    for (std::size_t i = 3; i + 1 < order.size(); ++i)
        EXPECT_LT(key(points[order[i - 1]]), key(points[order[i]])) << i;
}

}  // namespace
}  // namespace sg
