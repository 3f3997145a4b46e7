#include "splitgrid/builder.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <type_traits>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include "splitgrid/cell_math.hpp"
#include "splitgrid/clip.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/float_step.hpp"
#include "splitgrid/resolution.hpp"
#include "splitgrid/stats.hpp"

namespace sg {
namespace {

// Nodes with fewer triangles than this do their per-triangle work serially, and their
// subtrees are built by one thread (Builder::build_serial): below it the task overhead
// outweighs the work. The grid depends on it only through rounding: above it a straddling
// triangle is clipped to each cell's box, below it to the node's box and cut at the cells'
// planes (the same pieces up to double rounding). It does not depend on the thread count.
constexpr std::size_t parallel_grain = 4096;

// A one-cell bounding node is added where it cuts a cell's surface area by at least this
// fraction (BuildConfig::bounding_nodes). Counted on seven scenes (docs/BENCH.md, "Lever 4"):
// 0.1 costs 5-20% more bytes for no fewer instructions per ray, 0.5 costs 2-10% more
// instructions.
constexpr double bounding_node_gain = 0.25;

// A cell becomes a leaf when it received every one of its parent's triangles this many levels
// in a row. Such a cell holds a place where all of them meet (a fan around a vertex, a shared
// edge or corner): each split there repeats the last at a smaller scale, with the same
// triangles in the cell around the meeting point, down to max_depth. 1 would put a whole fan
// into the cell around its centre, where many rays pass; 2 ends the chains and leaves the
// work per ray as it was (docs/BENCH.md, "Lever 4b", has the counts for 1, 2 and no limit).
constexpr std::uint32_t kept_all_limit = 2;

// Clipped extent of one triangle inside a node box, in floats rounded outward, and the
// size of the whole (unclipped) triangle. `known` is false for an extent not computed yet.
struct TriExtent {
    Vec3f lower;
    Vec3f upper;
    Vec3f size;
    bool is_empty = false;
    bool known = false;
};

// Leaves the elements a container adds without arguments (std::vector's resize) unwritten,
// where std::allocator fills them (with zeros, or a type's default member initializers):
// the top of the tree sizes its arrays of triangle ids and extents and then writes every
// element, and filling them first was a pass over tens of megabytes per level
// (docs/BENCH.md, "The top nodes' triangles handed out in parallel"). For types whose bytes
// may be left as they are until written: trivially copyable and destructible (so that the
// allocation itself creates them, as for malloc).
template <class T>
struct UninitializedAllocator {
    using value_type = T;
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);

    UninitializedAllocator() noexcept = default;
    template <class U>
    UninitializedAllocator(const UninitializedAllocator<U>& /*other*/) noexcept
    {
    }

    T* allocate(std::size_t n) { return std::allocator<T>{}.allocate(n); }
    void deallocate(T* p, std::size_t n) noexcept { std::allocator<T>{}.deallocate(p, n); }
    void construct(T* /*p*/) noexcept {}
    template <class... Args>
    void construct(T* p, Args&&... args)
    {
        ::new (static_cast<void*>(p)) T(std::forward<Args>(args)...);
    }

    template <class U>
    bool operator==(const UninitializedAllocator<U>& /*other*/) const noexcept
    {
        return true;
    }
};

// The triangle ids and extents of a node in the parallel top of the tree.
using TriangleIds = std::vector<std::uint32_t, UninitializedAllocator<std::uint32_t>>;
using ExtentArray = std::vector<TriExtent, UninitializedAllocator<TriExtent>>;

// A candidate split of a node: axis, bounding planes, resolution and each triangle's cells.
struct Split {
    int axis = 0;
    float lo = 0.0f;
    float hi = 0.0f;
    std::uint32_t resolution = 0;
    std::vector<std::uint32_t> first;   // first cell of each triangle
    std::vector<std::uint32_t> last;    // last cell of each triangle (< first: none)
    std::vector<std::uint32_t> counts;  // triangles per cell
    // For at least parallel_grain triangles, per block of them (TriangleBlocks), the block's
    // counts as differences (see try_split), resolution + 1 per block.
    std::vector<std::uint32_t> block_counts;
};

// The blocks in which a node of at least parallel_grain triangles locates, counts and hands
// out its triangles in parallel: parallel_grain triangles each, or more where the node has
// many cells, so that the blocks' counts (resolution + 1 per block) take at most about a
// quarter of an entry per triangle. They depend on the triangle count and the resolution
// alone, not on the thread count.
struct TriangleBlocks {
    std::size_t triangles;
    std::size_t size;
    std::size_t count;

    TriangleBlocks(std::size_t n, std::uint32_t resolution) noexcept
        : triangles(n),
          size(std::max(parallel_grain, 4 * (std::size_t{resolution} + 1))),
          count((n + size - 1) / size)
    {
    }
    // Block b's triangles, [first, second).
    std::pair<std::size_t, std::size_t> range(std::size_t b) const noexcept
    {
        return {b * size, std::min(triangles, (b + 1) * size)};
    }
};

// A subtree built by one thread, in its final depth-first pre-order, with indices local to
// its own arrays: flatten() appends it to the grid and shifts them. Every subtree of fewer
// than parallel_grain triangles is built this way, without allocating per node.
struct Fragment {
    CellRef root;
    std::vector<GridNode> nodes;
    std::vector<CellRef> cells;
    std::vector<std::uint16_t> leaf_words;
};

// The record of a new node whose cells are still empty: a one-cell node holds its cell, the
// others get a block at the end of `cells`.
GridNode new_node(int axis, float lo, float hi, std::uint32_t resolution,
                  std::vector<CellRef>& cells)
{
    if (resolution == 1) return GridNode::make_one_cell(axis, lo, hi, CellRef::make_empty());
    const auto first_cell = static_cast<std::uint32_t>(cells.size());
    cells.resize(cells.size() + resolution);
    return GridNode::make(axis, lo, hi, resolution, first_cell);
}

// Stores cell `c` of node `index`, in the node's record or in its block of `cells`.
void store_cell(std::vector<GridNode>& nodes, std::vector<CellRef>& cells, std::uint32_t index,
                std::uint32_t c, CellRef cell)
{
    GridNode& node = nodes[index];
    if (node.resolution() == 1)
        node.set_only_cell(cell);
    else
        cells[node.first_cell() + c] = cell;
}

// The top of the tree, where nodes are built in parallel; flattened into SplitGrid arrays
// afterwards, in a fixed order, which is what makes the output independent of the thread
// count. Below parallel_grain triangles a cell holds a Fragment.
struct BuiltNode;
struct BuiltCell {
    CellKind kind = CellKind::Empty;
    TriangleIds triangles;               // leaf
    std::unique_ptr<BuiltNode> node;     // inner
    std::unique_ptr<Fragment> fragment;  // a serially built subtree (kind: its root's)
};
struct BuiltNode {
    int axis = 0;
    float lo = 0.0f;
    float hi = 0.0f;
    std::vector<BuiltCell> cells;
};

// What planning a node needs from its triangles' extents, gathered in one pass over them: the
// tight box of the clipped pieces and, per axis, the mean size of the whole triangles whose
// pieces are not empty (BuildConfig::min_cell_width; zero where there are none, and when
// min_cell_width is off).
struct ExtentSummary {
    Aabb tight;
    std::array<double, 3> mean_size{};
};

// The extents a node's steps read (plan_cell, distribute), one per triangle of the node, in
// the node's order: stored in an array...
struct StoredExtents {
    TriExtent* items;
    std::size_t count;

    std::size_t size() const noexcept { return count; }
    const TriExtent& operator[](std::size_t k) const noexcept { return items[k]; }
};

// ... or, at the root, computed where they are read: every triangle lies in the root's box,
// so its extent there is its own bounding box, whose corners are floats already (what
// rounded_extent gives for it: the clipped_extent of a triangle inside its box). The root
// then fills no array of them, which took a tenth of a build (docs/BENCH.md, "The root
// without an array of extents").
struct WholeExtents {
    const MeshView* mesh;
    const std::uint32_t* tris;
    std::size_t count;

    std::size_t size() const noexcept { return count; }
    TriExtent operator[](std::size_t k) const noexcept
    {
        const Vec3f a = mesh->vertex(tris[k], 0);
        const Vec3f b = mesh->vertex(tris[k], 1);
        const Vec3f c = mesh->vertex(tris[k], 2);
        // triangle_box and size_of in floats: the same box and sizes, without the conversions
        // to double, in a step the root takes up to three times per triangle. Read through
        // triangle_box and size_of, the dragon's build took 1.19 times as long (A/B, 3 rounds).
        TriExtent e;
        e.known = true;
        for (int i = 0; i < 3; ++i) {
            e.lower[i] = std::min({a[i], b[i], c[i]});
            e.upper[i] = std::max({a[i], b[i], c[i]});
            // As size_of: the difference in double, then rounded to float.
            e.size[i] = static_cast<float>(double(e.upper[i]) - double(e.lower[i]));
        }
        return e;
    }
};

// One-cell nodes around a cell (see Builder::choose_bounds): at most one per axis.
struct Bound {
    int axis = 0;
    float lo = 0.0f;
    float hi = 0.0f;
};
struct Bounds {
    std::array<Bound, 3> items;
    std::uint32_t count = 0;
};

// Working memory of one serially built subtree, reused by all its nodes: the triangles and
// extents of every node on the path from the subtree's root are stacked in `tris` and
// `extents` (a node's cells after its own range), the cell counts of those nodes in
// `cell_counts`; `split` is the candidate split of the node at hand and `cell_boxes` its
// cells' padded boxes. `tris` and `extents` never shrink: their size is the most any subtree
// built with them has stacked, and only the entries a node writes are read.
struct Scratch {
    std::vector<std::uint32_t> tris;
    std::vector<TriExtent> extents;
    std::vector<std::uint32_t> cell_counts;
    std::vector<Aabbd> cell_boxes;
    Split split;
};

// What one thread builds its serial subtrees with, one after another: the stacks, and the
// arrays a subtree is written to before it is copied into a Fragment of its exact size. Kept
// for the whole build, so that a subtree neither allocates nor fills its stacks with zeros
// once the thread's first ones have grown them.
struct Workspace {
    Scratch scratch;
    Fragment out;
};

class Builder {
public:
    Builder(const MeshView& mesh, const BuildConfig& config, const BuildProgress& progress,
            float pad)
        : mesh_(mesh), config_(config), progress_(progress), pad_(pad)
    {
        // A cell holds each triangle at most once: no node has more than the mesh's.
        small_resolutions_.resize(std::min(parallel_grain, mesh.triangle_count() + 1));
        for (std::size_t n = 0; n < small_resolutions_.size(); ++n)
            small_resolutions_[n] = node_resolution(config_, n);
    }

    // Builds the cell covering `box` for the triangles `tris` (all known to touch the padded
    // box), as a node at `depth`, or a leaf when splitting does not pay. `extents` holds, per
    // triangle, its clipped extent in this box where the parent already knew it (known).
    // `weight` is this cell's share of the whole build, for progress reports. `kept_all` counts
    // the levels in a row at which this cell received all of its parent's triangles (see
    // kept_all_limit).
    BuiltCell build_cell(const Aabb& box, TriangleIds tris,
                         ExtentArray extents, std::uint32_t depth, double weight,
                         std::uint32_t kept_all = 0)
    {
        if (tris.empty()) return {};
        if (tris.size() < parallel_grain)
            return build_fragment(box, tris, extents, depth, weight, kept_all);
        const std::size_t n = tris.size();
        const StoredExtents stored{extents.data(), n};
        Split split;
        const Plan plan = plan_cell(box, tris.data(), stored, depth, kept_all, false, split);
        if (!plan.is_node) return wrap(plan.bounds, make_leaf(std::move(tris), weight));
        return split_node(box, plan, split, std::move(tris), stored, [&] { extents = {}; },
                          weight, kept_all);
    }

    // build_cell for the root: its box holds every triangle whole (WholeExtents).
    BuiltCell build_root(const Aabb& box)
    {
        TriangleIds tris(mesh_.triangle_count());
        for (std::size_t k = 0; k < tris.size(); ++k) tris[k] = static_cast<std::uint32_t>(k);
        const WholeExtents whole{&mesh_, tris.data(), tris.size()};
        if (tris.size() < parallel_grain) {
            ExtentArray extents(tris.size());
            for (std::size_t k = 0; k < extents.size(); ++k) extents[k] = whole[k];
            return build_fragment(box, tris, extents, 0, 1.0, 0);
        }
        Split split;
        const Plan plan = plan_cell(box, tris.data(), whole, 0, 0, true, split);
        if (!plan.is_node) return wrap(plan.bounds, make_leaf(std::move(tris), 1.0));
        return split_node(box, plan, split, std::move(tris), whole, [] {}, 1.0, 0);
    }

    // Frees the threads' workspaces (once the tree is built, before it is flattened).
    void release_workspaces() { workspaces_.clear(); }

private:
    // What a cell does with its triangles: becomes a leaf, or a node split as the Split
    // beside it says; either way inside the one-cell nodes `bounds` (outermost first). A
    // node's cells lie in `bounded`, the box narrowed by them.
    struct Plan {
        bool is_node = false;
        Bounds bounds;
        Aabb bounded;
        std::uint32_t child_depth = 0;
    };

    // The decisions for a cell covering `box` with the n triangles `tris` (all known to touch
    // the padded box) at `depth`, the same for build_root, build_cell and build_serial.
    // `extents` holds n entries: per triangle its clipped extent in this box where the parent
    // already knew it; the other stored ones are clipped here, unless `all_known` says there
    // are none (so no pass looks for them). Fills `split` for a node.
    template <class Extents>
    Plan plan_cell(const Aabb& box, const std::uint32_t* tris, const Extents& extents,
                   std::uint32_t depth, std::uint32_t kept_all, bool all_known,
                   Split& split) const
    {
        Plan plan;
        const std::size_t n = extents.size();
        if (ends_as_plain_leaf(n, depth)) return plan;
        if constexpr (std::is_same_v<Extents, StoredExtents>) {
            if (!all_known) clip_unknown(box, tris, extents.items, n);
        }
        const ExtentSummary summary = summarize(extents);
        const Aabb& tight = summary.tight;
        if (tight.is_empty()) return plan;
        plan.bounded = box;
        if (n <= config_.leaf_size || kept_all >= kept_all_limit ||
            !find_split(box, summary, extents, split)) {
            plan.bounds = choose_bounds(plan.bounded, tight, -1, depth);
            return plan;
        }
        // One-cell nodes on the other axes where the triangles leave much of the box empty;
        // the node and its cells then lie in the narrowed box.
        plan.is_node = true;
        plan.bounds = choose_bounds(plan.bounded, tight, split.axis, depth);
        plan.child_depth = depth + 1 + plan.bounds.count;
        return plan;
    }

    // True for a cell of n triangles at `depth` that becomes a leaf before its triangles are
    // clipped (past max_depth, or small without bounding nodes).
    bool ends_as_plain_leaf(std::size_t n, std::uint32_t depth) const noexcept
    {
        return depth > config_.max_depth || (!config_.bounding_nodes && n <= config_.leaf_size);
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
    // once instead of once per cell (2.0 cells per straddling triangle on the dragon).
    // `cell_counts` (when clipping pieces) holds the number of triangles each cell gets: a
    // cell that becomes a leaf without looking at its extents gets no pieces. `cell_boxes`
    // is working memory for the cells' padded boxes. Returns false when a cell that looks
    // at its extents got one not computed yet (unclipped pieces, or a polygon that rounding
    // lost), so that the cells know whether they have to look for such extents.
    template <class Extents, class Put>
    bool distribute(const Aabb& box, const Plan& plan, const Split& split,
                    const std::uint32_t* tris, const Extents& extents, std::size_t begin,
                    std::size_t end, const std::uint32_t* cell_counts,
                    std::vector<Aabbd>& cell_boxes, const Put& put) const
    {
        const bool clip_pieces = cell_counts != nullptr && config_.clip_triangles;
        const Aabbd clip_box = Aabbd::from(box).padded(pad_);
        if (clip_pieces) {
            const CellMath cm(split.lo, split.hi, split.resolution);
            cell_boxes.resize(split.resolution);
            for (std::uint32_t c = 0; c < split.resolution; ++c)
                cell_boxes[c] = Aabbd::from(cm.cell_box(plan.bounded, split.axis, c)).padded(pad_);
        }
        auto wants_extents = [&](std::uint32_t c) {
            return !ends_as_plain_leaf(cell_counts[c], plan.child_depth);
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
                clipped = wanted && polygon.clip(Vec3d(mesh_.vertex(tris[k], 0)),
                                                 Vec3d(mesh_.vertex(tris[k], 1)),
                                                 Vec3d(mesh_.vertex(tris[k], 2)), clip_box);
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

    // A child's share of its parent's weight (progress reports): its share of the references.
    static double share(double weight, std::size_t count, std::size_t total_refs) noexcept
    {
        return weight * static_cast<double>(count) / static_cast<double>(total_refs);
    }

    // A cell of fewer than parallel_grain triangles: its whole subtree, built by this thread
    // in the thread's workspace (no task of the build runs inside it: it calls no parallel
    // algorithm, and report() isolates the progress callback).
    BuiltCell build_fragment(const Aabb& box, const TriangleIds& tris,
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
        // Fragments wait for flatten() until the whole tree is built: no spare capacity.
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
    // cells as one block, then its children), which is the order flatten() gives the parallel
    // part. `top` is the first free place on the stacks; the children's triangles are stacked
    // there, cell after cell. `all_known`: this cell's extents are all computed, or it becomes a
    // leaf without reading them (ends_as_plain_leaf).
    CellRef build_serial(const Aabb& box, std::size_t begin, std::size_t n, std::size_t top,
                         std::uint32_t depth, double weight, std::uint32_t kept_all,
                         bool all_known, Scratch& s, Fragment& out)
    {
        if (n == 0) return CellRef::make_empty();
        const Plan plan =
            plan_cell(box, s.tris.data() + begin, StoredExtents{s.extents.data() + begin, n},
                      depth, kept_all, all_known, s.split);
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

    static void emit_bounds(const Bounds& bounds, Chain& chain, Fragment& out)
    {
        for (std::uint32_t b = 0; b < bounds.count; ++b)
            chain.add_node(bounds.items[b].axis, bounds.items[b].lo, bounds.items[b].hi, 1, out);
    }

    CellRef emit_leaf(const Scratch& s, std::size_t begin, std::size_t n, double weight,
                      Fragment& out)
    {
        // The ids are strictly ascending, as append_leaf needs: the root's list counts up and
        // every hand-out to the cells keeps the order (see distribute).
        const std::uint32_t first =
            append_leaf(out.leaf_words, std::span(s.tris).subspan(begin, n));
        report(weight);
        return CellRef::make_leaf(first);
    }

    // The rest of build_cell (and build_root) for a node planned as `plan` and `split`: hands
    // its triangles to the cells, calls `release` (which frees the node's stored extents) and
    // builds the cells in parallel.
    template <class Extents, class Release>
    BuiltCell split_node(const Aabb& box, const Plan& plan, Split& split, TriangleIds tris,
                         const Extents& extents, const Release& release, double weight,
                         std::uint32_t kept_all)
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
    void hand_out(const Aabb& box, const Plan& plan, const Split& split, const TriangleIds& tris,
                  const Extents& extents, std::vector<TriangleIds>& cell_tris,
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

    // Clips the triangles whose extent in `box` is not known yet.
    void clip_unknown(const Aabb& box, const std::uint32_t* tris, TriExtent* extents,
                      std::size_t n) const
    {
        const Aabbd clip_box = Aabbd::from(box).padded(pad_);
        run(n, [&](std::size_t begin, std::size_t end) {
            for (std::size_t k = begin; k < end; ++k)
                if (!extents[k].known) extents[k] = clipped_extent(tris[k], clip_box);
        });
    }

    // The split of the first axis, by decreasing extent of the clipped triangles, that makes
    // progress (the others are tried only if the longest makes none).
    template <class Extents>
    bool find_split(const Aabb& box, const ExtentSummary& summary, const Extents& extents,
                    Split& split) const
    {
        const Aabb& tight = summary.tight;
        // Insertion sort, stable like std::stable_sort, which allocates a buffer on every call
        // (once per node).
        std::array<int, 3> axes{0, 1, 2};
        for (std::size_t i = 1; i < axes.size(); ++i)
            for (std::size_t j = i; j > 0 && tight.extent(axes[j]) > tight.extent(axes[j - 1]); --j)
                std::swap(axes[j], axes[j - 1]);
        for (int axis : axes) {
            if (!(tight.extent(axis) > 0.0f)) break;
            if (try_split(box, summary, axis, extents, split)) return true;
        }
        return false;
    }

    // The one-cell nodes worth putting around a cell of box `box` whose clipped triangles
    // span `tight`, outermost first, on axes other than `skip`: greedily the axis whose
    // planes cut the box's surface area most, while the cut is at least
    // bounding_node_gain of it (the surface-area model's chance that a ray through the box
    // reaches the contents). Narrows `box` to the planes. Each such node is one level: none
    // is added past max_depth. An axis once narrowed cannot cut the area again, so there are
    // at most three.
    Bounds choose_bounds(Aabb& box, const Aabb& tight, int skip, std::uint32_t depth) const
    {
        Bounds bounds;
        if (!config_.bounding_nodes) return bounds;
        while (bounds.count < bounds.items.size()) {
            if (depth + bounds.count + (skip >= 0 ? 1 : 0) > config_.max_depth) break;
            const double area = box.surface_area();
            if (!(area > 0.0)) break;
            Bound best;
            double best_area = area * (1.0 - bounding_node_gain);
            bool found = false;
            for (int b = 0; b < 3; ++b) {
                if (b == skip) continue;
                Bound candidate{b, std::max(box.lower[b], tight.lower[b] - pad_), 0.0f};
                candidate.hi = std::max(candidate.lo, std::min(box.upper[b], tight.upper[b] + pad_));
                Aabb narrowed = box;
                narrowed.lower[b] = candidate.lo;
                narrowed.upper[b] = candidate.hi;
                const double narrowed_area = narrowed.surface_area();
                if (narrowed_area < best_area) {
                    best_area = narrowed_area;
                    best = candidate;
                    found = true;
                }
            }
            if (!found) break;
            box.lower[best.axis] = best.lo;
            box.upper[best.axis] = best.hi;
            bounds.items[bounds.count++] = best;
        }
        return bounds;
    }

    // `inner` inside the one-cell nodes `bounds` (outermost first).
    static BuiltCell wrap(const Bounds& bounds, BuiltCell inner)
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

    // Fills `split` for `axis` and says whether it makes progress (BuildConfig's
    // no_progress_fraction and stop_by_cost).
    template <class Extents>
    bool try_split(const Aabb& box, const ExtentSummary& summary, int axis,
                   const Extents& extents, Split& split) const
    {
        const Aabb& tight = summary.tight;
        const std::size_t n = extents.size();
        // Bounding planes: the tight extent widened by the pad (so points a few ulps off a
        // triangle stay inside), kept within the node's box.
        split.axis = axis;
        split.lo = std::max(box.lower[axis], tight.lower[axis] - pad_);
        split.hi = std::max(split.lo, std::min(box.upper[axis], tight.upper[axis] + pad_));
        if (!config_.bounding_planes) {
            split.lo = box.lower[axis];
            split.hi = box.upper[axis];
        }
        split.resolution = n < small_resolutions_.size() ? small_resolutions_[n]
                                                         : node_resolution(config_, n);
        if (config_.min_cell_width > 0.0) {
            // The whole triangles' extent, not the clipped one: clipped pieces shrink with the
            // cells, and a cap on them would let every level slice finer than the last.
            const double mean_extent = summary.mean_size[static_cast<std::size_t>(axis)];
            const double cap = (double(split.hi) - split.lo) / (config_.min_cell_width * mean_extent);
            if (mean_extent > 0.0 && cap < split.resolution)
                split.resolution = static_cast<std::uint32_t>(std::max(2.0, std::floor(cap)));
        }
        if (split.resolution < 2) return false;
        const CellMath cm(split.lo, split.hi, split.resolution);

        // Cell range of each triangle: the cells whose padded slab its clipped extent touches
        // (none, first > last, for an empty one), and the cells' triangles counted in the same
        // pass: by the node, or from parallel_grain triangles up by each block of them, in
        // parallel (the blocks' counts are summed after, and tell hand_out where each block
        // writes).
        split.first.resize(n);
        split.last.resize(n);
        // The counts are summed from differences (+1 at a triangle's first cell, -1 past its
        // last: an empty extent's cancel), two adds per triangle without a loop over its
        // cells, whose length the branch predictor cannot know. Unsigned arithmetic wraps,
        // and every prefix sum is a count.
        const std::size_t stride = split.resolution + 1;
        split.counts.assign(stride, 0);
        // The coordinates are gathered in blocks, so that locate_cells finds four triangles'
        // cells at once (docs/BENCH.md, "Locating four triangles at once"). An empty extent's
        // coordinates are zero; its cells are thrown away.
        auto locate = [&](std::size_t begin, std::size_t end, std::uint32_t* counts) {
            constexpr std::size_t block = 64;
            std::array<float, block> lower;
            std::array<float, block> upper;
            for (std::size_t b = begin; b < end; b += block) {
                const std::size_t m = std::min(block, end - b);
                for (std::size_t j = 0; j < m; ++j) {
                    const TriExtent& e = extents[b + j];
                    lower[j] = e.lower[axis] - pad_;
                    upper[j] = e.upper[axis] + pad_;
                }
                locate_cells(cm, lower.data(), upper.data(), m, split.first.data() + b,
                             split.last.data() + b);
                for (std::size_t k = b; k < b + m; ++k) {
                    if (extents[k].is_empty) {
                        split.first[k] = 1;
                        split.last[k] = 0;
                    }
                    ++counts[split.first[k]];
                    --counts[split.last[k] + 1];
                }
            }
        };
        if (n < parallel_grain) {
            locate(0, n, split.counts.data());
        } else {
            const TriangleBlocks blocks(n, split.resolution);
            split.block_counts.assign(blocks.count * stride, 0);
            tbb::parallel_for(std::size_t{0}, blocks.count, [&](std::size_t b) {
                const auto [begin, end] = blocks.range(b);
                locate(begin, end, split.block_counts.data() + b * stride);
            });
            for (std::size_t b = 0; b < blocks.count; ++b)
                for (std::size_t c = 0; c < stride; ++c)
                    split.counts[c] += split.block_counts[b * stride + c];
        }
        for (std::uint32_t c = 1; c < split.resolution; ++c) split.counts[c] += split.counts[c - 1];
        split.counts.pop_back();

        // Progress by counts: at most one cell may keep nearly everything, and not all.
        const double heavy_limit = config_.no_progress_fraction * static_cast<double>(n);
        std::size_t heavy = 0, nonempty = 0;
        for (std::uint32_t c : split.counts) {
            nonempty += c > 0 ? 1 : 0;
            // A cell that would get every triangle is heavy whatever the fraction: with
            // no_progress_fraction = 1 (in range) "more than n" never holds, and copies of one
            // triangle, or a shared edge, were then split into every cell down to max_depth,
            // resolution^depth nodes (found by tests/fuzz/build_trace_fuzz).
            heavy += static_cast<double>(c) > heavy_limit || c == n ? 1 : 0;
        }
        if (nonempty == 0 || heavy >= 2 || heavy == nonempty) return false;
        if (!config_.stop_by_cost) return true;

        // Progress by cost (the model of stats.hpp with unit constants): entering the node,
        // stepping its cells and testing each cell's triangles, against testing all n here.
        const double box_area = box.surface_area();
        auto probability = [&](const Aabb& b) {
            return box_area > 0.0 ? b.surface_area() / box_area : 1.0;
        };
        Aabb slab = box;
        slab.lower[axis] = split.lo;
        slab.upper[axis] = split.hi;
        double cost =
            1.0 + probability(slab) * expected_cells_crossed(slab, axis, split.resolution);
        for (std::uint32_t c = 0; c < split.resolution; ++c)
            if (split.counts[c] > 0) cost += probability(cm.cell_box(box, axis, c)) * split.counts[c];
        return cost < static_cast<double>(n);
    }

    template <class F>
    void run(std::size_t n, const F& body) const
    {
        if (n < parallel_grain) {
            body(0, n);
            return;
        }
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, parallel_grain / 4),
                          [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
    }

    // A triangle's bounding box `whole` intersected with `clip_box`
    // (BuildConfig::clip_triangles off); false when they do not touch.
    static bool clip_triangle_box(const Aabbd& whole, const Aabbd& clip_box, Aabbd& out) noexcept
    {
        for (int k = 0; k < 3; ++k) {
            out.lower[k] = std::max(whole.lower[k], clip_box.lower[k]);
            out.upper[k] = std::min(whole.upper[k], clip_box.upper[k]);
            if (out.lower[k] > out.upper[k]) return false;
        }
        return true;
    }

    TriExtent clipped_extent(std::uint32_t tri, const Aabbd& clip_box) const noexcept
    {
        const Vec3d a(mesh_.vertex(tri, 0));
        const Vec3d b(mesh_.vertex(tri, 1));
        const Vec3d c(mesh_.vertex(tri, 2));
        const Aabbd whole = triangle_box(a, b, c);
        Aabbd clipped;
        if (config_.clip_triangles ? !clip_triangle_bounds(a, b, c, clip_box, clipped)
                                   : !clip_triangle_box(whole, clip_box, clipped))
            return empty_extent();
        return rounded_extent(clipped, size_of(whole));
    }

    // A whole triangle's size per axis (TriExtent::size) from its bounding box.
    static Vec3f size_of(const Aabbd& whole) noexcept
    {
        Vec3f size;
        for (int k = 0; k < 3; ++k) size[k] = static_cast<float>(whole.upper[k] - whole.lower[k]);
        return size;
    }

    // The extent of a clipped piece in floats, rounded outward so it still contains it.
    static TriExtent rounded_extent(const Aabbd& clipped, Vec3f size) noexcept
    {
        TriExtent e;
        e.known = true;
        for (int k = 0; k < 3; ++k) {
            e.lower[k] = float_not_above(clipped.lower[k]);
            e.upper[k] = float_not_below(clipped.upper[k]);
        }
        e.size = size;
        return e;
    }
    static TriExtent empty_extent() noexcept
    {
        TriExtent e;
        e.known = true;
        e.is_empty = true;
        return e;
    }

    // The tight box (min and max are exact, so any order gives the same box, up to the sign
    // of a zero, which the pad added to each side of it erases) and the mean sizes, in one
    // pass. Below parallel_grain triangles the sizes are summed in the triangles' order; from
    // parallel_grain up in parallel, in pieces that the triangle count alone fixes (halved
    // until at most parallel_grain), added in a fixed order
    // (tbb::parallel_deterministic_reduce): either way the sums do not depend on the thread
    // count.
    template <class Extents>
    ExtentSummary summarize(const Extents& extents) const
    {
        struct Sums {
            Aabb tight;
            std::array<double, 3> size{};
            std::size_t kept = 0;
        };
        const bool sizes = config_.min_cell_width > 0.0;
        auto body = [&](const tbb::blocked_range<std::size_t>& r, Sums sums) {
            for (std::size_t k = r.begin(); k < r.end(); ++k) {
                const TriExtent& e = extents[k];
                if (e.is_empty) continue;
                sums.tight.extend(Aabb{e.lower, e.upper});
                if (!sizes) continue;
                for (int i = 0; i < 3; ++i) sums.size[static_cast<std::size_t>(i)] += e.size[i];
                ++sums.kept;
            }
            return sums;
        };
        const tbb::blocked_range<std::size_t> all(0, extents.size(), parallel_grain);
        const Sums sums =
            extents.size() < parallel_grain
                ? body(all, Sums{})
                : tbb::parallel_deterministic_reduce(all, Sums{}, body, [](Sums a, const Sums& b) {
                      a.tight.extend(b.tight);
                      for (std::size_t i = 0; i < 3; ++i) a.size[i] += b.size[i];
                      a.kept += b.kept;
                      return a;
                  });
        ExtentSummary summary;
        summary.tight = sums.tight;
        if (sums.kept > 0)
            for (std::size_t i = 0; i < 3; ++i)
                summary.mean_size[i] = sums.size[i] / static_cast<double>(sums.kept);
        return summary;
    }

    BuiltCell make_leaf(TriangleIds tris, double weight)
    {
        BuiltCell cell;
        cell.kind = CellKind::Leaf;
        cell.triangles = std::move(tris);
        report(weight);
        return cell;
    }

    void report(double weight)
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

    const MeshView& mesh_;
    const BuildConfig& config_;
    const BuildProgress& progress_;
    const float pad_;
    // node_resolution of the serial subtrees' nodes, which it would otherwise compute (with
    // an exp) once per node and axis tried.
    std::vector<std::uint32_t> small_resolutions_;
    tbb::enumerable_thread_specific<Workspace> workspaces_;
    std::mutex progress_mutex_;
    double done_ = 0.0;
    double last_reported_ = 0.0;
};

// A fragment's cell with its indices shifted past the grid's `node_base` nodes and
// `word_base` leaf words.
CellRef shifted(CellRef cell, std::uint32_t node_base, std::uint32_t word_base)
{
    if (cell.is_inner())
        return CellRef::make_inner(cell.child() + node_base, cell.has_one_cell_child() ? 1 : 2);
    if (cell.is_leaf()) return CellRef::make_leaf(cell.first_word() + word_base);
    return cell;
}

// Appends a serially built subtree, already in pre-order, and releases it.
CellRef append_fragment(Fragment& fragment, SplitGrid& grid)
{
    if (grid.leaf_words.size() + fragment.leaf_words.size() > std::size_t{max_cell_index} + 1)
        throw InputError("Split Grid too large: more than 2^30 leaf words");
    if (grid.nodes.size() + fragment.nodes.size() > std::size_t{max_cell_index} + 1 ||
        grid.cells.size() + fragment.cells.size() > std::size_t{0xFFFFFFFFu})
        throw InputError("Split Grid too large: more than 2^30 nodes or 2^32 cells");
    const auto node_base = static_cast<std::uint32_t>(grid.nodes.size());
    const auto cell_base = static_cast<std::uint32_t>(grid.cells.size());
    const auto word_base = static_cast<std::uint32_t>(grid.leaf_words.size());
    for (const GridNode& node : fragment.nodes) {
        const std::uint32_t cells = node.resolution() == 1
                                        ? shifted(node.only_cell(), node_base, word_base).raw_bits()
                                        : node.first_cell() + cell_base;
        grid.nodes.push_back(GridNode::from_raw(node.lo, node.hi, cells, node.axis_res_bits()));
    }
    for (const CellRef cell : fragment.cells) grid.cells.push_back(shifted(cell, node_base, word_base));
    grid.leaf_words.insert(grid.leaf_words.end(), fragment.leaf_words.begin(),
                           fragment.leaf_words.end());
    const CellRef root = shifted(fragment.root, node_base, word_base);
    fragment = {};
    return root;
}

// Numbers of nodes, cells and leaf words under `cell`.
struct GridSize {
    std::size_t nodes = 0;
    std::size_t cells = 0;
    std::size_t leaf_words = 0;
};
void add_size(const BuiltCell& cell, GridSize& size)
{
    if (cell.fragment) {
        size.nodes += cell.fragment->nodes.size();
        size.cells += cell.fragment->cells.size();
        size.leaf_words += cell.fragment->leaf_words.size();
    } else if (cell.kind == CellKind::Leaf) {
        size.leaf_words += leaf_word_count(cell.triangles);
    } else if (cell.kind == CellKind::Inner) {
        size.nodes += 1;
        if (cell.node->cells.size() >= 2) size.cells += cell.node->cells.size();
        for (const BuiltCell& child : cell.node->cells) add_size(child, size);
    }
}

// Depth-first pre-order: a node's record, then its cells as one block, then its children.
CellRef flatten(BuiltCell& cell, SplitGrid& grid)
{
    if (cell.fragment) {
        const CellRef root = append_fragment(*cell.fragment, grid);
        cell.fragment.reset();
        return root;
    }
    switch (cell.kind) {
    case CellKind::Empty:
        return CellRef::make_empty();
    case CellKind::Leaf: {
        if (grid.leaf_words.size() + leaf_word_count(cell.triangles) >
            std::size_t{max_cell_index} + 1)
            throw InputError("Split Grid too large: more than 2^30 leaf words");
        // Strictly ascending, as emit_leaf's (append_leaf needs it).
        const std::uint32_t first = append_leaf(grid.leaf_words, cell.triangles);
        cell.triangles = {};
        return CellRef::make_leaf(first);
    }
    case CellKind::Inner:
        break;
    }
    BuiltNode& node = *cell.node;
    if (grid.nodes.size() > max_cell_index ||
        grid.cells.size() + node.cells.size() > std::size_t{0xFFFFFFFFu})
        throw InputError("Split Grid too large: more than 2^30 nodes or 2^32 cells");
    const auto index = static_cast<std::uint32_t>(grid.nodes.size());
    const auto resolution = static_cast<std::uint32_t>(node.cells.size());
    grid.nodes.push_back(new_node(node.axis, node.lo, node.hi, resolution, grid.cells));
    for (std::uint32_t c = 0; c < resolution; ++c)
        store_cell(grid.nodes, grid.cells, index, c, flatten(node.cells[c], grid));
    cell.node.reset();
    return CellRef::make_inner(index, resolution);
}

}  // namespace

float boundary_pad(const Aabb& scene) noexcept
{
    float magnitude = 0.0f;
    for (int k = 0; k < 3; ++k)
        magnitude = std::max({magnitude, std::abs(scene.lower[k]), std::abs(scene.upper[k])});
    // Never below a normal float, so the pad survives being added to coordinates near zero.
    return std::max(magnitude * 0x1p-20f, std::numeric_limits<float>::min() * 64.0f);
}

Aabb padded_root_box(const Aabb& scene, float pad) noexcept
{
    constexpr float float_max = std::numeric_limits<float>::max();
    Aabb box;
    for (int k = 0; k < 3; ++k) {
        box.lower[k] = std::max(-float_max, scene.lower[k] - pad);
        box.upper[k] = std::min(float_max, scene.upper[k] + pad);
    }
    return box;
}

SplitGrid build_split_grid(const MeshView& mesh, const BuildConfig& config,
                           const BuildProgress& progress)
{
    SplitGrid grid;
    rebuild_split_grid(grid, mesh, config, progress);
    return grid;
}

void rebuild_split_grid(SplitGrid& grid, const MeshView& mesh, const BuildConfig& config,
                        const BuildProgress& progress)
{
    validate(config);
    if (mesh.triangle_count() > std::size_t{max_referenced_triangle} + 1)
        throw InputError("mesh has more than 2^30 triangles");
    // Every step runs in the build's arena, the mesh's check and box too (in parallel for a
    // large mesh), so that `threads` bounds all of it.
    tbb::task_arena arena(config.threads == 0 ? tbb::task_arena::automatic
                                              : static_cast<int>(config.threads));
    Aabb scene;
    arena.execute([&] { scene = checked_bounds(mesh); });

    // The arrays are emptied, not freed: their memory is what a rebuild reuses.
    grid.nodes.clear();
    grid.cells.clear();
    grid.leaf_words.clear();
    grid.root = CellRef{};
    grid.root_box = Aabb{};
    grid.config = config;
    grid.config.threads = 0;  // the thread count does not change the result, so it is not kept
    grid.triangle_count = static_cast<std::uint32_t>(mesh.triangle_count());
    if (mesh.triangle_count() == 0) return;

    const float pad = boundary_pad(scene);
    grid.root_box = padded_root_box(scene, pad);

    Builder builder(mesh, config, progress, pad);
    BuiltCell root;
    arena.execute([&] {
        root = builder.build_root(grid.root_box);
    });
    builder.release_workspaces();
    // The arrays get their final size at once: growing them by doubling would hold up to
    // three times their size while the built tree is still held too.
    GridSize size;
    add_size(root, size);
    if (size.nodes > std::size_t{max_cell_index} + 1 || size.cells > std::size_t{0xFFFFFFFFu})
        throw InputError("Split Grid too large: more than 2^30 nodes or 2^32 cells");
    if (size.leaf_words > std::size_t{max_cell_index} + 1)
        throw InputError("Split Grid too large: more than 2^30 leaf words");
    grid.nodes.reserve(size.nodes);
    grid.cells.reserve(size.cells);
    grid.leaf_words.reserve(size.leaf_words);
    grid.root = flatten(root, grid);
}

}  // namespace sg
