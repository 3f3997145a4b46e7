#pragma once

// Point queries, part 3: the BVH's closest point search (baselines/bvh.hpp).

#include <array>

#include "point_search.hpp"
#include "splitgrid/baselines/bvh.hpp"

namespace sg::kernels::points {

/// Depth first over the wide nodes, each node's children nearest first by the distance to
/// their boxes (which hold their triangles whole, padded); a pending child is skipped when its
/// box lies beyond the search's bound by the time it is popped.
inline void walk_bvh(const Bvh& bvh, const MeshView& mesh, PointSearch& search) noexcept
{
    const std::span<const BvhWideNode> wide = bvh.wide_nodes();
    if (wide.empty() || search.prunes(box_distance2(search.point(), bvh.box()))) return;
    const std::uint32_t* const refs = bvh.refs().data();
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
            for (std::uint32_t k = 0; k < p.count; ++k) search.offer(mesh, refs[p.child + k]);
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
            const double d2 = box_distance2(search.point(), box);
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

}  // namespace sg::kernels::points
