#pragma once

// The Split Grid builder's second seam: what a cell does with its triangles. It becomes a
// leaf or a node; a node gets its axis, bounding planes and resolution (find_split,
// try_split), each triangle its range of cells, and the cell the one-cell bounding nodes
// around it (choose_bounds). Nothing here moves a triangle: node_building.hpp hands them out.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "build_extents.hpp"
#include "splitgrid/aabb.hpp"

namespace sg::detail {

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

// One-cell nodes around a cell (see SplitPlanner::choose_bounds): at most one per axis.
struct Bound {
    int axis = 0;
    float lo = 0.0f;
    float hi = 0.0f;
};
struct Bounds {
    std::array<Bound, 3> items;
    std::uint32_t count = 0;
};

// What a cell does with its triangles: becomes a leaf, or a node split as the Split
// beside it says; either way inside the one-cell nodes `bounds` (outermost first). A
// node's cells lie in `bounded`, the box narrowed by them.
struct Plan {
    bool is_node = false;
    Bounds bounds;
    Aabb bounded;
    std::uint32_t child_depth = 0;
};

// The decisions of one build, the same for every cell whichever thread builds it.
class SplitPlanner {
public:
    explicit SplitPlanner(const BuildContext& context);

    // The decisions for a cell covering `box` with the n triangles `tris` (all known to touch
    // the padded box) at `depth`, the same for the root, the parallel top of the tree and
    // the serial subtrees. `extents` holds n entries: per triangle its clipped extent in this
    // box where the parent already knew it; the other stored ones are clipped here, unless
    // `all_known` says there are none (so no pass looks for them). `kept_all` counts the
    // levels in a row at which this cell received all of its parent's triangles. Fills
    // `split` for a node. Defined for StoredExtents and WholeExtents.
    template <class Extents>
    [[nodiscard]] Plan plan_cell(const Aabb& box, const std::uint32_t* tris,
                                 const Extents& extents, std::uint32_t depth,
                                 std::uint32_t kept_all, bool all_known, Split& split) const;

    // True for a cell of n triangles at `depth` that becomes a leaf before its triangles are
    // clipped (past max_depth, or small without bounding nodes).
    [[nodiscard]] bool ends_as_plain_leaf(std::size_t n, std::uint32_t depth) const noexcept
    {
        const BuildConfig& config = context_.config;
        return depth > config.max_depth || (!config.bounding_nodes && n <= config.leaf_size);
    }

private:
    template <class Extents>
    bool find_split(const Aabb& box, const ExtentSummary& summary, const Extents& extents,
                    Split& split) const;
    template <class Extents>
    bool try_split(const Aabb& box, const ExtentSummary& summary, int axis,
                   const Extents& extents, Split& split) const;
    Bounds choose_bounds(Aabb& box, const Aabb& tight, int skip, std::uint32_t depth) const;

    const BuildContext context_;
    // node_resolution of the serial subtrees' nodes, which it would otherwise compute (with
    // an exp) once per node and axis tried.
    std::vector<std::uint32_t> small_resolutions_;
};

}  // namespace sg::detail
