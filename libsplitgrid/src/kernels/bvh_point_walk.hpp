#pragma once

// Traversal kernels, part 11: the BVH's closest point search (baselines/bvh.hpp).

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

/// Depth first over the wide nodes, each node's children nearest first by the distance to
/// their boxes (which hold their triangles whole, padded); a pending child is skipped when its
/// box lies beyond the search's bound by the time it is popped. A leaf's references (at most
/// eight) are measured in one batch (test_point_lanes).
inline void walk_bvh_points(const Bvh& bvh, const MeshArrays& mesh,
                            points::PointSearch& search) noexcept
{
    const std::span<const BvhWideNode> wide = bvh.wide_nodes();
    if (wide.empty() || search.prunes(points::box_distance2(search.point(), bvh.box()))) return;
    const std::uint32_t* const refs = bvh.refs().data();
    const std::uint32_t* const refs_end = refs + bvh.refs().size();
    NoMailbox no_mailbox;
    struct Pending {
        std::uint32_t child;
        std::uint32_t count;  ///< 0 for a wide node
        double distance2;
    };
    constexpr std::size_t stack_size = (BvhWideNode::width - 1) * bvh_max_supported_depth + 1;
    std::array<Pending, stack_size> stack;  // only [0, sp) is read
    std::size_t sp = 0;
    stack[sp++] = Pending{0, 0, 0.0};
    while (sp > 0) {
        const Pending p = stack[--sp];
        if (search.prunes(p.distance2)) continue;
        if (p.count != 0) {
            test_point_ids(search, mesh, no_mailbox, refs + p.child, p.count, refs_end);
            continue;
        }
        const BvhWideNode& node = wide[p.child];
        std::array<Pending, BvhWideNode::width> order;
        std::size_t m = 0;
        for (int i = 0; i < BvhWideNode::width; ++i) {
            if (node.child[i] == BvhWideNode::unused_slot) break;
            Aabb box;
            for (int k = 0; k < 3; ++k) {
                box.lower[k] = node.lower[k][i];
                box.upper[k] = node.upper[k][i];
            }
            const double d2 = points::box_distance2(search.point(), box);
            if (search.prunes(d2)) continue;
            // Insertion by distance, farthest first, so that the nearest is pushed last.
            const Pending child{node.child[i], node.count[i], d2};
            std::size_t j = m++;
            for (; j > 0 && order[j - 1].distance2 < d2; --j) order[j] = order[j - 1];
            order[j] = child;
        }
        for (std::size_t j = 0; j < m; ++j) stack[sp++] = order[j];
    }
}

}  // namespace sg::kernels::SG_KERNEL_ISA
