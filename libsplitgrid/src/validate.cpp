#include "splitgrid/validate.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "splitgrid/cell_math.hpp"
#include "splitgrid/clip.hpp"
#include "splitgrid/error.hpp"

namespace sg {
namespace {

[[noreturn]] void fail(const std::string& what) { throw FormatError(what); }

std::string node_name(std::uint32_t node) { return "node " + std::to_string(node); }

// Checks one cell record. An inner cell's kind must match its child's resolution. A leaf's
// words must lie in the array and end with a reference marked last (the traversal reads up to
// it), name triangles of the mesh in strictly ascending order, and belong to no other leaf.
// `place` names the cell in a message; it is called only to fail: a name built for every cell
// made loading a large file markedly slower (docs/notebook/layout.md, "A file's check names a
// cell only when it refuses one").
template <class Place>
void check_cell(const SplitGrid& grid, const CellRef& cell, const Place& place,
                std::vector<bool>& word_seen)
{
    const auto where = [&] { return std::string(place()); };
    if (!cell.has_valid_kind())
        fail(where() + ": cell word " + std::to_string(cell.raw_bits()) + " is not a valid cell");
    if (cell.is_empty()) return;
    if (cell.is_inner()) {
        if (cell.child() >= grid.nodes.size())
            fail(where() + ": child node " + std::to_string(cell.child()) + " out of range (" +
                 std::to_string(grid.nodes.size()) + " nodes)");
        // The walk enters the child as the kind says, without looking at its record.
        const std::uint32_t n = grid.nodes[cell.child()].resolution();
        if (cell.has_one_cell_child() != (n == 1))
            fail(where() + ": the cell's kind says its child node " + std::to_string(cell.child()) +
                 (cell.has_one_cell_child() ? " has one cell" : " has two or more cells") +
                 ", but it has " + std::to_string(n));
        return;
    }
    const std::span<const std::uint16_t> words(grid.leaf_words);
    const std::size_t first = cell.first_word();
    if (first >= words.size())
        fail(where() + ": first leaf word " + std::to_string(first) + " out of range (" +
             std::to_string(words.size()) + " words)");
    bool any = false, unordered = false;
    std::uint32_t previous = 0, beyond = 0;
    const std::size_t end = read_leaf(words, first, [&](std::uint32_t id) {
        if (any && id <= previous) unordered = true;
        if (id >= grid.triangle_count && beyond == 0) beyond = id + 1;
        previous = id;
        any = true;
    });
    if (end == 0)
        fail(where() + ": the leaf at word " + std::to_string(first) +
             " runs past the end of the array or is not a valid leaf");
    if (beyond != 0)
        fail(where() + ": the leaf names triangle " + std::to_string(beyond - 1) +
             " but there are " + std::to_string(grid.triangle_count) + " triangles");
    if (unordered) fail(where() + ": the leaf's triangle ids are not strictly ascending");
    // The encoding of a list of ids is unique (leaf_words.hpp), so files are comparable byte
    // for byte: wide exactly when the ids span 2^15 or more, and no id above the limit.
    const std::uint32_t head = leaf_pair(words.data() + first);
    const bool wide = (head & leaf_code::wide_bit) != 0;
    const std::uint32_t span = previous - (head & leaf_code::id_mask);
    if (wide != (span >= leaf_code::narrow_span))
        fail(where() + ": the leaf is " + (wide ? "wide" : "narrow") + " but its ids span " +
             std::to_string(span) + " (wide exactly from 2^15 on)");
    if (previous > max_referenced_triangle)
        fail(where() + ": the leaf names triangle " + std::to_string(previous) +
             ", above the largest id a leaf can hold (2^30 - 1)");
    for (std::size_t w = first; w < end; ++w) {
        if (word_seen[w])
            fail(where() + ": leaf word " + std::to_string(w) + " also belongs to another leaf");
        word_seen[w] = true;
    }
}

struct Pending {
    std::uint32_t node;
    std::uint32_t depth;
    Aabb box;
};

}  // namespace

void check_invariants(const SplitGrid& grid)
{
    if (grid.root.is_empty()) {
        if (!grid.nodes.empty() || !grid.cells.empty() || !grid.leaf_words.empty())
            fail("root cell is empty but the grid has nodes, cells or leaf words");
        return;
    }
    if (!is_finite(grid.root_box.lower) || !is_finite(grid.root_box.upper) ||
        grid.root_box.is_empty())
        fail("root box is empty or not finite");

    std::vector<bool> word_seen(grid.leaf_words.size(), false);
    check_cell(grid, grid.root, [] { return "root cell"; }, word_seen);
    std::vector<bool> node_seen(grid.nodes.size(), false);
    std::vector<bool> cell_owned(grid.cells.size(), false);
    std::vector<Pending> pending;
    if (grid.root.is_inner()) pending.push_back({grid.root.child(), 0, grid.root_box});
    std::size_t nodes_reached = 0;
    while (!pending.empty()) {
        const Pending p = pending.back();
        pending.pop_back();
        const auto where = [&] { return node_name(p.node); };
        if (node_seen[p.node])
            fail(where() + " is the child of more than one cell (a cycle or a shared subtree)");
        node_seen[p.node] = true;
        ++nodes_reached;
        if (p.depth > max_supported_depth)
            fail(where() + " is at depth " + std::to_string(p.depth) + ", deeper than " +
                 std::to_string(max_supported_depth));
        const GridNode& node = grid.nodes[p.node];
        if ((node.axis_res_bits() & 3u) == 3u) fail(where() + ": axis 3 is not an axis");
        const std::uint32_t n = node.resolution();
        if (n == 0) fail(where() + ": resolution 0");
        const int axis = node.axis();
        if (!std::isfinite(node.lo) || !std::isfinite(node.hi) || !(node.lo <= node.hi))
            fail(where() + ": bounding planes [" + std::to_string(node.lo) + ", " +
                 std::to_string(node.hi) + "] are not finite and ordered");
        if (node.lo < p.box.lower[axis] || node.hi > p.box.upper[axis])
            fail(where() + ": bounding planes [" + std::to_string(node.lo) + ", " +
                 std::to_string(node.hi) + "] leave the node's box on axis " +
                 std::to_string(axis));
        if (n >= 2) {
            const std::uint64_t end = std::uint64_t{node.first_cell()} + n;
            if (end > grid.cells.size())
                fail(where() + ": cells " + std::to_string(node.first_cell()) + ".." +
                     std::to_string(end) + " out of range (" +
                     std::to_string(grid.cells.size()) + " cells)");
            for (std::uint32_t i = 0; i < n; ++i) {
                if (cell_owned[node.first_cell() + i])
                    fail(where() + ": cell " + std::to_string(node.first_cell() + i) +
                         " also belongs to another node");
                cell_owned[node.first_cell() + i] = true;
            }
        }
        const CellMath cm(node.lo, node.hi, n);
        for (std::uint32_t i = 0; i < n; ++i) {
            const CellRef cell = node_cell(grid, node, i);
            const auto place = [&] { return where() + " cell " + std::to_string(i); };
            check_cell(grid, cell, place, word_seen);
            if (!cell.is_inner()) continue;
            pending.push_back({cell.child(), p.depth + 1, cm.cell_box(p.box, axis, i)});
        }
    }
    if (nodes_reached != grid.nodes.size())
        fail(std::to_string(grid.nodes.size() - nodes_reached) +
             " nodes are not reachable from the root");
    const auto cells_unowned = static_cast<std::size_t>(std::ranges::count(cell_owned, false));
    if (cells_unowned != 0)
        fail(std::to_string(cells_unowned) + " of the grid's " +
             std::to_string(grid.cells.size()) + " cells belong to no node");
    const auto words_seen =
        static_cast<std::size_t>(std::count(word_seen.begin(), word_seen.end(), true));
    if (words_seen != grid.leaf_words.size())
        fail("leaves hold " + std::to_string(words_seen) + " words but the grid has " +
             std::to_string(grid.leaf_words.size()));
}

namespace {

// Every leaf's triangle ids, decoded once, so the coverage check finds a triangle in a leaf by
// bisection (check_invariants makes sure the ids are ascending): decoding the leaf for every
// lookup made a leaf of n references cost n^2.
struct LeafIndex {
    std::vector<std::uint32_t> first_words;  // each leaf's first word, ascending
    std::vector<std::size_t> starts;         // where each leaf's ids begin in `ids`, and the end
    std::vector<std::uint32_t> ids;

    explicit LeafIndex(std::span<const std::uint16_t> words)
    {
        (void)for_each_leaf(words, [&](std::size_t first, std::size_t,
                                       std::span<const std::uint32_t> leaf) {
            first_words.push_back(static_cast<std::uint32_t>(first));
            starts.push_back(ids.size());
            ids.insert(ids.end(), leaf.begin(), leaf.end());
        });
        starts.push_back(ids.size());
    }

    [[nodiscard]] bool contains(std::uint32_t first_word, std::uint32_t tri) const
    {
        const auto at = std::ranges::lower_bound(first_words, first_word);
        if (at == first_words.end() || *at != first_word) return false;
        const auto leaf = static_cast<std::size_t>(at - first_words.begin());
        const std::span<const std::uint32_t> leaf_ids(ids.data() + starts[leaf],
                                                      starts[leaf + 1] - starts[leaf]);
        return std::ranges::binary_search(leaf_ids, tri);
    }
};

// Descends from `cell` (covering `box`) through every cell the triangle overlaps.
void check_triangle(const SplitGrid& grid, const LeafIndex& leaves,
                    std::uint32_t tri, const Vec3d (&v)[3], const CellRef& cell, const Aabb& box,
                    const std::string& where)
{
    if (!triangle_overlaps_box(v[0], v[1], v[2], Aabbd::from(box))) return;
    const std::string tri_name = "triangle " + std::to_string(tri);
    if (cell.is_empty()) fail(tri_name + " overlaps " + where + ", which is empty");
    if (cell.is_leaf()) {
        if (!leaves.contains(cell.first_word(), tri)) fail(tri_name + " overlaps " + where + " but is not in its leaf");
        return;
    }
    const std::uint32_t index = cell.child();
    const GridNode& node = grid.nodes[index];
    const int axis = node.axis();
    const std::string name = node_name(index);
    // The space cut away by the bounding planes must not hold any of the triangle.
    for (int side = 0; side < 2; ++side) {
        Aabb cut = box;
        if (side == 0) {
            if (!(node.lo > box.lower[axis])) continue;
            cut.upper[axis] = std::nextafter(node.lo, -std::numeric_limits<float>::infinity());
        } else {
            if (!(node.hi < box.upper[axis])) continue;
            cut.lower[axis] = std::nextafter(node.hi, std::numeric_limits<float>::infinity());
        }
        if (triangle_overlaps_box(v[0], v[1], v[2], Aabbd::from(cut)))
            fail(tri_name + " reaches past the " + (side == 0 ? "lower" : "upper") +
                 " bounding plane of " + name);
    }
    const std::uint32_t n = node.resolution();
    const CellMath cm(node.lo, node.hi, n);
    // Only cells within the triangle's bounding box on this axis can overlap it.
    const double tmin = std::min({v[0][axis], v[1][axis], v[2][axis]});
    const double tmax = std::max({v[0][axis], v[1][axis], v[2][axis]});
    const std::uint32_t c0 = cm.locate_lowest(
        std::nextafter(static_cast<float>(tmin), -std::numeric_limits<float>::infinity()));
    const std::uint32_t c1 = cm.locate_highest(
        std::nextafter(static_cast<float>(tmax), std::numeric_limits<float>::infinity()));
    for (std::uint32_t i = c0; i <= c1 && i < n; ++i) {
        check_triangle(grid, leaves, tri, v, node_cell(grid, node, i),
                       cm.cell_box(box, axis, i), name + " cell " + std::to_string(i));
    }
}

}  // namespace

void check_coverage(const SplitGrid& grid, const MeshView& mesh)
{
    if (mesh.triangle_count() != grid.triangle_count)
        fail("grid was built for " + std::to_string(grid.triangle_count) +
             " triangles but the mesh has " + std::to_string(mesh.triangle_count()));
    if (grid.root.is_empty()) {
        if (grid.triangle_count != 0) fail("root is empty but the mesh has triangles");
        return;
    }
    const LeafIndex leaves(grid.leaf_words);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, grid.triangle_count, 256),
                      [&](const tbb::blocked_range<std::uint32_t>& r) {
                          for (std::uint32_t t = r.begin(); t < r.end(); ++t) {
                              const Vec3d v[3] = {Vec3d(mesh.vertex(t, 0)),
                                                  Vec3d(mesh.vertex(t, 1)),
                                                  Vec3d(mesh.vertex(t, 2))};
                              for (const Vec3d& p : v)
                                  for (int k = 0; k < 3; ++k)
                                      if (p[k] < grid.root_box.lower[k] ||
                                          p[k] > grid.root_box.upper[k])
                                          fail("triangle " + std::to_string(t) +
                                               " lies outside the root box");
                              check_triangle(grid, leaves, t, v, grid.root, grid.root_box,
                                             "the root cell");
                          }
                      });
}

}  // namespace sg
