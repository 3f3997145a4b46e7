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
#include "splitgrid/baselines/traversal_common.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/traverse.hpp"

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
    /// Cost of visiting a node, in ray/triangle tests. Range (0, 1e6].
    double traversal_cost = 1.0;
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

/// One BVH node, 32 bytes:
///   offset  0  Aabb    bounds       the node's box (24 bytes)
///   offset 24  uint32  index        inner: first child (the second is index + 1);
///                                   leaf: first triangle reference
///   offset 28  uint32  bits 0-1     inner: split axis 0, 1, 2 (orders the children);
///                                   3 for a leaf
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

/// A bounding volume hierarchy over the triangles' boxes, each padded by boundary_pad so that
/// a hit the watertight test reports a few ulps outside its triangle is inside the leaf's box.
/// Every triangle is referenced exactly once.
class Bvh : public BaselineQueries<Bvh> {
public:
    using Config = BvhConfig;

    /// Builds the BVH (subtrees in parallel on oneTBB). Throws ConfigError for a bad config,
    /// InputError for a bad mesh (check_mesh) or one too large for 32-bit indices. An empty
    /// mesh gives an empty BVH on which every query misses.
    [[nodiscard]] static Bvh build(const MeshView& mesh, const BvhConfig& config = {});

    // Queries (intersect, occluded, intersect_with, occluded_with): BaselineQueries in
    // traversal_common.hpp. Counters: nodes_visited = inner nodes whose children were tested, cells_visited = leaves.

    /// Bytes of the BVH itself: nodes and references (not the mesh).
    [[nodiscard]] std::size_t memory_bytes() const noexcept
    {
        return sizeof(triangle_count_) + nodes_.size() * sizeof(BvhNode) +
               refs_.size() * sizeof(std::uint32_t);
    }

    [[nodiscard]] std::span<const BvhNode> nodes() const noexcept { return nodes_; }
    [[nodiscard]] std::span<const std::uint32_t> refs() const noexcept { return refs_; }
    [[nodiscard]] std::size_t node_count() const noexcept { return nodes_.size(); }
    [[nodiscard]] std::size_t leaf_count() const noexcept { return (nodes_.size() + 1) / 2; }
    [[nodiscard]] std::size_t reference_count() const noexcept { return refs_.size(); }
    /// Depth of the deepest leaf (root = 0; 0 also for an empty BVH).
    [[nodiscard]] std::uint32_t depth() const noexcept { return depth_; }
    [[nodiscard]] std::uint32_t triangle_count() const noexcept { return triangle_count_; }

    friend bool operator==(const Bvh&, const Bvh&) = default;

private:
    // The slab test's rounding allowance (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013):
    // each crossing (plane - origin) * (1 / direction) has three roundings, so its relative
    // error is below gamma(3) = 3u / (1 - 3u), u = 2^-24. Widening the entry down and the
    // exit up by 2 gamma(3) each (twice what Ize needs) keeps every box the exact ray
    // touches, including at its edges and corners.
    static constexpr float t_pad(Padding padding) noexcept
    {
        constexpr double u = 0x1p-24;
        return padding == Padding::Conservative ? static_cast<float>(2.0 * 3.0 * u / (1.0 - 3.0 * u))
                                                : 0.0f;
    }

    friend class BaselineQueries<Bvh>;
    template <Padding padding, class Search>
    void walk(const detail::BaselineRay& ray, Search& search) const noexcept;

    std::uint32_t triangle_count_ = 0;
    std::uint32_t depth_ = 0;
    std::vector<BvhNode> nodes_;
    std::vector<std::uint32_t> refs_;
};

namespace detail {

// Entry parameter of the ray into `box` within [t_min, t_max], widened by `pad`, or +inf if
// the ray misses it. Zero direction components have infinite reciprocals: a crossing is then
// +-inf, or NaN when the origin lies on the plane; the max/min below keep their first
// operand when the second is NaN, so such an axis constrains nothing, as it should (the ray
// lies in the closed slab).
[[nodiscard]] inline float slab_entry(const BaselineRay& ray, const std::array<int, 3>& negative,
                                      const Aabb& box, float t_min, float t_max, float pad) noexcept
{
    float enter = t_min;
    float leave = t_max;
    for (int k = 0; k < 3; ++k) {
        const auto uk = static_cast<std::size_t>(k);
        const float near_plane = negative[uk] ? box.upper[k] : box.lower[k];
        const float far_plane = negative[uk] ? box.lower[k] : box.upper[k];
        const float t_near = (near_plane - ray.origin[k]) * ray.inv_dir[k];
        const float t_far = (far_plane - ray.origin[k]) * ray.inv_dir[k];
        enter = enter < t_near ? t_near : enter;
        leave = t_far < leave ? t_far : leave;
    }
    enter = widen_down(enter, pad);
    return enter <= widen_up(leave, pad) ? enter : std::numeric_limits<float>::infinity();
}

}  // namespace detail

template <Padding padding, class Search>
void Bvh::walk(const detail::BaselineRay& ray, Search& search) const noexcept
{
    if (nodes_.empty()) return;
    constexpr float pad = t_pad(padding);
    constexpr float miss = std::numeric_limits<float>::infinity();
    const std::array<int, 3> negative{std::signbit(ray.inv_dir[0]) ? 1 : 0,
                                      std::signbit(ray.inv_dir[1]) ? 1 : 0,
                                      std::signbit(ray.inv_dir[2]) ? 1 : 0};
    if (detail::slab_entry(ray, negative, nodes_[0].bounds, ray.t_min, ray.t_max, pad) == miss)
        return;

    struct Pending {
        std::uint32_t node;
        float t_enter;
    };
    std::array<Pending, bvh_max_supported_depth + 1> stack;  // only [0, sp) is read
    std::size_t sp = 0;
    std::uint32_t index = 0;
    for (;;) {
        const BvhNode& node = nodes_[index];
        if (!node.is_leaf()) {
            search.count_node();
            // The child on the ray's side of the split first (by the direction's sign).
            const auto flip = static_cast<std::uint32_t>(negative[static_cast<std::size_t>(node.axis())]);
            const std::uint32_t near_child = node.first_child() + flip;
            const std::uint32_t far_child = node.first_child() + 1 - flip;
            const float t_near = detail::slab_entry(ray, negative, nodes_[near_child].bounds,
                                                    ray.t_min, search.best_t(), pad);
            const float t_far = detail::slab_entry(ray, negative, nodes_[far_child].bounds,
                                                   ray.t_min, search.best_t(), pad);
            if (t_near != miss) {
                if (t_far != miss) {
                    SG_ASSERT(sp < stack.size());
                    stack[sp++] = Pending{far_child, t_far};
                }
                index = near_child;
                continue;
            }
            if (t_far != miss) {
                index = far_child;
                continue;
            }
        } else {
            search.count_cell();
            search.test_all(refs_.data() + node.first_ref(), node.ref_count());
            if (search.done()) return;
        }
        // Next pending subtree whose box starts before the closest hit so far.
        for (;;) {
            if (sp == 0) return;
            const Pending& next = stack[--sp];
            if (next.t_enter <= search.best_t()) {
                index = next.node;
                break;
            }
        }
    }
}

}  // namespace sg
