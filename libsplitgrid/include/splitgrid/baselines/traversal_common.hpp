#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include <algorithm>
#include <utility>

#include "splitgrid/aabb.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/query_policy.hpp"
#include "splitgrid/ray_triangle.hpp"
#include "splitgrid/traverse.hpp"

/// What the three comparison structures (uniform_grid.hpp, kd_tree.hpp, bvh.hpp) share: the
/// ray set-up and hit bookkeeping of a query, templated on the triangle-test and padding
/// policies of query_policy.hpp. The Split Grid's own traverser (traverse.hpp) is not built
/// on this; the semantics are the same (ray.hpp).

namespace sg {

namespace detail {

/// The ray as the baseline traversals see it: direction components below FLT_MIN flushed to
/// (signed) zero as ray.hpp specifies, and their reciprocals (+-infinity for zero
/// components, which the BVH's slab test relies on).
struct BaselineRay {
    Vec3f origin;
    Vec3f direction;
    Vec3f inv_dir;
    bool is_parallel[3];
    float t_min;
    float t_max;

    explicit BaselineRay(const Ray& ray) noexcept
        : origin(ray.origin), direction(ray.direction), t_min(ray.t_min), t_max(ray.t_max)
    {
        for (int k = 0; k < 3; ++k) {
            if (std::abs(direction[k]) < std::numeric_limits<float>::min())
                direction[k] = std::copysign(0.0f, direction[k]);
            is_parallel[k] = direction[k] == 0.0f;
            inv_dir[k] = 1.0f / direction[k];
        }
    }
    [[nodiscard]] Ray flushed() const noexcept { return Ray{origin, direction, t_min, t_max}; }
    /// Ray parameter of the plane `coord` on `axis`; precondition: not parallel to it.
    [[nodiscard]] float crossing(int axis, float coord) const noexcept
    {
        return (coord - origin[axis]) * inv_dir[axis];
    }
};

/// Moves t down (widen_down) or up (widen_up) by `pad` relative, whatever its sign: the
/// interval [widen_down(a), widen_up(b)] contains [a, b] and every value within a relative
/// error of `pad` of its ends. Infinities stay as they are.
[[nodiscard]] inline float widen_down(float t, float pad) noexcept
{
    return t * (t > 0.0f ? 1.0f - pad : 1.0f + pad);
}
[[nodiscard]] inline float widen_up(float t, float pad) noexcept
{
    return t * (t > 0.0f ? 1.0f + pad : 1.0f - pad);
}

/// Narrows [t0, t1] to the part of the ray inside the closed `box`, each plane crossing
/// widened by `pad` relative; false if nothing is left. An axis the ray is parallel to keeps
/// the interval if the origin lies in the box's slab (faces included).
[[nodiscard]] inline bool clip_to_box(const BaselineRay& ray, const Aabb& box, float pad, float& t0,
                                      float& t1) noexcept
{
    for (int k = 0; k < 3; ++k) {
        if (ray.is_parallel[k]) {
            if (!(ray.origin[k] >= box.lower[k] && ray.origin[k] <= box.upper[k])) return false;
            continue;
        }
        float tn = ray.crossing(k, box.lower[k]);
        float tf = ray.crossing(k, box.upper[k]);
        if (tn > tf) std::swap(tn, tf);
        t0 = std::max(t0, widen_down(tn, pad));
        t1 = std::min(t1, widen_up(tf, pad));
    }
    return t0 <= t1;
}

/// Closest-hit (any_hit = false) or any-hit bookkeeping of one query: tests triangles with
/// the policy over [t_min, best t so far], keeps the smallest t (the first found on ties, as
/// intersect_brute_force does) and counts the tests.
template <class Test, bool any_hit>
class HitSearch {
public:
    HitSearch(const MeshView& mesh, const BaselineRay& ray, TraversalCounters* counters) noexcept
        : mesh_(mesh), test_(ray.flushed()), counters_(counters), t_min_(ray.t_min),
          best_t_(ray.t_max)
    {
    }

    /// Tests one triangle; true if it is the new closest hit (any hit, for any_hit).
    bool test(std::uint32_t tri) noexcept
    {
        if (counters_) ++counters_->triangles_tested;
        float t, u, v;
        if (!test_(mesh_.vertex(tri, 0), mesh_.vertex(tri, 1), mesh_.vertex(tri, 2), t_min_,
                   best_t_, t, u, v))
            return false;
        if (hit_.is_hit() && !(t < best_t_)) return false;
        best_t_ = t;
        hit_ = Hit{t, tri, u, v};
        return true;
    }
    /// Tests refs[first, first + count); true if one of them is a new closest (or any) hit.
    bool test_all(const std::uint32_t* refs, std::uint32_t count) noexcept
    {
        bool improved = false;
        for (std::uint32_t k = 0; k < count; ++k) {
            if (test(refs[k])) {
                improved = true;
                if constexpr (any_hit) return true;
            }
        }
        return improved;
    }

    [[nodiscard]] bool found() const noexcept { return hit_.is_hit(); }
    /// t_max of the ray until a hit is found, then the closest hit's t.
    [[nodiscard]] float best_t() const noexcept { return best_t_; }
    /// True once an any-hit query may stop.
    [[nodiscard]] bool done() const noexcept { return any_hit && hit_.is_hit(); }
    [[nodiscard]] const Hit& hit() const noexcept { return hit_; }
    void count_node() noexcept
    {
        if (counters_) ++counters_->nodes_visited;
    }
    void count_cell() noexcept
    {
        if (counters_) ++counters_->cells_visited;
    }

private:
    const MeshView& mesh_;
    const Test test_;
    TraversalCounters* counters_;
    float t_min_;
    float best_t_;
    Hit hit_;
};

/// The last `size` triangles one query has tested (mailboxing, Amanatides and Woo 1987): a
/// triangle that spans several cells is tested once while the ray walks through them. It lives
/// on the query's stack, so concurrent queries share nothing.
template <std::size_t size>
class Mailbox {
public:
    /// True if `tri` is among the last `size` triangles seen; records it otherwise.
    bool seen(std::uint32_t tri) noexcept
    {
        for (std::uint32_t id : ids_)
            if (id == tri) return true;
        ids_[next_] = tri;
        next_ = (next_ + 1) % size;
        return false;
    }

private:
    std::array<std::uint32_t, size> ids_ = make_empty();
    std::size_t next_ = 0;
    static constexpr std::array<std::uint32_t, size> make_empty() noexcept
    {
        std::array<std::uint32_t, size> a{};
        a.fill(invalid_triangle);
        return a;
    }
};

/// Runs `walk(ray, search)` for a closest-hit query with the semantics of ray.hpp: invalid
/// rays miss without touching the structure; a miss has t = t_max.
template <class Test, class Walk>
[[nodiscard]] Hit closest_hit_query(const MeshView& mesh, const Ray& ray,
                                    TraversalCounters* counters, const Walk& walk) noexcept
{
    Hit miss;
    miss.t = ray.t_max;
    if (!is_valid(ray)) return miss;
    const BaselineRay prepared(ray);
    HitSearch<Test, false> search(mesh, prepared, counters);
    walk(prepared, search);
    return search.found() ? search.hit() : miss;
}

/// The same for an any-hit query: true if any triangle is hit in [t_min, t_max].
template <class Test, class Walk>
[[nodiscard]] bool any_hit_query(const MeshView& mesh, const Ray& ray,
                                 TraversalCounters* counters, const Walk& walk) noexcept
{
    if (!is_valid(ray)) return false;
    const BaselineRay prepared(ray);
    HitSearch<Test, true> search(mesh, prepared, counters);
    walk(prepared, search);
    return search.found();
}

}  // namespace detail

/// The queries every comparison structure offers, inherited by UniformGrid, KdTree and Bvh
/// (which supply `walk<padding>(ray, search)`). Semantics of intersect() in traverse.hpp:
/// the smallest t in the closed window [t_min, t_max] found by the watertight test; invalid
/// rays (see is_valid) miss without touching the structure; a miss has t = t_max. `mesh` must
/// be the mesh the structure was built on. The counters' meaning is given per structure.
template <class Structure>
class BaselineQueries {
public:
    /// Closest hit.
    [[nodiscard]] Hit intersect(const MeshView& mesh, const Ray& ray,
                                TraversalCounters* counters = nullptr) const noexcept
    {
        return intersect_with<>(mesh, ray, counters);
    }
    /// True if any triangle is hit in [t_min, t_max]; stops at the first.
    [[nodiscard]] bool occluded(const MeshView& mesh, const Ray& ray,
                                TraversalCounters* counters = nullptr) const noexcept
    {
        return occluded_with<>(mesh, ray, counters);
    }

    /// The same queries with another triangle-test policy (see WatertightTest) or without the
    /// traversal's conservative widening (Padding::None), for sg-bench's speed/accuracy chart.
    template <class Test = WatertightTest, Padding padding = Padding::Conservative>
    [[nodiscard]] Hit intersect_with(const MeshView& mesh, const Ray& ray,
                                     TraversalCounters* counters = nullptr) const noexcept
    {
        return detail::closest_hit_query<Test>(mesh, ray, counters, [&](const detail::BaselineRay& r, auto& s) {
            static_cast<const Structure&>(*this).template walk<padding>(r, s);
        });
    }
    template <class Test = WatertightTest, Padding padding = Padding::Conservative>
    [[nodiscard]] bool occluded_with(const MeshView& mesh, const Ray& ray,
                                     TraversalCounters* counters = nullptr) const noexcept
    {
        return detail::any_hit_query<Test>(mesh, ray, counters, [&](const detail::BaselineRay& r, auto& s) {
            static_cast<const Structure&>(*this).template walk<padding>(r, s);
        });
    }

    friend bool operator==(const BaselineQueries&, const BaselineQueries&) = default;
};

}  // namespace sg
