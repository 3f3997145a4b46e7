#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/structure_queries.hpp"

namespace sg {

/// Deepest kd-tree the traverser's fixed stack supports (KdTreeConfig::max_depth's range).
inline constexpr std::uint32_t kd_max_supported_depth = 64;

/// Parameters of the kd-tree (a comparison structure for sg-bench; docs/BASELINES.md).
///
/// Surface area heuristic (Wald and Havran, "On building fast kd-trees for ray tracing, and
/// on doing that in O(N log N)", IEEE RT 2006): splitting a node of box B with n triangles at
/// a plane with nl triangles below and nr above costs
///   traversal_cost + intersection_cost * (SA(Bl) nl + SA(Br) nr) / SA(B),
/// times (1 - empty_bonus) when nl or nr is 0; keeping the node as a leaf costs
/// intersection_cost * n. The cheapest plane of the three axes is taken if it beats the leaf.
/// Only the ratio of the two costs matters.
struct KdTreeConfig {
    /// Cost of one traversal step, relative to intersection_cost. Range (0, 1e6].
    /// Wald and Havran use 15 against 20. With clipped ("perfect") extents that ratio splits
    /// around shared vertices down to the depth limit on scans. 3 against 1 traces as fast
    /// there (traversal is memory-bound) with a much smaller tree, built faster
    /// (docs/BASELINES.md, "kd-tree", has the figures).
    double traversal_cost = 3.0;
    /// Cost of one ray/triangle test. Range (0, 1e6].
    double intersection_cost = 1.0;
    /// Discount of a split that cuts off empty space (one side holds no triangle), which
    /// lets the tree wrap geometry tightly. Range [0, 1). 0.2 as in Wald and Havran.
    double empty_bonus = 0.2;
    /// Deepest leaf (the root is depth 0); 0 means automatic: round(8 + 1.3 log2 N) (Havran's
    /// rule), at most 64. Range [0, 64].
    std::uint32_t max_depth = 0;
    /// A node with at most this many triangles becomes a leaf without consulting the SAH.
    /// Range [1, 2^20].
    std::uint32_t leaf_size = 1;
    /// Candidate planes per axis for large nodes: the node's extent is cut into this many
    /// bins (Wald's binned build), plus the two planes that cut off the empty space on each
    /// side. Range [2, 1024].
    std::uint32_t bins = 32;
    /// Nodes with fewer triangles evaluate every triangle boundary as a candidate (the exact
    /// SAH sweep over sorted events, O(n log n) per node); larger ones are binned. The deep,
    /// small nodes decide the tree's tightness and cost little to sweep. Range [0, 2^30];
    /// 0 bins everywhere.
    std::uint32_t exact_below = 1024;
    /// Worker threads for the build; 0 means all hardware threads. Range [0, 1024]. The tree
    /// is identical for every value.
    unsigned threads = 0;

    /// Throws ConfigError naming the first field out of range.
    void validate() const;
    /// max_depth, or the automatic depth for `triangles` triangles when max_depth is 0.
    [[nodiscard]] std::uint32_t depth_limit(std::size_t triangles) const noexcept;
    friend bool operator==(const KdTreeConfig&, const KdTreeConfig&) = default;
};

/// One kd-tree node, 8 bytes (the layout of Wald's thesis and pbrt's KdAccelNode):
///   offset 0  float   split      inner: the split plane's coordinate on `axis`
///             uint32  first_ref  leaf: index of the first triangle reference
///   offset 4  uint32  bits 0-1   axis 0, 1, 2 for an inner node; 3 for a leaf
///                     bits 2-31  inner: index of the child above the plane (the child below
///                                is the next node); leaf: number of references (0 = empty)
/// Nodes are in depth-first order, so the child below is always at index + 1.
class KdNode {
public:
    static constexpr std::uint32_t max_index = (1u << 30) - 1;

    /// Precondition (checked by the builder, which throws InputError): above_child <= max_index.
    [[nodiscard]] static KdNode make_inner(int axis, float split, std::uint32_t above_child) noexcept
    {
        SG_ASSERT(axis >= 0 && axis <= 2 && above_child <= max_index);
        return KdNode(std::bit_cast<std::uint32_t>(split),
                      static_cast<std::uint32_t>(axis) | (above_child << 2));
    }
    /// Precondition: count <= max_index.
    [[nodiscard]] static KdNode make_leaf(std::uint32_t first_ref, std::uint32_t count) noexcept
    {
        SG_ASSERT(count <= max_index);
        return KdNode(first_ref, 3u | (count << 2));
    }

    [[nodiscard]] bool is_leaf() const noexcept { return (bits_ & 3u) == 3u; }
    [[nodiscard]] int axis() const noexcept { return static_cast<int>(bits_ & 3u); }
    [[nodiscard]] float split() const noexcept { return std::bit_cast<float>(word_); }
    [[nodiscard]] std::uint32_t above_child() const noexcept { return bits_ >> 2; }
    [[nodiscard]] std::uint32_t first_ref() const noexcept { return word_; }
    [[nodiscard]] std::uint32_t ref_count() const noexcept { return bits_ >> 2; }

    KdNode() = default;
    friend bool operator==(const KdNode&, const KdNode&) = default;

private:
    KdNode(std::uint32_t word, std::uint32_t bits) noexcept : word_(word), bits_(bits) {}
    std::uint32_t word_ = 0;
    std::uint32_t bits_ = 3u;
};
static_assert(sizeof(KdNode) == 8 && alignof(KdNode) == 4,
              "KdNode must be 8 bytes (a float or uint32, and a packed uint32) with no padding");
static_assert(std::is_trivially_copyable_v<KdNode>, "KdNode is copied as bytes when merged");

/// A kd-tree over the scene's bounding box (padded by boundary_pad), built by the SAH with
/// "perfect splits": every triangle is clipped to the node's box in double precision
/// (clip.hpp) before its extent is used for candidate planes and for the split, so a
/// triangle that crosses the node's box but not a child is not referenced by that child.
///
/// Robustness: a triangle goes to every child whose box, padded by boundary_pad, its clipped
/// polygon reaches (so planar triangles lying in a split plane go to both sides, and a hit the
/// watertight test reports a few ulps outside its triangle is still in a visited leaf); the
/// traversal widens its plane crossings (t_pad) and visits both children when a ray parallel
/// to the split plane lies in it.
class KdTree : public StructureQueries<KdTree> {
public:
    using Config = KdTreeConfig;

    /// Builds the tree (subtrees in parallel on oneTBB). Throws ConfigError for a bad config,
    /// InputError for a bad mesh (check_mesh) or one too large for 32-bit indices. An empty
    /// mesh gives an empty tree on which every query misses.
    [[nodiscard]] static KdTree build(const MeshView& mesh, const KdTreeConfig& config = {});

    // Queries (intersect, occluded): StructureQueries (structure_queries.hpp), traversed by
    // src/kernels/kd_tree_walk.hpp. Counters: nodes_visited = inner nodes, cells_visited =
    // leaves.

    /// Bytes of the tree itself: box, nodes and references (not the mesh).
    [[nodiscard]] std::size_t memory_bytes() const noexcept
    {
        return sizeof(box_) + sizeof(triangle_count_) + nodes_.size() * sizeof(KdNode) +
               refs_.size() * sizeof(std::uint32_t);
    }

    /// The root box: the scene's bounding box padded by boundary_pad.
    [[nodiscard]] const Aabb& box() const noexcept { return box_; }
    [[nodiscard]] std::span<const KdNode> nodes() const noexcept { return nodes_; }
    [[nodiscard]] std::span<const std::uint32_t> refs() const noexcept { return refs_; }
    [[nodiscard]] std::size_t node_count() const noexcept { return nodes_.size(); }
    [[nodiscard]] std::size_t leaf_count() const noexcept;
    [[nodiscard]] std::size_t reference_count() const noexcept { return refs_.size(); }
    /// Depth of the deepest leaf (root = 0; 0 also for an empty tree).
    [[nodiscard]] std::uint32_t depth() const noexcept { return depth_; }
    [[nodiscard]] std::uint32_t triangle_count() const noexcept { return triangle_count_; }

    friend bool operator==(const KdTree&, const KdTree&) = default;

private:
    Aabb box_;
    std::uint32_t triangle_count_ = 0;
    std::uint32_t depth_ = 0;
    std::vector<KdNode> nodes_;
    std::vector<std::uint32_t> refs_;
};

}  // namespace sg
