#pragma once

// Traversal kernels, part 6: the BVH's traversal (baselines/bvh.hpp). A wide node's eight
// boxes are tested at once (wide_box_entry), or in the scalar kernels (level 0) one after the
// other with the root box's test.

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

/// Narrows [t0, t1] to the ray's interval in `box` (empty: t0 > t1), with the crossings
/// computed as (p - o) * (1 / d) and widened by KernelRay::pad: the box test of Padding::none
/// (pad 0, the accuracy experiment's measure of what the allowance buys; +infinity on a
/// parallel axis, which then constrains nothing).
[[gnu::always_inline]] inline void clip_unpadded(const KernelRay& ray, const Aabb& box, float& t0,
                                                 float& t1) noexcept
{
    for (int k = 0; k < 3; ++k) {
        const float a = (box.lower[k] - ray.origin[k]) * ray.inv[k];
        const float b = (box.upper[k] - ray.origin[k]) * ray.inv[k];
        t0 = std::max(t0, std::min(a, b) - ray.pad[k]);
        t1 = std::min(t1, std::max(a, b) + ray.pad[k]);
    }
}

/// Entry parameter of the ray into `box` within [t0, t1] (clip_unpadded), or +infinity if the
/// ray misses it.
[[nodiscard, gnu::always_inline]] inline float unpadded_box_entry(const KernelRay& ray,
                                                                  const Aabb& box, float t0,
                                                                  float t1) noexcept
{
    clip_unpadded(ray, box, t0, t1);
    return t0 <= t1 ? t0 : std::numeric_limits<float>::infinity();
}

/// The ray as the BVH's widened box test reads it. A plane p's crossing, widened by the
/// axis's allowance, is one multiply and one add, p * (1 / d) + (-(o * (1 / d)) -+ pad), and
/// the plane the ray meets first on each axis is known from the direction's sign, so a box
/// costs 18 operations (six multiplies, six adds, six min/max) instead of 30 (six
/// subtractions and six multiplies for both crossings, six min/max to order them, six to
/// widen them and six to narrow the interval; docs/notebook/trace.md, "The BVH's box test:
/// planes chosen by the ray's signs, the allowance folded in").
/// The product form rounds differently from (p - o) * (1 / d): below
/// 5u (M + |o|) / |d| in all, inside the allowance of 64u (docs/SPLIT_GRID.md derives it).
/// An axis where that bound could overflow ((M + |o|) / |d| >= 2^124, KernelRay::extreme),
/// or a parallel one, constrains nothing: scale 0 and offsets -+infinity, so the box is then
/// visited whatever the ray's position on that axis, which is conservative.
struct BoxRay {
    float scale[3];
    float near_offset[3];  ///< added to the product of the plane met first
    float far_offset[3];   ///< added to the product of the plane met last
    /// Byte offsets in an Aabb of the planes met first and last on each axis: the choice is
    /// then an address, not a select, which GCC compiled as branches on the ray's signs, each
    /// a coin toss on incoherent rays (docs/notebook/trace.md, "The BVH's box test: planes
    /// chosen by the ray's signs, the allowance folded in").
    std::uint32_t near_plane[3];
    std::uint32_t far_plane[3];
    /// The same choice in a BvhWideNode: byte offsets of its children's planes on each axis.
    std::uint32_t near_wide[3];
    std::uint32_t far_wide[3];

    explicit BoxRay(const KernelRay& ray) noexcept
    {
        static_assert(std::is_standard_layout_v<Aabb>, "plane_at reads an Aabb by offset");
        constexpr float inf = std::numeric_limits<float>::infinity();
        // pad = 2^-18 (M + |o|) / |d|, so (M + |o|) / |d| >= 2^124 is pad >= 2^106 (or an
        // overflowed pad, which is infinite as on a parallel axis).
        constexpr float unsafe_pad = 0x1p106f;
        for (int k = 0; k < 3; ++k) {
            const std::size_t along = static_cast<std::size_t>(k) * sizeof(float);
            const auto lower = static_cast<std::uint32_t>(offsetof(Aabb, lower) + along);
            const auto upper = static_cast<std::uint32_t>(offsetof(Aabb, upper) + along);
            near_plane[k] = ray.negative[k] ? upper : lower;
            far_plane[k] = ray.negative[k] ? lower : upper;
            const auto wide_lower = static_cast<std::uint32_t>(offsetof(BvhWideNode, lower) +
                                                               BvhWideNode::width * along);
            const auto wide_upper = static_cast<std::uint32_t>(offsetof(BvhWideNode, upper) +
                                                               BvhWideNode::width * along);
            near_wide[k] = ray.negative[k] ? wide_upper : wide_lower;
            far_wide[k] = ray.negative[k] ? wide_lower : wide_upper;
            if (ray.parallel[k] || !(ray.pad[k] < unsafe_pad)) {
                scale[k] = 0.0f;
                near_offset[k] = -inf;
                far_offset[k] = inf;
                continue;
            }
            const float offset = -(ray.origin[k] * ray.inv[k]);
            scale[k] = ray.inv[k];
            near_offset[k] = offset - ray.pad[k];
            far_offset[k] = offset + ray.pad[k];
        }
    }
};

/// The plane at byte `offset` of `box` (BoxRay::near_plane, far_plane).
[[nodiscard, gnu::always_inline]] inline float plane_at(const Aabb& box,
                                                        std::uint32_t offset) noexcept
{
    float plane;
    std::memcpy(&plane, reinterpret_cast<const unsigned char*>(&box) + offset, sizeof plane);
    return plane;
}

/// Narrows [t0, t1] to the ray's interval in `box` (empty: t0 > t1), every crossing widened
/// by the axis's allowance.
[[gnu::always_inline]] inline void clip_widened(const BoxRay& ray, const Aabb& box, float& t0,
                                                float& t1) noexcept
{
    // Operand order matters: on an unconstrained axis an infinite plane (a padded box next to
    // FLT_MAX) times scale 0 is NaN, and std::max and std::min return their first operand when
    // the second is NaN, so the axis then leaves the interval as it was.
    for (int k = 0; k < 3; ++k) {
        const float near = plane_at(box, ray.near_plane[k]) * ray.scale[k] + ray.near_offset[k];
        const float far = plane_at(box, ray.far_plane[k]) * ray.scale[k] + ray.far_offset[k];
        t0 = std::max(t0, near);
        t1 = std::min(t1, far);
    }
}

/// Entry parameter of the ray into `box` within [t0, t1] (clip_widened), or +infinity if the
/// ray misses it: the root box's test (the wide nodes' boxes go through wide_box_entry, which
/// does the same lane by lane). Always inlined: as a call in the binary walk it cost time
/// (docs/notebook/trace.md, "Calls inside the walks, and the BVH's order of children").
[[nodiscard, gnu::always_inline]] inline float box_entry(const BoxRay& ray, const Aabb& box,
                                                         float t0, float t1) noexcept
{
    clip_widened(ray, box, t0, t1);
    return t0 <= t1 ? t0 : std::numeric_limits<float>::infinity();
}

/// The box test of the walk's padding.
template <Padding padding>
[[nodiscard, gnu::always_inline]] inline float box_entry(const KernelRay& ray,
                                                         const BoxRay& widened, const Aabb& box,
                                                         float t0, float t1) noexcept
{
    if constexpr (padding == Padding::none) return unpadded_box_entry(ray, box, t0, t1);
    else return box_entry(widened, box, t0, t1);
}

#if SG_KERNEL_ISA_LEVEL >= 2
static_assert(BvhWideNode::width == lane_count,
              "a BvhWideNode's boxes are tested in one vfloat (simd.hpp), a lane per child");

/// The entry parameters of a wide node's children, a lane each.
using ChildEntries = vfloat;

/// The children's planes at byte `offset` of `node` (near_wide, far_wide: chosen per ray, as
/// in plane_at).
[[nodiscard, gnu::always_inline]] inline vfloat planes_at(const BvhWideNode& node,
                                                           std::uint32_t offset) noexcept
{
    vfloat v;
    std::memcpy(&v, reinterpret_cast<const unsigned char*>(&node) + offset, sizeof v);
    return v;
}

/// The children's entry parameters (box_entry and unpadded_box_entry lane by lane, with the
/// same operations in the same order, so each lane's result is the scalar test's bit for bit:
/// std::max(a, b) is written (a < b ? b : a) and std::min(a, b) (b < a ? b : a), which keep
/// their first operand against a NaN as the scalar test relies on), and a bit per used child
/// the ray enters within [t0, t1].
template <Padding padding>
[[nodiscard, gnu::always_inline]] inline std::uint32_t wide_box_entry(
    const KernelRay& ray, const BoxRay& widened, const BvhWideNode& node, float t0_in, float t1_in,
    ChildEntries& t_enter) noexcept
{
    vfloat t0 = splat(t0_in);
    vfloat t1 = splat(t1_in);
    for (int k = 0; k < 3; ++k) {
        if constexpr (padding == Padding::none) {
            vfloat lo, hi;
            std::memcpy(&lo, node.lower[k], sizeof lo);
            std::memcpy(&hi, node.upper[k], sizeof hi);
            const float o = ray.origin[k], inv = ray.inv[k], pad = ray.pad[k];
            const vfloat a = (lo - o) * inv;
            const vfloat b = (hi - o) * inv;
            const vfloat near = (b < a ? b : a) - pad;
            const vfloat far = (a < b ? b : a) + pad;
            t0 = t0 < near ? near : t0;
            t1 = far < t1 ? far : t1;
        } else {
            const vfloat near = planes_at(node, widened.near_wide[k]) * widened.scale[k] +
                                widened.near_offset[k];
            const vfloat far = planes_at(node, widened.far_wide[k]) * widened.scale[k] +
                               widened.far_offset[k];
            t0 = t0 < near ? near : t0;
            t1 = far < t1 ? far : t1;
        }
    }
    vint child;
    std::memcpy(&child, node.child, sizeof child);
    const vint hit = (t0 <= t1) & (child != static_cast<std::int32_t>(BvhWideNode::unused_slot));
    t_enter = t0;
    return lane_bits(hit);
}
#else
/// The entry parameters of a wide node's children, one each.
using ChildEntries = float[BvhWideNode::width];

/// The scalar kernels' wide_box_entry: the children's boxes one at a time, each with the root
/// box's test of the padding (clip_unpadded, clip_widened), so each entry is the one the
/// lanes compute, bit for bit.
template <Padding padding>
[[nodiscard, gnu::always_inline]] inline std::uint32_t wide_box_entry(
    const KernelRay& ray, const BoxRay& widened, const BvhWideNode& node, float t0_in, float t1_in,
    ChildEntries& t_enter) noexcept
{
    std::uint32_t hits = 0;
    for (int i = 0; i < BvhWideNode::width; ++i) {
        t_enter[i] = t0_in;
        if (node.child[i] == BvhWideNode::unused_slot) continue;
        Aabb box;
        for (int k = 0; k < 3; ++k) {
            box.lower[k] = node.lower[k][i];
            box.upper[k] = node.upper[k][i];
        }
        float t0 = t0_in, t1 = t1_in;
        if constexpr (padding == Padding::none) clip_unpadded(ray, box, t0, t1);
        else clip_widened(widened, box, t0, t1);
        t_enter[i] = t0;
        if (t0 <= t1) hits |= 1u << i;
    }
    return hits;
}
#endif

/// Depth first over the wide nodes (Bvh::wide_nodes), the children a ray enters visited
/// nearest first (by their entry parameters; equal ones in slot order); a pending child is
/// skipped when its box starts past the closest hit so far. Counters: nodes_visited = wide
/// nodes whose children were tested, cells_visited = leaves.
template <TriangleTest test, Padding padding, class Search>
inline void walk_bvh(const Bvh& bvh, const MeshArrays& mesh, const KernelRay& ray,
                     Search& search) noexcept
{
    const std::span<const BvhWideNode> wide = bvh.wide_nodes();
    if (wide.empty()) return;
    constexpr float miss = std::numeric_limits<float>::infinity();
    const BoxRay widened(ray);
    if (box_entry<padding>(ray, widened, bvh.box(), ray.t_min, ray.t_max) == miss) return;
    const std::uint32_t* const refs = bvh.refs().data();
    const std::uint32_t* const refs_end = refs + bvh.refs().size();
    NoMailbox no_mailbox;
    const BvhWideNode* const nodes = wide.data();

    // A child to visit: its BvhWideNode child word in the low half of `target`, its count
    // word (0 for a wide node) in the high half.
    struct Pending {
        std::uint64_t target;
        float t_enter;
    };
    auto target_of = [](const BvhWideNode& node, int i) noexcept {
        return std::uint64_t{node.child[i]} | (std::uint64_t{node.count[i]} << 32);
    };
    // A wide node is at most as deep as the binary node it collapses, and each visit keeps
    // at most width - 1 children.
    constexpr std::size_t stack_size = (BvhWideNode::width - 1) * bvh_max_supported_depth + 1;
    std::array<Pending, stack_size> stack;  // only [0, sp) is read
    std::size_t sp = 0;
    std::uint64_t next = 0;  // the root, a wide node
    for (;;) {
        const auto index = static_cast<std::uint32_t>(next);
        const auto count = static_cast<std::uint32_t>(next >> 32);
        if (count == 0) {
            const BvhWideNode& node = nodes[index];
            search.count_node();
            ChildEntries t;
            std::uint32_t hits = wide_box_entry<padding>(ray, widened, node, ray.t_min,
                                                         search.best_t(), t);
            if (hits != 0) {
                const int first = __builtin_ctz(hits);
                hits &= hits - 1;
                if (hits == 0) {
                    next = target_of(node, first);
                    continue;
                }
                // Nearest first: the entered children sorted by entry (insertion, stable, so
                // ties keep slot order), all but the nearest pushed farthest first.
                float entry[BvhWideNode::width];
                std::memcpy(entry, &t, sizeof entry);
                std::array<Pending, BvhWideNode::width> order;
                order[0] = Pending{target_of(node, first), entry[first]};
                std::size_t m = 1;
                while (hits != 0) {
                    const int i = __builtin_ctz(hits);
                    hits &= hits - 1;
                    const Pending p{target_of(node, i), entry[i]};
                    std::size_t j = m++;
                    for (; j > 0 && p.t_enter < order[j - 1].t_enter; --j) order[j] = order[j - 1];
                    order[j] = p;
                }
                for (std::size_t j = m; j-- > 1;) {
                    SG_ASSERT(sp < stack.size());
                    stack[sp++] = order[j];
                }
                next = order[0].target;
                continue;
            }
        } else {
            search.count_cell();
            (void)test_id_leaf<test>(ray, mesh, search, no_mailbox, refs + index, count, refs_end);
            if (search.done()) return;
        }
        // Next pending child whose box starts before the closest hit so far.
        for (;;) {
            if (sp == 0) return;
            const Pending& p = stack[--sp];
            if (p.t_enter <= search.best_t()) {
                next = p.target;
                break;
            }
        }
    }
}

}  // namespace sg::kernels::SG_KERNEL_ISA
