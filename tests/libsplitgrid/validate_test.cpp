#include "splitgrid/validate.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "support/leaf_triangles.hpp"
#include "support/random_scene.hpp"

namespace sg {
namespace {

struct Fixture {
    Mesh mesh = test::random_triangles(1, 3000, Aabb{{0, 0, 0}, {10, 10, 10}}, 0.5f);
    SplitGrid grid = build_split_grid(mesh.view(), {});
};

void expect_refused(const SplitGrid& grid, const std::string& needle)
{
    try {
        check_invariants(grid);
        FAIL() << "accepted a grid that should fail with '" << needle << "'";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
            << "expected '" << needle << "', got: " << e.what();
    }
}

TEST(Validate, AcceptsWhatTheBuilderMakes)
{
    Fixture f;
    EXPECT_NO_THROW(check_invariants(f.grid));
    EXPECT_NO_THROW(check_coverage(f.grid, f.mesh.view()));
}

TEST(Validate, RefusesEachKindOfCorruption)
{
    Fixture f;
    ASSERT_GT(f.grid.nodes.size(), 3u);
    const std::size_t inner = [&] {
        for (std::size_t c = 0; c < f.grid.cells.size(); ++c)
            if (f.grid.cells[c].is_inner()) return c;
        return std::size_t{0};
    }();
    const std::size_t leaf = [&] {
        for (std::size_t c = 0; c < f.grid.cells.size(); ++c)
            if (f.grid.cells[c].is_leaf()) return c;
        return std::size_t{0};
    }();

    SplitGrid g = f.grid;
    g.cells[inner] = CellRef::make_inner(static_cast<std::uint32_t>(g.nodes.size()), 2);
    expect_refused(g, "out of range");

    g = f.grid;  // back to the root: a cycle
    g.cells[inner] = CellRef::make_inner(0, g.nodes[0].resolution());
    expect_refused(g, "more than one cell");

    g = f.grid;
    g.cells[leaf] = CellRef::make_leaf(static_cast<std::uint32_t>(g.leaf_words.size()));
    expect_refused(g, "out of range");

    // The leaf's head names the triangle one past the mesh's last (its flags kept).
    g = f.grid;
    test::set_leaf_head(g, g.cells[leaf].first_word(), g.triangle_count);
    expect_refused(g, "names triangle " + std::to_string(g.triangle_count));

    // A cell pointing inside another leaf: its second word read as a head.
    g = f.grid;
    g.cells[leaf] = CellRef::make_leaf(g.cells[leaf].first_word() + 1);
    expect_refused(g, "leaf");

    // Words that belong to no leaf.
    g = f.grid;
    g.leaf_words.insert(g.leaf_words.end(), {0x0000, 0x8000});
    expect_refused(g, "leaves hold " + std::to_string(f.grid.leaf_words.size()) + " words");

    // A leaf stored wide although its ids span less than 2^15: not the encoding of its ids.
    g = f.grid;
    g.root = CellRef::make_leaf(0);
    g.nodes.clear();
    g.cells.clear();
    g.leaf_words = {0x0001, 0x4000, 0x0005, 0x8000};  // ids 1 and 5
    expect_refused(g, "the leaf is wide but its ids span 4");
    g.leaf_words = {0x0001, 0x0000, 0x8004};  // the same ids, narrow
    EXPECT_NO_THROW(check_invariants(g));

    // Two leaves sharing one list of references.
    g = f.grid;
    const std::size_t other_leaf = [&] {
        for (std::size_t c = leaf + 1; c < g.cells.size(); ++c)
            if (g.cells[c].is_leaf()) return c;
        return leaf;
    }();
    ASSERT_NE(other_leaf, leaf);
    g.cells[other_leaf] = g.cells[leaf];
    expect_refused(g, "also belongs to another leaf");

    // The last reference lost its end mark (bit 15 of the array's last word, in each of the
    // leaf's forms): the leaf would run off the array.
    g = f.grid;
    g.leaf_words.back() = static_cast<std::uint16_t>(g.leaf_words.back() & 0x7FFFu);
    expect_refused(g, "runs past the end of the array");

    // Two references of a narrow leaf swapped: its ids are no longer ascending.
    g = f.grid;
    bool swapped = false;
    for (const CellRef& cell : g.cells) {
        std::vector<std::uint16_t>& words = g.leaf_words;
        const std::size_t w = cell.first_word();
        if (!cell.is_leaf() || (words[w + 1] & 0xC000u) != 0 || (words[w + 2] & 0x8000u) != 0)
            continue;  // wide, one reference, or two
        const auto second = static_cast<std::uint16_t>(words[w + 2]);
        words[w + 2] = static_cast<std::uint16_t>(words[w + 3] & 0x7FFFu);
        words[w + 3] = static_cast<std::uint16_t>(second | (words[w + 3] & 0x8000u));
        swapped = true;
        break;
    }
    ASSERT_TRUE(swapped);
    expect_refused(g, "not strictly ascending");

    // A wide head marked last: not a leaf the encoder makes.
    g = f.grid;
    g.root = CellRef::make_leaf(static_cast<std::uint32_t>(g.leaf_words.size()));
    g.leaf_words.insert(g.leaf_words.end(), {0x0000, 0xC000});
    expect_refused(g, "not a valid leaf");

    // A word that is no cell at all: an empty kind with an index.
    g = f.grid;  // (the first leaf's index is 0, and a zero word is a valid empty cell)
    g.cells[other_leaf] = CellRef::from_raw(g.cells[other_leaf].raw_bits() & ~3u);
    expect_refused(g, "is not a valid cell");

    // An inner cell whose kind disagrees with its child's resolution (the walk would enter the
    // child the wrong way), both ways round.
    for (const bool one_cell_child : {true, false}) {
        g = f.grid;
        const auto cell = std::ranges::find_if(g.cells, [&](CellRef c) {
            return c.is_inner() && (g.nodes[c.child()].resolution() == 1) == one_cell_child;
        });
        ASSERT_NE(cell, g.cells.end());
        *cell = CellRef::make_inner(cell->child(), one_cell_child ? 2 : 1);
        expect_refused(g, one_cell_child ? "says its child node " + std::to_string(cell->child()) +
                                               " has two or more cells, but it has 1"
                                         : "has one cell, but it has");
    }
    // The same in the root cell and in a one-cell node's own cell.
    g = f.grid;
    ASSERT_TRUE(g.root.is_inner());
    const std::uint32_t root_child = g.root.child();
    g.root = CellRef::make_inner(root_child, g.nodes[root_child].resolution() == 1 ? 2 : 1);
    expect_refused(g, "root cell: the cell's kind says its child node");
    g = f.grid;
    const auto chain = std::ranges::find_if(g.nodes, [](const GridNode& n) {
        return n.resolution() == 1 && n.only_cell().is_inner();
    });
    ASSERT_NE(chain, g.nodes.end());
    const CellRef own = chain->only_cell();
    chain->set_only_cell(
        CellRef::make_inner(own.child(), g.nodes[own.child()].resolution() == 1 ? 2 : 1));
    expect_refused(g, "cell 0: the cell's kind says its child node");

    g = f.grid;
    g.nodes[1] = GridNode::from_raw(g.nodes[1].lo, g.nodes[1].hi, g.nodes[1].cells_bits(),
                                    g.nodes[1].axis_res_bits() | 3u);
    expect_refused(g, "axis 3");

    g = f.grid;
    g.nodes[2].lo = std::numeric_limits<float>::quiet_NaN();
    expect_refused(g, "not finite");

    g = f.grid;
    g.nodes[0].lo = g.root_box.lower[g.nodes[0].axis()] - 1.0f;
    expect_refused(g, "leave the node's box");

    const std::size_t multi = [&] {
        for (std::size_t k = 0; k < f.grid.nodes.size(); ++k)
            if (f.grid.nodes[k].resolution() >= 2) return k;
        return std::size_t{0};
    }();
    g = f.grid;
    g.nodes[multi] = GridNode::from_raw(g.nodes[multi].lo, g.nodes[multi].hi,
                                        static_cast<std::uint32_t>(g.cells.size()),
                                        g.nodes[multi].axis_res_bits());
    expect_refused(g, "out of range");

    // A one-cell node keeps its cell in its record: the same checks apply to that cell.
    const std::size_t single = [&] {
        for (std::size_t k = 0; k < f.grid.nodes.size(); ++k)
            if (f.grid.nodes[k].resolution() == 1 && f.grid.nodes[k].only_cell().is_inner())
                return k;
        return std::size_t{0};
    }();
    ASSERT_EQ(f.grid.nodes[single].resolution(), 1u);
    g = f.grid;
    g.nodes[single].set_only_cell(
        CellRef::make_inner(static_cast<std::uint32_t>(g.nodes.size()), 2));
    expect_refused(g, "out of range");
    g = f.grid;
    g.nodes[single].set_only_cell(CellRef::make_inner(0, g.nodes[0].resolution()));
    expect_refused(g, "more than one cell");
    g = f.grid;
    g.nodes[single].set_only_cell(CellRef::from_raw(g.nodes[single].cells_bits() & ~3u));
    expect_refused(g, "is not a valid cell");
    g = f.grid;
    g.nodes[single].set_only_cell(
        CellRef::make_leaf(static_cast<std::uint32_t>(g.leaf_words.size())));
    expect_refused(g, "out of range");

    g = f.grid;
    g.nodes.push_back(g.nodes[0]);  // unreachable
    expect_refused(g, "not reachable");

    g = f.grid;
    g.cells.push_back(CellRef{});  // owned by no node
    expect_refused(g, "cells belong to no node");
}

TEST(Validate, RefusesTwoNodesSharingABlockOfCells)
{
    // Node 0 has two inner cells; nodes 1 and 2 both claim cells 2..3 (empty), so the count of
    // owned cells matches the array while cells 4..5 belong to nobody.
    SplitGrid g;
    g.root_box = Aabb{{0, 0, 0}, {1, 1, 1}};
    g.triangle_count = 1;
    g.root = CellRef::make_inner(0, 2);
    g.nodes = {GridNode::make(0, 0.0f, 1.0f, 2, 0), GridNode::make(1, 0.0f, 1.0f, 2, 2),
               GridNode::make(1, 0.0f, 1.0f, 2, 4)};
    g.cells = {CellRef::make_inner(1, 2), CellRef::make_inner(2, 2), CellRef{}, CellRef{},
               CellRef::make_leaf(0), CellRef{}};
    g.leaf_words = {0x0000, 0x8000};  // one leaf: triangle 0, marked last
    // As built (node 2 owns cells 4..5) the grid is valid: the leaf is reached through node 2.
    EXPECT_NO_THROW(check_invariants(g));
    g.nodes[2] = GridNode::make(1, 0.0f, 1.0f, 2, 2);
    g.leaf_words.clear();
    g.cells[4] = CellRef{};
    expect_refused(g, "also belongs to another node");
}

TEST(Validate, RefusesTreesDeeperThanTheTraversalStack)
{
    // A chain of nodes with one cell each, one deeper than supported.
    SplitGrid g;
    g.root_box = Aabb{{0, 0, 0}, {1, 1, 1}};
    g.triangle_count = 1;
    g.root = CellRef::make_inner(0, 1);
    for (std::uint32_t d = 0; d <= max_supported_depth + 1; ++d) {
        g.nodes.push_back(GridNode::make_one_cell(0, 0.0f, 1.0f,
                                                  d == max_supported_depth + 1
                                                      ? CellRef::make_leaf(0)
                                                      : CellRef::make_inner(d + 1, 1)));
    }
    g.leaf_words = {0x0000, 0x8000};
    expect_refused(g, "deeper than");
    g.nodes.resize(max_supported_depth + 1);
    g.nodes.back().set_only_cell(CellRef::make_leaf(0));
    EXPECT_NO_THROW(check_invariants(g));
}

TEST(Validate, CoverageCatchesAMissingReference)
{
    Fixture f;
    // One triangle of a narrow leaf replaced by another: the head's id a becomes a - 1 (not in
    // the leaf, whose ids ascend from a), the further words' offsets one more, so the leaf
    // passes check_invariants but lacks triangle a, which coverage must notice.
    std::vector<std::uint16_t>& words = f.grid.leaf_words;
    for (CellRef& cell : f.grid.cells) {
        const std::size_t w = cell.first_word();
        if (!cell.is_leaf() || (words[w + 1] & 0xC000u) != 0) continue;  // wide, or one reference
        const std::uint32_t dropped = words[w] | (std::uint32_t{words[w + 1]} << 16);
        if (dropped == 0) continue;
        test::set_leaf_head(f.grid, w, dropped - 1);
        for (std::size_t k = w + 2;; ++k) {
            words[k] = static_cast<std::uint16_t>(words[k] + 1);
            if ((words[k] & 0x8000u) != 0) break;
        }
        ASSERT_NO_THROW(check_invariants(f.grid));
        try {
            check_coverage(f.grid, f.mesh.view());
            FAIL() << "coverage accepted a leaf without triangle " << dropped;
        } catch (const FormatError& e) {
            EXPECT_NE(std::string(e.what()).find("triangle " + std::to_string(dropped)),
                      std::string::npos)
                << e.what();
        }
        return;
    }
    FAIL() << "no leaf with two references";
}

}  // namespace
}  // namespace sg
