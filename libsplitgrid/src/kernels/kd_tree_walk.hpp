#pragma once

// Traversal kernels, part 7: the kd-tree's traversal (baselines/kd_tree.hpp).

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

/// Front to back with a stack of far children (Wald's thesis, pbrt): the near child's
/// interval ends at the split crossing widened up, the far child's starts at it widened down,
/// so the two overlap around the plane and no ray slips between them; a ray parallel to the
/// plane goes to the side holding its origin, or to both when it lies in the plane.
/// Triangles are referenced by every leaf they reach, so leaves share a mailbox.
/// Counters: nodes_visited = inner nodes, cells_visited = leaves.
template <TriangleTest test, class Search>
inline void walk_kd_tree(const KdTree& tree, const MeshArrays& mesh, const KernelRay& ray,
                         Search& search) noexcept
{
    const std::span<const KdNode> nodes = tree.nodes();
    if (nodes.empty()) return;
    float t0 = ray.t_min;
    float t1 = ray.t_max;
    if (!ray.clip_box(tree.box(), t0, t1)) return;
    const std::uint32_t* const refs = tree.refs().data();
    const std::uint32_t* const refs_end = refs + tree.refs().size();
    Mailbox mailbox;

    struct Pending {
        std::uint32_t node;
        float t0;
        float t1;
    };
    std::array<Pending, kd_max_supported_depth + 1> stack;  // only [0, sp) is read
    std::size_t sp = 0;
    std::uint32_t index = 0;
    for (;;) {
        KdNode node = nodes[index];
        while (!node.is_leaf()) {
            search.count_node();
            const int a = node.axis();
            const float split = node.split();
            const std::uint32_t below = index + 1;
            const std::uint32_t above = node.above_child();
            if (ray.parallel[a]) {
                if (ray.origin[a] < split) {
                    index = below;
                } else if (ray.origin[a] > split) {
                    index = above;
                } else {
                    SG_ASSERT(sp < stack.size());
                    stack[sp++] = Pending{above, t0, t1};
                    index = below;
                }
            } else {
                // Children in ray order by the direction's sign (robust for an origin on the
                // plane, where the crossing is +-0).
                const float t_split = ray.crossing(a, split);
                const bool below_first = !ray.negative[a];
                const std::uint32_t first = below_first ? below : above;
                const std::uint32_t second = below_first ? above : below;
                const float first_end = std::min(t1, t_split + ray.pad[a]);
                const float second_start = std::max(t0, t_split - ray.pad[a]);
                const bool visit_first = t0 <= first_end;
                const bool visit_second = second_start <= t1;
                if (visit_first) {
                    if (visit_second) {
                        SG_ASSERT(sp < stack.size());
                        stack[sp++] = Pending{second, second_start, t1};
                    }
                    index = first;
                    t1 = first_end;
                } else {
                    index = second;
                    t0 = second_start;
                }
            }
            node = nodes[index];
        }
        search.count_cell();
        if (node.ref_count() > 0) {
            (void)test_id_leaf<test>(ray, mesh, search, mailbox, refs + node.first_ref(),
                                     node.ref_count(), refs_end);
        }
        if (search.done()) return;
        // Next pending node that may still hold a closer hit; hits beyond this leaf's interval
        // are kept as candidates and cut the rest off here.
        for (;;) {
            if (sp == 0) return;
            const Pending& next = stack[--sp];
            if (next.t0 <= search.best_t()) {
                index = next.node;
                t0 = next.t0;
                t1 = next.t1;
                break;
            }
        }
    }
}

}  // namespace sg::kernels::SG_KERNEL_ISA
