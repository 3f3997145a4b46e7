#pragma once

// The Split Grid builder's third seam: building the tree. Each cell is planned
// (split_planning.hpp), its triangles handed to its cells with their extents there
// (distribute), and the cells built in turn: in parallel at the top of the tree, as
// BuiltNode objects (split_node, hand_out), and below parallel_grain triangles by one thread
// straight into the grid's layout (build_serial, a Fragment each). tree_assembly.hpp lays
// the result out.

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "build_extents.hpp"
#include "split_planning.hpp"
#include "splitgrid/builder.hpp"
#include "tree_assembly.hpp"

namespace sg::detail {

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

// Builds the tree of one build: build_root once, inside the build's task arena.
class NodeBuilder {
public:
    NodeBuilder(const BuildContext& context, const BuildProgress& progress);

    // The root cell, covering `box` (the padded scene box), which holds every triangle whole
    // (WholeExtents).
    [[nodiscard]] BuiltCell build_root(const Aabb& box);

    // Frees the threads' workspaces (once the tree is built, before it is assembled).
    void release_workspaces() { workspaces_.clear(); }

private:
    BuiltCell build_cell(const Aabb& box, TriangleIds tris, ExtentArray extents,
                         std::uint32_t depth, double weight, std::uint32_t kept_all = 0);
    template <class Extents, class Release>
    BuiltCell split_node(const Aabb& box, const Plan& plan, Split& split, TriangleIds tris,
                         const Extents& extents, const Release& release, double weight,
                         std::uint32_t kept_all);
    template <class Extents>
    void hand_out(const Aabb& box, const Plan& plan, const Split& split, const TriangleIds& tris,
                  const Extents& extents, std::vector<TriangleIds>& cell_tris,
                  std::vector<ExtentArray>& cell_extents) const;
    template <class Extents, class Put>
    bool distribute(const Aabb& box, const Plan& plan, const Split& split,
                    const std::uint32_t* tris, const Extents& extents, std::size_t begin,
                    std::size_t end, const std::uint32_t* cell_counts,
                    std::vector<Aabbd>& cell_boxes, const Put& put) const;
    BuiltCell build_fragment(const Aabb& box, const TriangleIds& tris,
                             const ExtentArray& extents, std::uint32_t depth, double weight,
                             std::uint32_t kept_all);
    CellRef build_serial(const Aabb& box, std::size_t begin, std::size_t n, std::size_t top,
                         std::uint32_t depth, double weight, std::uint32_t kept_all,
                         bool all_known, Scratch& s, Fragment& out);
    CellRef emit_leaf(const Scratch& s, std::size_t begin, std::size_t n, double weight,
                      Fragment& out);
    BuiltCell make_leaf(TriangleIds tris, double weight);
    void report(double weight);

    const BuildContext context_;
    const SplitPlanner planner_;
    const BuildProgress& progress_;
    tbb::enumerable_thread_specific<Workspace> workspaces_;
    std::mutex progress_mutex_;
    double done_ = 0.0;
    double last_reported_ = 0.0;
};

}  // namespace sg::detail
