#include "splitgrid/leaf_words.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/validate.hpp"
#include "support/leaf_triangles.hpp"
#include "support/oracle.hpp"
#include "support/random_scene.hpp"

namespace sg {
namespace {

using Words = std::vector<std::uint16_t>;
using Ids = std::vector<std::uint32_t>;

Words encode(const Ids& ids)
{
    Words words;
    EXPECT_EQ(append_leaf(words, ids), 0u);
    EXPECT_EQ(words.size(), leaf_word_count(ids));
    return words;
}

TEST(LeafWords, EncodesTheDocumentedWords)
{
    // docs/FORMAT.md, TREF: a head pair (id, bit 30 wide, bit 31 last), then one word per
    // reference (offset, bit 15 last) or, for a wide leaf, one pair (id, bit 31 last).
    EXPECT_EQ(encode({7}), (Words{7, 0x8000}));
    EXPECT_EQ(encode({5, 6, 40}), (Words{5, 0, 1, 0x8000 | 35}));
    EXPECT_EQ(encode({70000, 70001}), (Words{70000 - 65536, 1, 0x8000 | 1}));
    // The span decides: below 2^15 narrow, from 2^15 on wide.
    EXPECT_EQ(encode({0, 32767}), (Words{0, 0, 0x8000 | 32767}));
    EXPECT_EQ(encode({0, 32768}), (Words{0, 0x4000, 32768, 0x8000}));
    EXPECT_EQ(encode({1, 2, 100000}),
              (Words{1, 0x4000, 2, 0, 100000 - 65536, 0x8000 | 1}));
    // The largest id, alone and in a wide leaf.
    EXPECT_EQ(encode({max_referenced_triangle}), (Words{0xFFFF, 0x8000 | 0x3FFF}));
    EXPECT_EQ(encode({0, max_referenced_triangle}), (Words{0, 0x4000, 0xFFFF, 0x8000 | 0x3FFF}));
}

TEST(LeafWords, AppendsAfterWhatIsThere)
{
    Words words{1, 2, 3};
    EXPECT_EQ(append_leaf(words, Ids{9, 10}), 3u);
    EXPECT_EQ(words, (Words{1, 2, 3, 9, 0, 0x8000 | 1}));
}

TEST(LeafWords, RefusesWhatItCannotEncodeAndLeavesTheWordsAlone)
{
    Words words{4, 0x8000};
    const Words before = words;
    EXPECT_THROW((void)append_leaf(words, Ids{}), ConfigError);
    EXPECT_THROW((void)append_leaf(words, Ids{3, 2}), ConfigError);
    EXPECT_THROW((void)append_leaf(words, Ids{3, 3}), ConfigError);
    EXPECT_THROW((void)append_leaf(words, Ids{max_referenced_triangle + 1}), ConfigError);
    EXPECT_THROW((void)append_leaf(words, Ids{1, max_referenced_triangle + 1}), ConfigError);
    EXPECT_EQ(words, before);
}

TEST(LeafWords, ReadsBackWhatItWroteAsAnIndependentReaderDoes)
{
    // Random leaves of random sizes and spans, back to back, read by read_leaf and by the
    // tests' own reader of the documented layout.
    std::mt19937 rng(11);
    std::vector<Ids> leaves;
    SplitGrid grid;
    std::vector<std::size_t> firsts;
    for (int l = 0; l < 3000; ++l) {
        const std::uint32_t span = std::array<std::uint32_t, 4>{40, 32768, 40000, 1u << 29}[rng() % 4];
        std::set<std::uint32_t> set;
        const std::size_t n = 1 + rng() % 40;
        const std::uint32_t base = static_cast<std::uint32_t>(rng() % ((1u << 30) - span));
        set.insert(base);
        while (set.size() < n && set.size() < span) set.insert(base + static_cast<std::uint32_t>(rng() % span));
        leaves.emplace_back(set.begin(), set.end());
        firsts.push_back(append_leaf(grid.leaf_words, leaves.back()));
    }
    std::size_t wide = 0, at = 0, total = 0;
    for (std::size_t l = 0; l < leaves.size(); ++l) {
        ASSERT_EQ(firsts[l], at);
        Ids read;
        const std::size_t end = read_leaf(grid.leaf_words, at, [&](std::uint32_t id) { read.push_back(id); });
        std::size_t independent_end = 0;
        EXPECT_EQ(read, leaves[l]);
        EXPECT_EQ(test::leaf_at(grid, at, &independent_end), leaves[l]);
        EXPECT_EQ(end, independent_end);
        EXPECT_EQ(leaf_ids(grid.leaf_words, at), leaves[l]);
        wide += leaves[l].back() - leaves[l].front() >= 32768 ? 1 : 0;
        total += leaves[l].size();
        at = end;
    }
    EXPECT_EQ(at, grid.leaf_words.size());
    EXPECT_EQ(count_references(grid.leaf_words), total);
    EXPECT_GT(wide, 500u);
    EXPECT_LT(wide, 2500u);
}

TEST(LeafWords, RefusesLeavesThatAreNotWellFormed)
{
    const auto end_of = [](const Words& words) {
        return read_leaf(words, 0, [](std::uint32_t) {});
    };
    // Every prefix of a narrow and of a wide leaf runs off the end.
    for (const Ids& ids : {Ids{5, 6, 40}, Ids{1, 2, 100000}}) {
        const Words words = encode(ids);
        EXPECT_EQ(end_of(words), words.size());
        for (std::size_t n = 0; n < words.size(); ++n)
            EXPECT_EQ(end_of(Words(words.begin(), words.begin() + static_cast<std::ptrdiff_t>(n))), 0u) << n;
    }
    EXPECT_EQ(end_of(Words{0, 0x8000 | 0x4000}), 0u) << "a wide head marked last";
    EXPECT_EQ(end_of(Words{0, 0x4000, 5, 0x8000 | 0x4000}), 0u) << "a wide reference with bit 30";
    EXPECT_EQ(read_leaf(Words{0, 0x8000}, 2, [](std::uint32_t) {}), 0u) << "past the end";
    // count_references counts the leaves before the first that is not well formed.
    EXPECT_EQ(count_references(Words{1, 0x8000, 2, 0, 5, 0x8000 | 6, 0, 0x4000}), 4u);
}

TEST(TraverseLeafWords, WideAndNarrowLeavesFindWhatBruteForceFinds)
{
    // Ids 0 .. 49,999: random triangles in the lower half of the box, in no spatial order, so
    // most leaves there span 2^15 ids or more (wide). Ids 50,000 .. 89,999: the upper half,
    // sorted along x, so its leaves span few ids (narrow), most from a head above 2^16 (whose
    // upper word the walk must not take for an offset). Closest and any hit against brute force.
    const Aabb box{{0, 0, 0}, {10, 10, 10}};
    Mesh mesh = test::random_triangles(23, 50000, Aabb{{0, 0, 0}, {4.9f, 10, 10}}, 0.4f);
    Mesh upper = test::random_triangles(24, 40000, Aabb{{5.1f, 0, 0}, {10, 10, 10}}, 0.4f);
    std::ranges::sort(upper.triangles, {}, [&](const Triangle& t) { return upper.vertices[t.v[0]].x; });
    test::append(mesh, upper);
    const SplitGrid grid = build_split_grid(mesh.view(), BuildConfig{});
    check_invariants(grid);
    std::size_t wide = 0, narrow_high = 0, long_leaves = 0;
    for (const Ids& leaf : test::all_leaves(grid)) {
        const bool is_wide = leaf.back() - leaf.front() >= 32768;
        wide += is_wide ? 1 : 0;
        narrow_high += !is_wide && leaf.front() >= 65536 ? 1 : 0;
        long_leaves += leaf.size() > 8 ? 1 : 0;
    }
    EXPECT_GT(wide, 1000u);
    EXPECT_GT(narrow_high, 1000u);
    EXPECT_GT(long_leaves, 1000u) << "leaves of more than one batch of lanes";
    std::printf("[ leaves   ] %zu wide, %zu narrow from a head above 2^16, %zu of more than 8 "
                "references\n", wide, narrow_high, long_leaves);
    const auto rays = test::rays_at_triangles(8, 1500, box, mesh.view());
    const auto r = test::compare_with_brute_force(grid, mesh.view(), rays);
    EXPECT_EQ(r.closest_disagreements, 0u) << r.first_failure;
    EXPECT_EQ(r.any_hit_disagreements, 0u) << r.first_failure;
    EXPECT_GT(r.hits, rays.size() / 4);
}

TEST(TraverseLeafWords, LeavesOfEveryLengthInBothFormsEndingTheArray)
{
    // A grid whose root is one leaf, the array's only and last one, of 1 to 24 references,
    // narrow and wide: every way a batch of eight lanes can end against the array's end. The
    // leaf's triangles are real ones in the unit box; every other triangle of the mesh is a
    // point far outside it, which no ray hits.
    const Aabb box{{0, 0, 0}, {1, 1, 1}};
    constexpr std::uint32_t triangles = 33000;
    for (const bool wide : {false, true}) {
        for (const std::uint32_t count : {1u, 2u, 7u, 8u, 9u, 15u, 16u, 17u, 24u}) {
            if (wide && count == 1) continue;  // a one-reference leaf is always narrow
            SCOPED_TRACE((wide ? "wide, " : "narrow, ") + std::to_string(count) + " references");
            const std::size_t n = count;
            Ids ids;
            for (std::uint32_t k = 0; k + 1 < count; ++k) ids.push_back(10 + k);
            // The last id is the next one, or 2^15 or more past the first for a wide leaf.
            ids.push_back(wide ? 10 + count + 32768 : 10 + count - 1);
            const Mesh real = test::random_triangles(count, n, box, 0.6f);
            Mesh mesh;
            mesh.vertices = real.vertices;
            mesh.vertices.push_back({50, 50, 50});
            const auto far = static_cast<std::uint32_t>(mesh.vertices.size() - 1);
            mesh.triangles.assign(triangles, Triangle{{far, far, far}});
            for (std::size_t k = 0; k < n; ++k) mesh.triangles[ids[k]] = real.triangles[k];
            SplitGrid grid;
            grid.root_box = box;
            grid.triangle_count = triangles;
            grid.root = CellRef::make_leaf(append_leaf(grid.leaf_words, ids));
            ASSERT_EQ(grid.leaf_words.size(), wide ? 2 * n : n + 1);
            check_invariants(grid);
            const auto rays = test::rays_at_triangles(3, 300, box, real.view());
            const auto r = test::compare_with_brute_force(grid, mesh.view(), rays);
            EXPECT_EQ(r.closest_disagreements, 0u) << r.first_failure;
            EXPECT_EQ(r.any_hit_disagreements, 0u) << r.first_failure;
            EXPECT_GT(r.hits, rays.size() / 2);
        }
    }
}

}  // namespace
}  // namespace sg
