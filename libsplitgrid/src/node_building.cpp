#include "node_building.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <span>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "splitgrid/cell_math.hpp"
#include "splitgrid/clip.hpp"
#include "splitgrid/leaf_words.hpp"

namespace sg::detail {
namespace {

// A child's share of its parent's weight (progress reports): its share of the references.
double share(double weight, std::size_t count, std::size_t total_refs) noexcept
{
    return weight * static_cast<double>(count) / static_cast<double>(total_refs);
}

// Nodes written to a Fragment, each in the one cell of the one before: the one-cell
// nodes around a cell, outermost first, then the cell's own node or leaf.
struct Chain {
    CellRef head;
    std::size_t last_node = std::numeric_limits<std::size_t>::max();

    void link(CellRef ref, Fragment& out)
    {
        if (last_node == std::numeric_limits<std::size_t>::max())
            head = ref;
        else
            out.nodes[last_node].set_only_cell(ref);
    }
    // Appends a node record (and, for two or more cells, its block of cells, still empty)
    // and links it; returns its index.
    std::uint32_t add_node(int axis, float lo, float hi, std::uint32_t resolution,
                           Fragment& out)
    {
        const auto index = static_cast<std::uint32_t>(out.nodes.size());
        out.nodes.push_back(new_node(axis, lo, hi, resolution, out.cells));
        link(CellRef::make_inner(index, resolution), out);
        last_node = index;
        return index;
    }
};

// Appends the one-cell nodes `bounds` to `out`, each in the one before.
void emit_bounds(const Bounds& bounds, Chain& chain, Fragment& out)
{
    for (std::uint32_t b = 0; b < bounds.count; ++b)
        chain.add_node(bounds.items[b].axis, bounds.items[b].lo, bounds.items[b].hi, 1, out);
}

// `inner` inside the one-cell nodes `bounds` (outermost first).
BuiltCell wrap(const Bounds& bounds, BuiltCell inner)
{
    for (std::uint32_t b = bounds.count; b-- > 0;) {
        auto node = std::make_unique<BuiltNode>();
        node->axis = bounds.items[b].axis;
        node->lo = bounds.items[b].lo;
        node->hi = bounds.items[b].hi;
        node->cells.resize(1);
        node->cells[0] = std::move(inner);
        inner = BuiltCell{};
        inner.kind = CellKind::Inner;
        inner.node = std::move(node);
    }
    return inner;
}

}  // namespace

NodeBuilder::NodeBuilder(const BuildContext& context, const BuildProgress& progress)
    : context_(context), planner_(context), progress_(progress)
{
}

BuiltCell NodeBuilder::build_root(const Aabb& box)
{
    TriangleIds tris(context_.mesh.triangle_count());
    for (std::size_t k = 0; k < tris.size(); ++k) tris[k] = static_cast<std::uint32_t>(k);
    const WholeExtents whole{&context_.mesh, tris.data(), tris.size()};
    if (tris.size() < parallel_grain) {
        ExtentArray extents(tris.size());
        for (std::size_t k = 0; k < extents.size(); ++k) extents[k] = whole[k];
        return build_fragment(box, tris, extents, 0, 1.0, 0);
    }
    Split split;
    const Plan plan = planner_.plan_cell(box, tris.data(), whole, 0, 0, true, split);
    if (!plan.is_node) return wrap(plan.bounds, make_leaf(std::move(tris), 1.0));
    return split_node(box, plan, split, std::move(tris), whole, [] {}, 1.0, 0);
}

// Builds the cell covering `box` for the triangles `tris` (all known to touch the padded
// box), as a node at `depth`, or a leaf when splitting does not pay. `extents` holds, per
// triangle, its clipped extent in this box where the parent already knew it (known).
// `weight` is this cell's share of the whole build, for progress reports. `kept_all` counts
// the levels in a row at which this cell received all of its parent's triangles (see
// SplitPlanner::plan_cell).
BuiltCell NodeBuilder::build_cell(const Aabb& box, TriangleIds tris, ExtentArray extents,
                                  std::uint32_t depth, double weight, std::uint32_t kept_all)
{
    if (tris.empty()) return {};
    if (tris.size() < parallel_grain)
        return build_fragment(box, tris, extents, depth, weight, kept_all);
    const std::size_t n = tris.size();
    const StoredExtents stored{extents.data(), n};
    Split split;
    const Plan plan = planner_.plan_cell(box, tris.data(), stored, depth, kept_all, false, split);
    if (!plan.is_node) return wrap(plan.bounds, make_leaf(std::move(tris), weight));
    return split_node(box, plan, split, std::move(tris), stored, [&] { extents = {}; },
                      weight, kept_all);
}

// The rest of build_cell (and build_root) for a node planned as `plan` and `split`: hands
// its triangles to the cells, calls `release` (which frees the node's stored extents) and
// builds the cells in parallel.
template <class Extents, class Release>
BuiltCell NodeBuilder::split_node(const Aabb& box, const Plan& plan, Split& split,
                                  TriangleIds tris, const Extents& extents,
                                  const Release& release, double weight, std::uint32_t kept_all)
{
    const std::size_t n = tris.size();
    const int axis = split.axis;
    const std::uint32_t resolution = split.resolution;
    const CellMath cm(split.lo, split.hi, resolution);
    std::size_t total_refs = 0;
    for (std::uint32_t c : split.counts) total_refs += c;
    std::vector<TriangleIds> cell_tris(resolution);
    std::vector<ExtentArray> cell_extents(resolution);
    hand_out(box, plan, split, tris, extents, cell_tris, cell_extents);
    tris = {};
    release();
    split = {};

    auto node = std::make_unique<BuiltNode>();
    node->axis = axis;
    node->lo = cm.lo;
    node->hi = cm.hi;
    node->cells.resize(resolution);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, resolution, 1),
                      [&](const tbb::blocked_range<std::uint32_t>& r) {
                          for (std::uint32_t c = r.begin(); c < r.end(); ++c) {
                              const std::size_t count = cell_tris[c].size();
                              node->cells[c] = build_cell(
                                  cm.cell_box(plan.bounded, axis, c), std::move(cell_tris[c]),
                                  std::move(cell_extents[c]), plan.child_depth,
                                  share(weight, count, total_refs),
                                  count == n ? kept_all + 1 : 0);
                          }
                      });
    BuiltCell cell;
    cell.kind = CellKind::Inner;
    cell.node = std::move(node);
    return wrap(plan.bounds, std::move(cell));
}

// Hands the triangles of a node of at least parallel_grain of them to its cells
// (distribute), in parallel, in the blocks try_split counted them in: each block writes
// what it gives a cell after what the blocks before it gave, so that a cell's triangles
// keep the node's order whatever the thread count. The cells' arrays are sized from the
// counts and left unwritten until then (UninitializedAllocator). The cells clip their
// straddling triangles themselves, in parallel, each to its own box.
template <class Extents>
void NodeBuilder::hand_out(const Aabb& box, const Plan& plan, const Split& split,
                           const TriangleIds& tris, const Extents& extents,
                           std::vector<TriangleIds>& cell_tris,
                           std::vector<ExtentArray>& cell_extents) const
{
    const std::uint32_t resolution = split.resolution;
    const TriangleBlocks blocks(tris.size(), resolution);
    // Where each block writes in each cell: after the blocks before it.
    std::vector<std::uint32_t> next(blocks.count * resolution);
    std::vector<std::uint32_t> given(resolution, 0);
    for (std::size_t b = 0; b < blocks.count; ++b) {
        const std::uint32_t* differences = split.block_counts.data() + b * (resolution + 1);
        std::uint32_t count = 0;
        for (std::uint32_t c = 0; c < resolution; ++c) {
            count += differences[c];
            next[b * resolution + c] = given[c];
            given[c] += count;
        }
    }
    tbb::parallel_for(std::uint32_t{0}, resolution, [&](std::uint32_t c) {
        cell_tris[c].resize(split.counts[c]);
        cell_extents[c].resize(split.counts[c]);
    });
    tbb::parallel_for(std::size_t{0}, blocks.count, [&](std::size_t b) {
        std::uint32_t* at = next.data() + b * resolution;
        const auto [begin, end] = blocks.range(b);
        std::vector<Aabbd> unused;
        distribute(box, plan, split, tris.data(), extents, begin, end, nullptr, unused,
                   [&](std::uint32_t c, std::size_t k, const TriExtent& e) {
                       const std::uint32_t to = at[c]++;
                       cell_tris[c][to] = tris[k];
                       cell_extents[c][to] = e;
                   });
    });
}

// Hands each triangle k in [begin, end) to the cells of `split` its extent touches:
// put(cell, k, extent). A triangle whose padded extent lies in one cell keeps its clipped
// extent there: the cell's padded box differs from this one on the split axis, where it
// still contains the clipped piece, and on the axes of bounding nodes, whose planes lie
// a pad outside the tight box of all pieces (choose_bounds), so clipping again would
// give the same piece. For the same reason the cell's box contains every piece on the
// other axes, which ClippedTriangle::slab_bounds requires. A triangle that straddles
// cells is clipped to this node's padded box once, when `cell_counts` is given, and each
// cell's piece is read from that polygon (ClippedTriangle::slab_bounds);
// otherwise the children clip it again, each to its own box. The parallel top of the
// tree leaves it to the children, which run in parallel; the serial subtrees clip here,
// once instead of once per cell (docs/notebook/build.md, section '"Build fast": each lever,
// measured', has the count of cells per straddling triangle).
// `cell_counts` (when clipping pieces) holds the number of triangles each cell gets: a
// cell that becomes a leaf without looking at its extents gets no pieces. `cell_boxes`
// is working memory for the cells' padded boxes. Returns false when a cell that looks
// at its extents got one not computed yet (unclipped pieces, or a polygon that rounding
// lost), so that the cells know whether they have to look for such extents.
template <class Extents, class Put>
bool NodeBuilder::distribute(const Aabb& box, const Plan& plan, const Split& split,
                             const std::uint32_t* tris, const Extents& extents,
                             std::size_t begin, std::size_t end,
                             const std::uint32_t* cell_counts, std::vector<Aabbd>& cell_boxes,
                             const Put& put) const
{
    const bool clip_pieces = cell_counts != nullptr && context_.config.clip_triangles;
    const Aabbd clip_box = Aabbd::from(box).padded(context_.pad);
    if (clip_pieces) {
        const CellMath cm(split.lo, split.hi, split.resolution);
        cell_boxes.resize(split.resolution);
        for (std::uint32_t c = 0; c < split.resolution; ++c)
            cell_boxes[c] =
                Aabbd::from(cm.cell_box(plan.bounded, split.axis, c)).padded(context_.pad);
    }
    auto wants_extents = [&](std::uint32_t c) {
        return !planner_.ends_as_plain_leaf(cell_counts[c], plan.child_depth);
    };
    ClippedTriangle polygon;
    bool all_known = true;
    for (std::size_t k = begin; k < end; ++k) {
        const std::uint32_t first = split.first[k];
        const std::uint32_t last = split.last[k];
        if (first == last) {
            put(first, k, extents[k]);
            continue;
        }
        bool clipped = false;
        if (first < last && clip_pieces) {
            bool wanted = false;
            for (std::uint32_t c = first; c <= last && !wanted; ++c) wanted = wants_extents(c);
            clipped = wanted && polygon.clip(Vec3d(context_.mesh.vertex(tris[k], 0)),
                                             Vec3d(context_.mesh.vertex(tris[k], 1)),
                                             Vec3d(context_.mesh.vertex(tris[k], 2)), clip_box);
            all_known = all_known && (clipped || !wanted);
        } else if (first < last) {
            all_known = false;
        }
        // Two cells that both want their piece (most straddlers on the scans): both
        // pieces in one pass over the polygon, where it applies.
        if (clipped && last == first + 1 && wants_extents(first) && wants_extents(last)) {
            std::array<Aabbd, 2> pieces;
            std::array<bool, 2> found{};
            if (polygon.adjacent_slab_bounds(split.axis, cell_boxes[first], cell_boxes[last],
                                             pieces, found)) {
                put(first, k,
                    found[0] ? rounded_extent(pieces[0], extents[k].size) : empty_extent());
                put(last, k,
                    found[1] ? rounded_extent(pieces[1], extents[k].size) : empty_extent());
                continue;
            }
        }
        for (std::uint32_t c = first; c <= last; ++c) {
            if (!clipped || !wants_extents(c)) {
                put(c, k, TriExtent{});
                continue;
            }
            const Aabbd& cell = cell_boxes[c];
            Aabbd piece;
            put(c, k,
                polygon.slab_bounds(split.axis, cell, piece)
                    ? rounded_extent(piece, extents[k].size)
                    : empty_extent());
        }
    }
    return all_known;
}

// A cell of fewer than parallel_grain triangles: its whole subtree, built by this thread
// in the thread's workspace (no task of the build runs inside it: it calls no parallel
// algorithm, and report() isolates the progress callback).
BuiltCell NodeBuilder::build_fragment(const Aabb& box, const TriangleIds& tris,
                                      const ExtentArray& extents, std::uint32_t depth,
                                      double weight, std::uint32_t kept_all)
{
    const std::size_t n = tris.size();
    Workspace& workspace = workspaces_.local();
    Scratch& scratch = workspace.scratch;
    if (scratch.tris.size() < n) {
        scratch.tris.resize(n);
        scratch.extents.resize(n);
    }
    std::copy(tris.begin(), tris.end(), scratch.tris.begin());
    // The parent's extents, each marked known or not.
    std::copy_n(extents.begin(), n, scratch.extents.begin());
    Fragment& out = workspace.out;
    out.nodes.clear();
    out.cells.clear();
    out.leaf_words.clear();
    const CellRef root =
        build_serial(box, 0, n, n, depth, weight, kept_all, false, scratch, out);
    // Fragments wait for assemble() until the whole tree is built: no spare capacity.
    BuiltCell cell;
    cell.kind = root.kind();
    cell.fragment = std::make_unique<Fragment>(
        Fragment{root, {out.nodes.begin(), out.nodes.end()},
                 {out.cells.begin(), out.cells.end()},
                 {out.leaf_words.begin(), out.leaf_words.end()}});
    return cell;
}

// build_cell for one thread: the same decisions, for the triangles at [begin, begin + n)
// of the scratch stacks, written to `out` in depth-first pre-order (a node's record, its
// cells as one block, then its children), which is the order assemble() gives the parallel
// part. `top` is the first free place on the stacks; the children's triangles are stacked
// there, cell after cell. `all_known`: this cell's extents are all computed, or it becomes a
// leaf without reading them (ends_as_plain_leaf).
CellRef NodeBuilder::build_serial(const Aabb& box, std::size_t begin, std::size_t n,
                                  std::size_t top, std::uint32_t depth, double weight,
                                  std::uint32_t kept_all, bool all_known, Scratch& s,
                                  Fragment& out)
{
    if (n == 0) return CellRef::make_empty();
    const Plan plan = planner_.plan_cell(box, s.tris.data() + begin,
                                         StoredExtents{s.extents.data() + begin, n}, depth,
                                         kept_all, all_known, s.split);
    Chain chain;
    emit_bounds(plan.bounds, chain, out);
    if (!plan.is_node) {
        chain.link(emit_leaf(s, begin, n, weight, out), out);
        return chain.head;
    }
    Split& split = s.split;
    const int axis = split.axis;
    const std::uint32_t resolution = split.resolution;
    const CellMath cm(split.lo, split.hi, resolution);

    // The cells' triangles, stacked from `top` in cell order. The counts go on a stack of
    // their own: `split` is reused by the children, and its counts become write cursors.
    const std::size_t counts_at = s.cell_counts.size();
    s.cell_counts.insert(s.cell_counts.end(), split.counts.begin(), split.counts.end());
    std::size_t child_top = top;
    for (std::uint32_t c = 0; c < resolution; ++c) {
        const std::uint32_t count = split.counts[c];
        split.counts[c] = static_cast<std::uint32_t>(child_top - top);
        child_top += count;
    }
    if (s.tris.size() < child_top) {
        s.tris.resize(child_top);
        s.extents.resize(child_top);
    }
    const bool children_known = distribute(
        box, plan, split, s.tris.data() + begin, StoredExtents{s.extents.data() + begin, n}, 0,
        n, s.cell_counts.data() + counts_at, s.cell_boxes,
        [&](std::uint32_t c, std::size_t k, const TriExtent& e) {
            const std::size_t to = top + split.counts[c]++;
            s.tris[to] = s.tris[begin + k];
            s.extents[to] = e;
        });
    const std::size_t total_refs = child_top - top;

    const std::uint32_t index = chain.add_node(axis, cm.lo, cm.hi, resolution, out);
    std::size_t child_begin = top;
    for (std::uint32_t c = 0; c < resolution; ++c) {
        const std::size_t count = s.cell_counts[counts_at + c];
        // Built before it is stored: the child appends to out.nodes and out.cells.
        const CellRef child =
            build_serial(cm.cell_box(plan.bounded, axis, c), child_begin, count, child_top,
                         plan.child_depth, share(weight, count, total_refs),
                         count == n ? kept_all + 1 : 0, children_known, s, out);
        store_cell(out.nodes, out.cells, index, c, child);
        child_begin += count;
    }
    s.cell_counts.resize(counts_at);
    return chain.head;
}

// A leaf of the triangles at [begin, begin + n) of the scratch stack, appended to `out`.
CellRef NodeBuilder::emit_leaf(const Scratch& s, std::size_t begin, std::size_t n, double weight,
                               Fragment& out)
{
    // The ids are strictly ascending, as append_leaf needs: the root's list counts up and
    // every hand-out to the cells keeps the order (see distribute).
    const std::uint32_t first =
        append_leaf(out.leaf_words, std::span(s.tris).subspan(begin, n));
    report(weight);
    return CellRef::make_leaf(first);
}

// A leaf of the parallel top of the tree.
BuiltCell NodeBuilder::make_leaf(TriangleIds tris, double weight)
{
    BuiltCell cell;
    cell.kind = CellKind::Leaf;
    cell.triangles = std::move(tris);
    report(weight);
    return cell;
}

// Adds `weight` to the share of the build done, and calls the progress callback at most once
// per half percent.
void NodeBuilder::report(double weight)
{
    if (!progress_) return;
    const std::lock_guard<std::mutex> lock(progress_mutex_);
    done_ += weight;
    if (done_ - last_reported_ >= 0.005 || done_ >= 1.0 - 1e-9) {
        last_reported_ = done_;
        // Isolated: a callback that runs parallel work of its own must not let this thread
        // take up another of the build's tasks, which would share its Workspace.
        tbb::this_task_arena::isolate([&] { progress_(std::min(1.0, done_)); });
    }
}

}  // namespace sg::detail
