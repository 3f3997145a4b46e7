#pragma once

// Traversal kernels, part 6: the BVH's traversal (baselines/bvh.hpp).

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

/// Entry parameter of the ray into `box` within [t0, t1], every crossing widened by the
/// axis's allowance (KernelRay::pad), or +infinity if the ray misses it. A parallel axis
/// (inv = 0, pad = infinity) constrains nothing: the box is then visited whether or not the
/// origin lies in its slab, which is conservative. Always inlined: GCC made it a call, twice
/// per inner node, and inline the BVH traces 3-5% faster (docs/BENCH.md, "Calls inside the
/// walks").
[[nodiscard, gnu::always_inline]] inline float box_entry(const KernelRay& ray, const Aabb& box,
                                                         float t0, float t1) noexcept
{
    for (int k = 0; k < 3; ++k) {
        const float a = (box.lower[k] - ray.origin[k]) * ray.inv[k];
        const float b = (box.upper[k] - ray.origin[k]) * ray.inv[k];
        t0 = std::max(t0, std::min(a, b) - ray.pad[k]);
        t1 = std::min(t1, std::max(a, b) + ray.pad[k]);
    }
    return t0 <= t1 ? t0 : std::numeric_limits<float>::infinity();
}

/// Depth-first, nearer child first (by the direction's sign on the node's split axis);
/// a pending subtree is skipped when its box starts past the closest hit so far.
/// Counters: nodes_visited = inner nodes whose children were tested, cells_visited = leaves.
template <TriangleTest test, class Search>
inline void walk_bvh(const Bvh& bvh, const MeshArrays& mesh, const KernelRay& ray,
                     Search& search) noexcept
{
    const std::span<const BvhNode> nodes = bvh.nodes();
    if (nodes.empty()) return;
    constexpr float miss = std::numeric_limits<float>::infinity();
    if (box_entry(ray, nodes[0].bounds, ray.t_min, ray.t_max) == miss) return;
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
            const float t_near = box_entry(ray, nodes[near_child].bounds, ray.t_min, search.best_t());
            const float t_far = box_entry(ray, nodes[far_child].bounds, ray.t_min, search.best_t());
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
