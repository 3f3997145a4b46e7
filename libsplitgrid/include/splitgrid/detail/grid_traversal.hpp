#pragma once

// The Split Grid's traversal, templated on the query kind and the policies of
// query_policy.hpp. Included by traverse.hpp only; use sg::intersect_with and friends.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "splitgrid/cell_math.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/query_policy.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/traversal_counters.hpp"

namespace sg {

namespace detail {

// Ray parameters of plane crossings are computed as (plane - origin) * (1 / direction): three
// roundings, so a relative error below 2^-22. Widening every interval by 2^-20 relative
// makes it contain the exact one, so no cell the ray really crosses is skipped.
template <Padding padding>
inline constexpr float grid_t_pad = padding == Padding::Conservative ? 0x1p-20f : 0.0f;

template <Padding padding>
[[nodiscard]] inline float grid_widen_down(float t) noexcept
{
    if constexpr (padding == Padding::None) return t;
    return t * (t > 0.0f ? 1.0f - grid_t_pad<padding> : 1.0f + grid_t_pad<padding>);
}
template <Padding padding>
[[nodiscard]] inline float grid_widen_up(float t) noexcept
{
    if constexpr (padding == Padding::None) return t;
    return t * (t > 0.0f ? 1.0f + grid_t_pad<padding> : 1.0f - grid_t_pad<padding>);
}

// Direction components below FLT_MIN count as zero (ray.hpp), so 1/d never overflows.
[[nodiscard]] inline Vec3f flush_denormals(Vec3f d) noexcept
{
    for (int k = 0; k < 3; ++k)
        if (std::abs(d[k]) < std::numeric_limits<float>::min()) d[k] = 0.0f;
    return d;
}

// The ray as every part of the traversal sees it.
template <class Test>
struct PreparedRay {
    Vec3f origin;
    Vec3f direction;               // denormal components flushed to zero
    std::array<float, 3> inv_dir;  // 0 where the component is zero (not used there)
    std::array<bool, 3> is_parallel;
    float t_min;
    float t_max;
    Test test;

    explicit PreparedRay(const Ray& ray) noexcept
        : origin(ray.origin), direction(flush_denormals(ray.direction)), inv_dir{}, is_parallel{},
          t_min(ray.t_min), t_max(ray.t_max), test(Ray{ray.origin, direction, ray.t_min, ray.t_max})
    {
        for (int k = 0; k < 3; ++k) {
            const auto uk = static_cast<std::size_t>(k);
            is_parallel[uk] = direction[k] == 0.0f;
            inv_dir[uk] = is_parallel[uk] ? 0.0f : 1.0f / direction[k];
        }
    }

    // Ray parameter where the ray crosses plane `coord` on `axis` (not parallel to it).
    [[nodiscard]] float crossing(int axis, float coord) const noexcept
    {
        return (coord - origin[axis]) * inv_dir[static_cast<std::size_t>(axis)];
    }

    // Narrows [t0, t1] to the part of the ray inside the slab [lo, hi] on `axis`.
    // Returns false when that part is empty.
    template <Padding padding>
    [[nodiscard]] bool clip_slab(int axis, float lo, float hi, float& t0, float& t1) const noexcept
    {
        if (is_parallel[static_cast<std::size_t>(axis)])
            return origin[axis] >= lo && origin[axis] <= hi && t0 <= t1;
        float tn = crossing(axis, lo);
        float tf = crossing(axis, hi);
        if (tn > tf) std::swap(tn, tf);
        t0 = std::max(t0, grid_widen_down<padding>(tn));
        t1 = std::min(t1, grid_widen_up<padding>(tf));
        return t0 <= t1;
    }
};

// A node whose cells are being walked, kept on the stack while a child is visited.
struct GridCursor {
    CellMath cells;            // the node's cell mapping (its width computed once)
    std::uint32_t first_cell;  // the node's cell 0 in SplitGrid::cells
    int axis;
    std::int32_t next_cell;    // next cell to visit, in ray order; -1 or N when done
    float t0;                // the ray's interval inside the node's slab
    float t1;
    float next_enter;        // widened crossing into next_cell (the last cell's exit)
};

// Max stack depth: one cursor per ancestor of the deepest node (check_invariants bounds
// the depth by max_supported_depth).
inline constexpr std::size_t grid_stack_size = max_supported_depth + 1;

// Counts work only when asked to: a null `counters` costs one predictable branch.
inline void count_node(TraversalCounters* counters) noexcept
{
    if (counters) ++counters->nodes_visited;
}
inline void count_cell(TraversalCounters* counters) noexcept
{
    if (counters) ++counters->cells_visited;
}
inline void count_triangle(TraversalCounters* counters) noexcept
{
    if (counters) ++counters->triangles_tested;
}

template <bool any_hit, class Test, Padding padding>
class GridTraversal {
public:
    GridTraversal(const SplitGrid& grid, const MeshView& mesh, const Ray& ray,
                  TraversalCounters* counters) noexcept
        : grid_(grid), mesh_(mesh), ray_(ray), counters_(counters), best_t_(ray.t_max)
    {
    }

    // Returns true on a hit; the closest one is in hit().
    bool run() noexcept
    {
        float t0 = ray_.t_min;
        float t1 = ray_.t_max;
        for (int k = 0; k < 3; ++k)
            if (!ray_.template clip_slab<padding>(k, grid_.root_box.lower[k],
                                                  grid_.root_box.upper[k], t0, t1))
                return false;
        if (grid_.root.is_empty()) return false;
        if (grid_.root.is_leaf()) {
            test_leaf(grid_.root);
            return found_;
        }
        enter_node(grid_.root.child(), t0, t1);

        while (sp_ > 0) {
            GridCursor& cur = stack_[sp_ - 1];
            const std::uint32_t n = cur.cells.n;
            const int axis = cur.axis;
            if (cur.next_cell < 0 || cur.next_cell >= static_cast<std::int32_t>(n)) {
                --sp_;
                continue;
            }
            const auto i = static_cast<std::uint32_t>(cur.next_cell);
            float c0 = cur.t0;
            float c1 = cur.t1;
            if (ray_.is_parallel[static_cast<std::size_t>(axis)]) {
                cur.next_cell = -1;  // a parallel ray stays in the one cell it started in
                if (c0 > best_t_) continue;
            } else {
                const bool forward = ray_.inv_dir[static_cast<std::size_t>(axis)] > 0.0f;
                const float leave = ray_.crossing(axis, cur.cells.boundary(forward ? i + 1 : i));
                c0 = std::max(c0, cur.next_enter);
                c1 = std::min(c1, grid_widen_up<padding>(leave));
                // The plane this cell is left through is the plane the next one is entered
                // through: the same crossing, widened the other way.
                cur.next_enter = grid_widen_down<padding>(leave);
                // Cells are in ray order: once one starts past the closest hit so far (or past
                // the node), so do all after it.
                if (c0 > std::min(cur.t1, best_t_)) {
                    --sp_;
                    continue;
                }
                cur.next_cell += forward ? 1 : -1;
            }
            count_cell(counters_);
            const CellRef cell = grid_.cells[cur.first_cell + i];
            if (cell.is_empty() || c0 > c1) continue;
            if (cell.is_leaf()) {
                if (test_leaf(cell) && any_hit) return true;
                continue;
            }
            enter_node(cell.child(), c0, c1);
        }
        return found_;
    }

    [[nodiscard]] const Hit& hit() const noexcept { return hit_; }

private:
    // Clips the ray interval to the node's bounding planes and pushes a cursor at the
    // cell the ray enters first. A full stack (ruled out by check_invariants) drops the
    // node rather than write past the stack.
    void enter_node(std::uint32_t index, float t0, float t1) noexcept
    {
        count_node(counters_);
        const GridNode& node = grid_.nodes[index];
        const int axis = node.axis();
        if (!ray_.template clip_slab<padding>(axis, node.lo, node.hi, t0, t1)) return;
        SG_ASSERT(sp_ < grid_stack_size);
        if (sp_ >= grid_stack_size) return;
        const std::uint32_t n = node.resolution();
        const CellMath cm(node.lo, node.hi, n);
        std::uint32_t i;
        float enter = t0;
        if (ray_.is_parallel[static_cast<std::size_t>(axis)]) {
            i = cm.locate_lowest(ray_.origin[axis]);
        } else {
            // Guess from the entry point, then correct with the same widened crossings the
            // walk uses, so the first cell visited is never past the true first one.
            i = cm.guess(ray_.origin[axis] + t0 * ray_.direction[axis]);
            if (ray_.inv_dir[static_cast<std::size_t>(axis)] > 0.0f) {
                while (i > 0 && grid_widen_down<padding>(ray_.crossing(axis, cm.boundary(i))) > t0)
                    --i;
                while (i + 1 < n &&
                       grid_widen_up<padding>(ray_.crossing(axis, cm.boundary(i + 1))) < t0)
                    ++i;
            } else {
                while (i + 1 < n &&
                       grid_widen_down<padding>(ray_.crossing(axis, cm.boundary(i + 1))) > t0)
                    ++i;
                while (i > 0 && grid_widen_up<padding>(ray_.crossing(axis, cm.boundary(i))) < t0)
                    --i;
            }
            const bool forward = ray_.inv_dir[static_cast<std::size_t>(axis)] > 0.0f;
            enter = grid_widen_down<padding>(ray_.crossing(axis, cm.boundary(forward ? i : i + 1)));
        }
        stack_[sp_++] =
            GridCursor{cm, node.first_cell(), axis, static_cast<std::int32_t>(i), t0, t1, enter};
    }

    bool test_leaf(CellRef cell) noexcept
    {
        bool hit_here = false;
        for (const TriangleRef* ref = grid_.triangle_refs.data() + cell.first_ref();; ++ref) {
            const TriangleRef r = *ref;
            const std::uint32_t tri = r.triangle();
            if (seen(tri)) {
                if (r.is_last()) return hit_here;
                continue;
            }
            count_triangle(counters_);
            float t, u, v;
            if (ray_.test(mesh_.vertex(tri, 0), mesh_.vertex(tri, 1), mesh_.vertex(tri, 2),
                          ray_.t_min, best_t_, t, u, v) &&
                !(found_ && !(t < best_t_))) {  // on equal t the first found stays
                found_ = hit_here = true;
                best_t_ = t;
                hit_ = Hit{t, tri, u, v};
                if constexpr (any_hit) return true;
            }
            if (r.is_last()) return hit_here;
        }
    }

    // Mailbox (Amanatides and Woo 1987): the last triangles tested. A triangle referenced by
    // neighbouring cells is tested once while the ray walks through them.
    bool seen(std::uint32_t tri) noexcept
    {
        for (std::uint32_t id : mailbox_)
            if (id == tri) return true;
        mailbox_[mailbox_next_] = tri;
        mailbox_next_ = (mailbox_next_ + 1) % mailbox_.size();
        return false;
    }

    const SplitGrid& grid_;
    const MeshView& mesh_;
    const PreparedRay<Test> ray_;
    std::array<std::uint32_t, 8> mailbox_{invalid_triangle, invalid_triangle, invalid_triangle,
                                          invalid_triangle, invalid_triangle, invalid_triangle,
                                          invalid_triangle, invalid_triangle};
    std::size_t mailbox_next_ = 0;
    TraversalCounters* counters_;
    float best_t_;
    bool found_ = false;
    Hit hit_;
    std::array<GridCursor, grid_stack_size> stack_;  // not zeroed: only [0, sp_) is ever read
    std::size_t sp_ = 0;
};

}  // namespace detail
}  // namespace sg
