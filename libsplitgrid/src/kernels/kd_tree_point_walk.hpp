#pragma once

// Traversal kernels, part 12: the kd-tree's closest point search (baselines/kd_tree.hpp).

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

/// Depth first, the child on the point's side of each split first; the other child waits on
/// a stack with its box, and is skipped when its box (widened by the pad the builder assigned
/// triangles with) lies beyond the search's bound by the time it is popped. Leaves share a
/// mailbox, since a triangle is referenced by every leaf it reaches.
inline void walk_kd_tree_points(const KdTree& tree, const MeshArrays& mesh,
                                points::PointSearch& search, float pad) noexcept
{
    const std::span<const KdNode> nodes = tree.nodes();
    if (nodes.empty()) return;
    const points::Vec3d q = search.point();
    const double qk[3] = {q.x, q.y, q.z};
    struct Pending {
        std::uint32_t node;
        Aabb box;
    };
    std::array<Pending, kd_max_supported_depth + 1> stack;  // only [0, sp) is read
    std::size_t sp = 0;
    stack[sp++] = Pending{0, tree.box()};
    const std::uint32_t* const refs = tree.refs().data();
    const std::uint32_t* const refs_end = refs + tree.refs().size();
    Mailbox mailbox;
    while (sp > 0) {
        Pending p = stack[--sp];
        Aabb widened = p.box;
        for (int k = 0; k < 3; ++k) {
            widened.lower[k] -= pad;
            widened.upper[k] += pad;
        }
        if (search.prunes(points::box_distance2(q, widened))) continue;
        KdNode node = nodes[p.node];
        while (!node.is_leaf()) {
            const int a = node.axis();
            const float split = node.split();
            Aabb below = p.box, above = p.box;
            below.upper[a] = split;
            above.lower[a] = split;
            const std::uint32_t below_child = p.node + 1, above_child = node.above_child();
            const bool below_first = qk[a] <= split;
            SG_ASSERT(sp < stack.size());
            stack[sp++] = below_first ? Pending{above_child, above} : Pending{below_child, below};
            p = below_first ? Pending{below_child, below} : Pending{above_child, above};
            node = nodes[p.node];
        }
        if (node.ref_count() > 0)
            test_point_ids(search, mesh, mailbox, refs + node.first_ref(), node.ref_count(),
                           refs_end);
    }
}

}  // namespace sg::kernels::SG_KERNEL_ISA
