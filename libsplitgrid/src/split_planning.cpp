#include "split_planning.hpp"

#include <cmath>
#include <type_traits>

#include <tbb/parallel_for.h>

#include "splitgrid/cell_math.hpp"
#include "splitgrid/resolution.hpp"
#include "splitgrid/stats.hpp"

namespace sg::detail {
namespace {

// A one-cell bounding node is added where it cuts a cell's surface area by at least this
// fraction (BuildConfig::bounding_nodes): counted on seven scenes, a tenth costs bytes for no
// fewer instructions per ray, a half costs instructions (docs/notebook/structure.md, "Lever 4:
// bounding nodes (one-cell nodes on the other axes)").
constexpr double bounding_node_gain = 0.25;

// A cell becomes a leaf when it received every one of its parent's triangles this many levels
// in a row. Such a cell holds a place where all of them meet (a fan around a vertex, a shared
// edge or corner): each split there repeats the last at a smaller scale, with the same
// triangles in the cell around the meeting point, down to max_depth. 1 would put a whole fan
// into the cell around its centre, where many rays pass; 2 ends the chains and leaves the
// work per ray as it was (docs/notebook/structure.md, "Lever 4b: a cell that keeps all of its
// parent's triangles twice in a row is a leaf", has the counts for 1, 2 and no limit).
constexpr std::uint32_t kept_all_limit = 2;

}  // namespace

SplitPlanner::SplitPlanner(const BuildContext& context) : context_(context)
{
    // A cell holds each triangle at most once: no node has more than the mesh's.
    small_resolutions_.resize(std::min(parallel_grain, context.mesh.triangle_count() + 1));
    for (std::size_t n = 0; n < small_resolutions_.size(); ++n)
        small_resolutions_[n] = node_resolution(context.config, n);
}

template <class Extents>
Plan SplitPlanner::plan_cell(const Aabb& box, const std::uint32_t* tris, const Extents& extents,
                             std::uint32_t depth, std::uint32_t kept_all, bool all_known,
                             Split& split) const
{
    Plan plan;
    const std::size_t n = extents.size();
    if (ends_as_plain_leaf(n, depth)) return plan;
    if constexpr (std::is_same_v<Extents, StoredExtents>) {
        if (!all_known) clip_unknown(context_, box, tris, extents.items, n);
    }
    const ExtentSummary summary = summarize(context_, extents);
    const Aabb& tight = summary.tight;
    if (tight.is_empty()) return plan;
    plan.bounded = box;
    if (n <= context_.config.leaf_size || kept_all >= kept_all_limit ||
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

// The split of the first axis, by decreasing extent of the clipped triangles, that makes
// progress (the others are tried only if the longest makes none).
template <class Extents>
bool SplitPlanner::find_split(const Aabb& box, const ExtentSummary& summary,
                              const Extents& extents, Split& split) const
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

// Fills `split` for `axis` and says whether it makes progress (BuildConfig's
// no_progress_fraction and stop_by_cost).
template <class Extents>
bool SplitPlanner::try_split(const Aabb& box, const ExtentSummary& summary, int axis,
                             const Extents& extents, Split& split) const
{
    const BuildConfig& config = context_.config;
    const float pad = context_.pad;
    const Aabb& tight = summary.tight;
    const std::size_t n = extents.size();
    // Bounding planes: the tight extent widened by the pad (so points a few ulps off a
    // triangle stay inside), kept within the node's box.
    split.axis = axis;
    split.lo = std::max(box.lower[axis], tight.lower[axis] - pad);
    split.hi = std::max(split.lo, std::min(box.upper[axis], tight.upper[axis] + pad));
    if (!config.bounding_planes) {
        split.lo = box.lower[axis];
        split.hi = box.upper[axis];
    }
    split.resolution = n < small_resolutions_.size() ? small_resolutions_[n]
                                                     : node_resolution(config, n);
    if (config.min_cell_width > 0.0) {
        // The whole triangles' extent, not the clipped one: clipped pieces shrink with the
        // cells, and a cap on them would let every level slice finer than the last.
        const double mean_extent = summary.mean_size[static_cast<std::size_t>(axis)];
        const double cap = (double(split.hi) - split.lo) / (config.min_cell_width * mean_extent);
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
    // cells at once (docs/notebook/build.md, "Locating four triangles at once"). An empty
    // extent's coordinates are zero; its cells are thrown away.
    auto locate = [&](std::size_t begin, std::size_t end, std::uint32_t* counts) {
        constexpr std::size_t block = 64;
        std::array<float, block> lower;
        std::array<float, block> upper;
        for (std::size_t b = begin; b < end; b += block) {
            const std::size_t m = std::min(block, end - b);
            for (std::size_t j = 0; j < m; ++j) {
                const TriExtent& e = extents[b + j];
                lower[j] = e.lower[axis] - pad;
                upper[j] = e.upper[axis] + pad;
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
    const double heavy_limit = config.no_progress_fraction * static_cast<double>(n);
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
    if (!config.stop_by_cost) return true;

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

// The one-cell nodes worth putting around a cell of box `box` whose clipped triangles
// span `tight`, outermost first, on axes other than `skip`: greedily the axis whose
// planes cut the box's surface area most, while the cut is at least
// bounding_node_gain of it (the surface-area model's chance that a ray through the box
// reaches the contents). Narrows `box` to the planes. Each such node is one level: none
// is added past max_depth. An axis once narrowed cannot cut the area again, so there are
// at most three.
Bounds SplitPlanner::choose_bounds(Aabb& box, const Aabb& tight, int skip,
                                   std::uint32_t depth) const
{
    const BuildConfig& config = context_.config;
    const float pad = context_.pad;
    Bounds bounds;
    if (!config.bounding_nodes) return bounds;
    while (bounds.count < bounds.items.size()) {
        if (depth + bounds.count + (skip >= 0 ? 1 : 0) > config.max_depth) break;
        const double area = box.surface_area();
        if (!(area > 0.0)) break;
        Bound best;
        double best_area = area * (1.0 - bounding_node_gain);
        bool found = false;
        for (int b = 0; b < 3; ++b) {
            if (b == skip) continue;
            Bound candidate{b, std::max(box.lower[b], tight.lower[b] - pad), 0.0f};
            candidate.hi = std::max(candidate.lo, std::min(box.upper[b], tight.upper[b] + pad));
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

template Plan SplitPlanner::plan_cell(const Aabb&, const std::uint32_t*, const StoredExtents&,
                                      std::uint32_t, std::uint32_t, bool, Split&) const;
template Plan SplitPlanner::plan_cell(const Aabb&, const std::uint32_t*, const WholeExtents&,
                                      std::uint32_t, std::uint32_t, bool, Split&) const;

}  // namespace sg::detail
