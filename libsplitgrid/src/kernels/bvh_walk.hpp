#pragma once

// Traversal kernels, part 6: the BVH's traversal (baselines/bvh.hpp).

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

/// Entry parameter of the ray into `box` within [t0, t1], or +infinity if the ray misses it,
/// with the crossings computed as (p - o) * (1 / d) and widened by KernelRay::pad: the box
/// test of Padding::none (pad 0, the accuracy experiment's measure of what the allowance buys;
/// +infinity on a parallel axis, which then constrains nothing).
[[nodiscard, gnu::always_inline]] inline float unpadded_box_entry(const KernelRay& ray,
                                                                  const Aabb& box, float t0,
                                                                  float t1) noexcept
{
    for (int k = 0; k < 3; ++k) {
        const float a = (box.lower[k] - ray.origin[k]) * ray.inv[k];
        const float b = (box.upper[k] - ray.origin[k]) * ray.inv[k];
        t0 = std::max(t0, std::min(a, b) - ray.pad[k]);
        t1 = std::min(t1, std::max(a, b) + ray.pad[k]);
    }
    return t0 <= t1 ? t0 : std::numeric_limits<float>::infinity();
}

/// The ray as the BVH's widened box test reads it. A plane p's crossing, widened by the
/// axis's allowance, is one multiply and one add, p * (1 / d) + (-(o * (1 / d)) -+ pad), and
/// the plane the ray meets first on each axis is known from the direction's sign, so a box
/// costs 18 operations (six multiplies, six adds, six min/max) instead of 30 (six
/// subtractions and six multiplies for both crossings, six min/max to order them, six to
/// widen them and six to narrow the interval; docs/BENCH.md, "The BVH's box test").
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
    /// then an address, not a select, which GCC compiled as branches on the ray's signs (7
    /// more mispredicted branches per incoherent ray on the bunny, cachegrind).
    std::uint32_t near_plane[3];
    std::uint32_t far_plane[3];

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

/// Entry parameter of the ray into `box` within [t0, t1], every crossing widened by the
/// axis's allowance, or +infinity if the ray misses it. Always inlined: GCC made it a call,
/// twice per inner node, and inline the BVH traces 3-5% faster (docs/BENCH.md, "Calls inside
/// the walks").
[[nodiscard, gnu::always_inline]] inline float box_entry(const BoxRay& ray, const Aabb& box,
                                                         float t0, float t1) noexcept
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

/// Depth-first, nearer child first (by the direction's sign on the node's split axis);
/// a pending subtree is skipped when its box starts past the closest hit so far.
/// Counters: nodes_visited = inner nodes whose children were tested, cells_visited = leaves.
template <TriangleTest test, Padding padding, class Search>
inline void walk_bvh(const Bvh& bvh, const MeshArrays& mesh, const KernelRay& ray,
                     Search& search) noexcept
{
    const std::span<const BvhNode> nodes = bvh.nodes();
    if (nodes.empty()) return;
    constexpr float miss = std::numeric_limits<float>::infinity();
    const BoxRay widened(ray);
    if (box_entry<padding>(ray, widened, nodes[0].bounds, ray.t_min, ray.t_max) == miss) return;
    const std::uint32_t* const refs = bvh.refs().data();
    const std::uint32_t* const refs_end = refs + bvh.refs().size();
    NoMailbox no_mailbox;

    struct Pending {
        std::uint32_t node;
        float t_enter;
    };
    std::array<Pending, bvh_max_supported_depth + 1> stack;  // only [0, sp) is read
    std::size_t sp = 0;
    std::uint32_t index = 0;
    for (;;) {
        const BvhNode& node = nodes[index];
        if (!node.is_leaf()) {
            search.count_node();
            const auto flip = static_cast<std::uint32_t>(ray.negative[node.axis()]);
            const std::uint32_t near_child = node.first_child() + flip;
            const std::uint32_t far_child = node.first_child() + 1 - flip;
            const float best = search.best_t();
            const float t_near =
                box_entry<padding>(ray, widened, nodes[near_child].bounds, ray.t_min, best);
            const float t_far =
                box_entry<padding>(ray, widened, nodes[far_child].bounds, ray.t_min, best);
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
            (void)test_id_leaf<test>(ray, mesh, search, no_mailbox, refs + node.first_ref(),
                                     node.ref_count(), refs_end);
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

}  // namespace sg::kernels::SG_KERNEL_ISA
