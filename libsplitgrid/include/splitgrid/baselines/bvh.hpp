#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <type_traits>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/structure_queries.hpp"

namespace sg {

/// Deepest BVH the traverser's fixed stack supports (BvhConfig::max_depth's range).
inline constexpr std::uint32_t bvh_max_supported_depth = 64;

/// Parameters of the BVH (a comparison structure for sg-bench; docs/BASELINES.md).
///
/// Binned SAH over triangle centroids (Wald, "On fast construction of SAH-based bounding
/// volume hierarchies", IEEE RT 2007): each node's centroid extent is cut into `bins` bins on
/// each axis, and the boundary between bins with the lowest
///   traversal_cost + (SA(left) n_left + SA(right) n_right) / SA(node)
/// (in units of one ray/triangle test) splits the node's triangles in two.
struct BvhConfig {
    /// Bins per axis. Range [2, 64]. 16 costs nothing measurable in trace speed against 32
    /// on the Stanford dragon here and builds faster (docs/BASELINES.md).
    std::uint32_t bins = 16;
    /// Nodes with at most this many triangles always become leaves. Range [1, max_leaf_size].
    std::uint32_t leaf_size = 1;
    /// Nodes with at most this many triangles become leaves when the SAH says splitting does
    /// not pay; larger nodes are always split (at the object median when their centroids
    /// coincide). Range [leaf_size, 2^20].
    std::uint32_t max_leaf_size = 8;
    /// Cost of visiting a node, in ray/triangle tests. Range (0, 1e6]. 4 because the
    /// kernels test a leaf's triangles eight at a time, so a triangle of a leaf costs far
    /// less than a node visit: against 1, it made the BVH faster and smaller, and 8 did no
    /// better (docs/notebook/trace.md, "A fair BVH: its cost model priced for the 8-wide leaf
    /// test").
    double traversal_cost = 4.0;
    /// Deepest leaf (root = 0); nodes at this depth become leaves whatever their size.
    /// Range [1, 64]; also bounds the traversal stack.
    std::uint32_t max_depth = bvh_max_supported_depth;
    /// Worker threads for the build; 0 means all hardware threads. Range [0, 1024]. The BVH
    /// is identical for every value.
    unsigned threads = 0;

    /// Throws ConfigError naming the first field out of range.
    void validate() const;
    friend bool operator==(const BvhConfig&, const BvhConfig&) = default;
};

/// One node of the build's binary tree (Bvh::build collapses it into BvhWideNodes), 32 bytes:
///   offset  0  Aabb    bounds       the node's box (24 bytes)
///   offset 24  uint32  index        inner: first child (the second is index + 1);
///                                   leaf: first triangle reference
///   offset 28  uint32  bits 0-1     inner: split axis 0, 1, 2; 3 for a leaf
///                      bits 2-31    leaf: number of references (>= 1)
/// Nodes are in the order a depth-first build allocates them: the root, then its two
/// children side by side, then the left child's subtree, then the right child's.
class BvhNode {
public:
    static constexpr std::uint32_t max_count = (1u << 30) - 1;

    [[nodiscard]] static BvhNode make_inner(const Aabb& bounds, int axis,
                                            std::uint32_t first_child) noexcept
    {
        SG_ASSERT(axis >= 0 && axis <= 2);
        return BvhNode(bounds, first_child, static_cast<std::uint32_t>(axis));
    }
    /// Precondition: 1 <= count <= max_count.
    [[nodiscard]] static BvhNode make_leaf(const Aabb& bounds, std::uint32_t first_ref,
                                           std::uint32_t count) noexcept
    {
        SG_ASSERT(count >= 1 && count <= max_count);
        return BvhNode(bounds, first_ref, 3u | (count << 2));
    }

    Aabb bounds;

    [[nodiscard]] bool is_leaf() const noexcept { return (bits_ & 3u) == 3u; }
    [[nodiscard]] int axis() const noexcept { return static_cast<int>(bits_ & 3u); }
    [[nodiscard]] std::uint32_t first_child() const noexcept { return index_; }
    [[nodiscard]] std::uint32_t first_ref() const noexcept { return index_; }
    [[nodiscard]] std::uint32_t ref_count() const noexcept { return bits_ >> 2; }

    BvhNode() = default;
    friend bool operator==(const BvhNode&, const BvhNode&) = default;

private:
    BvhNode(const Aabb& b, std::uint32_t index, std::uint32_t bits) noexcept
        : bounds(b), index_(index), bits_(bits)
    {
    }
    std::uint32_t index_ = 0;
    std::uint32_t bits_ = 3u;
};
static_assert(sizeof(BvhNode) == 32 && alignof(BvhNode) == 4,
              "BvhNode must be 32 bytes (a 24-byte Aabb and two uint32) with no padding");
static_assert(std::is_trivially_copyable_v<BvhNode>, "BvhNode is copied as bytes when merged");

/// Eight children of the BVH side by side, 256 bytes (four cache lines): the binary tree
/// collapsed so that a traversal step tests eight boxes at once, lane by lane in 8-wide vectors
/// (docs/BASELINES.md, "BVH").
///   offset   0  float[3][8]   lower   lower[k][i]: lower plane on axis k of child i
///   offset  96  float[3][8]   upper
///   offset 192  uint32[8]     child   inner child: index of its BvhWideNode; leaf child:
///                                     first triangle reference; unused slot: unused_slot
///   offset 224  uint32[8]     count   leaf child: number of references (>= 1); else 0
/// Used slots come first. An unused slot's box is empty (lower +infinity, upper -infinity), but
/// it is its child word that keeps the walk out of it: a ray unconstrained on every axis (see
/// BoxRay) would enter an empty box.
struct alignas(64) BvhWideNode {
    static constexpr int width = 8;
    static constexpr std::uint32_t unused_slot = 0xFFFFFFFFu;

    float lower[3][width];
    float upper[3][width];
    std::uint32_t child[width];
    std::uint32_t count[width];

    [[nodiscard]] bool is_used(int i) const noexcept { return child[i] != unused_slot; }
    [[nodiscard]] bool is_leaf(int i) const noexcept { return count[i] != 0; }
    friend bool operator==(const BvhWideNode&, const BvhWideNode&) = default;
};
static_assert(sizeof(BvhWideNode) == 32 * BvhWideNode::width, "BvhWideNode: no padding");
static_assert(std::is_standard_layout_v<BvhWideNode>, "the walk reads planes by byte offset");

/// A bounding volume hierarchy over the triangles' boxes, each padded by boundary_pad so that
/// a hit the watertight test reports a few ulps outside its triangle is inside the leaf's box.
/// Every triangle is referenced exactly once.
class Bvh : public StructureQueries<Bvh> {
public:
    using Config = BvhConfig;

    /// Builds the BVH (subtrees in parallel on oneTBB). Throws ConfigError for a bad config,
    /// InputError for a bad mesh (check_mesh) or one too large for 32-bit indices. An empty
    /// mesh gives an empty BVH on which every query misses.
    [[nodiscard]] static Bvh build(const MeshView& mesh, const BvhConfig& config = {});

    /// Refit for a mesh whose vertices moved: the same triangles (same count and order),
    /// new positions. Keeps the tree and the triangle order and recomputes every box from
    /// the leaves up, as the build would for that tree (each triangle's box padded by the new
    /// scene's boundary_pad), so every query stays exact; only its speed depends on how far
    /// the tree has drifted from what a build would choose. `threads` (as in
    /// BvhConfig::threads) refit the leaves; the inner slots, one union of a node's slots
    /// each, follow in one thread. Throws InputError for a bad mesh or a different triangle
    /// count.
    void refit(const MeshView& mesh, unsigned threads = 0);

    // Queries (intersect, occluded): StructureQueries (structure_queries.hpp), traversed by
    // src/kernels/bvh_walk.hpp over the wide nodes. Counters: nodes_visited = wide nodes whose
    // children were tested, cells_visited = leaves.

    /// Bytes of the BVH itself (not the mesh): its wide nodes, references and root box. The
    /// binary tree of the build is collapsed and freed (Bvh::build).
    [[nodiscard]] std::size_t memory_bytes() const noexcept
    {
        return sizeof(triangle_count_) + sizeof(depth_) + sizeof(leaf_count_) + sizeof(box_) +
               wide_.size() * sizeof(BvhWideNode) + refs_.size() * sizeof(std::uint32_t);
    }

    /// The tree: the build's binary tree collapsed to up to BvhWideNode::width children a
    /// node, root at 0, parents before children; empty for an empty mesh. A root that is a
    /// leaf is a wide node with one used slot.
    [[nodiscard]] std::span<const BvhWideNode> wide_nodes() const noexcept { return wide_; }
    [[nodiscard]] std::span<const std::uint32_t> refs() const noexcept { return refs_; }
    /// The root's box (empty for an empty mesh): the union of the root node's slots.
    [[nodiscard]] const Aabb& box() const noexcept { return box_; }
    [[nodiscard]] std::size_t node_count() const noexcept { return wide_.size(); }
    /// Leaves (slots holding triangle references), as in the build's binary tree.
    [[nodiscard]] std::size_t leaf_count() const noexcept { return leaf_count_; }
    [[nodiscard]] std::size_t reference_count() const noexcept { return refs_.size(); }
    /// Depth of the deepest leaf in the build's binary tree (root = 0; 0 also for an empty
    /// BVH); the wide tree is at most as deep.
    [[nodiscard]] std::uint32_t depth() const noexcept { return depth_; }
    [[nodiscard]] std::uint32_t triangle_count() const noexcept { return triangle_count_; }

    friend bool operator==(const Bvh&, const Bvh&) = default;

private:
    std::uint32_t triangle_count_ = 0;
    std::uint32_t depth_ = 0;
    std::uint32_t leaf_count_ = 0;
    Aabb box_;
    std::vector<std::uint32_t> refs_;
    std::vector<BvhWideNode> wide_;

    void collapse(std::span<const BvhNode> binary);
};

}  // namespace sg
