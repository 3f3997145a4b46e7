#pragma once

// Point queries, part 4: the kd-tree's closest point search (baselines/kd_tree.hpp).

#include <array>

#include "point_search.hpp"
#include "splitgrid/baselines/kd_tree.hpp"

namespace sg::kernels::points {

/// Depth first, the child on the point's side of each split first; the other child waits on
/// a stack with its box, and is skipped when its box (widened by the pad the builder assigned
/// triangles with) lies beyond the search's bound by the time it is popped.
inline void walk_kd_tree(const KdTree& tree, const MeshView& mesh, PointSearch& search,
                         float pad) noexcept
{
    const std::span<const KdNode> nodes = tree.nodes();
    if (nodes.empty()) return;
    auto widened = [pad](Aabb box) {
        for (int k = 0; k < 3; ++k) {
            box.lower[k] -= pad;
            box.upper[k] += pad;
        }
        return box;
    };
    const Vec3d q = search.point();
    const double qk[3] = {q.x, q.y, q.z};
    struct Pending {
        std::uint32_t node;
        Aabb box;
    };
    std::array<Pending, kd_max_supported_depth + 1> stack;  // only [0, sp) is read
    std::size_t sp = 0;
    stack[sp++] = Pending{0, tree.box()};
    const std::uint32_t* const refs = tree.refs().data();
    PointMailbox mailbox;  // a triangle is referenced by every leaf it reaches
    while (sp > 0) {
        Pending p = stack[--sp];
        if (search.prunes(box_distance2(q, widened(p.box)))) continue;
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
        for (std::uint32_t k = 0; k < node.ref_count(); ++k) {
            const std::uint32_t tri = refs[node.first_ref() + k];
            if (mailbox.first_visit(tri)) search.offer(mesh, tri);
        }
    }
}

}  // namespace sg::kernels::points
