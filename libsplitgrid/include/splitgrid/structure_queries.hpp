#pragma once

#include <cstdint>
#include <span>

#include "splitgrid/closest_point.hpp"
#include "splitgrid/intersections.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/query.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/traversal_counters.hpp"

namespace sg {

namespace detail {

/// The dispatched queries behind every structure's intersect() and occluded(): they run the
/// kernels of kernel_isa() (src/kernels/). Defined for SplitGrid, Bvh, KdTree and UniformGrid.
/// `total`, when not null, gets the work of every ray added to it.
template <class Structure>
void closest_hits(const Structure& structure, const MeshView& mesh, std::span<const Ray> rays,
                  std::span<Hit> hits, TraversalCounters* total,
                  const QueryOptions& options) noexcept;
template <class Structure>
void any_hits(const Structure& structure, const MeshView& mesh, std::span<const Ray> rays,
              std::span<std::uint8_t> occluded, TraversalCounters* total) noexcept;
template <class Structure>
void count_hits(const Structure& structure, const MeshView& mesh, std::span<const Ray> rays,
                std::span<std::int32_t> counts, TriangleTest test) noexcept;
template <class Structure>
void all_hits(const Structure& structure, const MeshView& mesh, std::span<const Ray> rays,
              IntersectionList& out);
/// The closest point of each of `points`, taken in `order` (closest_point.hpp).
template <class Structure>
void closest_point_hits(const Structure& structure, const MeshView& mesh,
                        std::span<const Vec3f> points, std::span<const std::uint32_t> order,
                        std::span<ClosestPoint> out, float max_distance) noexcept;

}  // namespace detail

/// The queries every comparison structure offers (inherited by UniformGrid, KdTree and Bvh),
/// with the semantics of the Split Grid's (traverse.hpp): the smallest t in the closed window
/// [t_min, t_max] found by the query's triangle test, the smallest triangle id on equal t;
/// invalid rays (is_valid) miss without touching the structure; a miss has t = t_max. `mesh`
/// must be the mesh the structure was built on. Each structure's header says what its counters count.
template <class Structure>
class StructureQueries {
public:
    /// Closest hit; `counters`, when given, gets this query's work added.
    [[nodiscard]] Hit intersect(const MeshView& mesh, const Ray& ray,
                                TraversalCounters* counters = nullptr,
                                const QueryOptions& options = {}) const noexcept
    {
        Hit hit;
        detail::closest_hits(self(), mesh, {&ray, 1}, {&hit, 1}, counters, options);
        return hit;
    }
    /// True if any triangle is hit in [t_min, t_max] (watertight test); stops at the first.
    [[nodiscard]] bool occluded(const MeshView& mesh, const Ray& ray,
                                TraversalCounters* counters = nullptr) const noexcept
    {
        std::uint8_t out = 0;
        detail::any_hits(self(), mesh, {&ray, 1}, {&out, 1}, counters);
        return out != 0;
    }
    /// Closest hits of a batch (`hits` has rays.size() entries), serially in the calling
    /// thread; `total` gets the work of all rays added.
    void intersect(const MeshView& mesh, std::span<const Ray> rays, std::span<Hit> hits,
                   TraversalCounters* total = nullptr, const QueryOptions& options = {}) const noexcept
    {
        detail::closest_hits(self(), mesh, rays, hits, total, options);
    }
    /// Any-hit answers of a batch (1 = occluded).
    void occluded(const MeshView& mesh, std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                  TraversalCounters* total = nullptr) const noexcept
    {
        detail::any_hits(self(), mesh, rays, occluded, total);
    }

    /// The number of distinct triangles each ray hits in [t_min, t_max] (`counts` has
    /// rays.size() entries; 0 for an invalid ray), serially in the calling thread; see
    /// sg::count_intersections (traverse.hpp).
    void count_intersections(const MeshView& mesh, std::span<const Ray> rays,
                             std::span<std::int32_t> counts,
                             TriangleTest test = TriangleTest::watertight) const noexcept
    {
        detail::count_hits(self(), mesh, rays, counts, test);
    }
    /// Every hit of each ray, appended to `out`; see sg::list_intersections (traverse.hpp).
    void list_intersections(const MeshView& mesh, std::span<const Ray> rays,
                            IntersectionList& out) const
    {
        detail::all_hits(self(), mesh, rays, out);
    }

    friend bool operator==(const StructureQueries&, const StructureQueries&) = default;

private:
    [[nodiscard]] const Structure& self() const noexcept
    {
        return static_cast<const Structure&>(*this);
    }
};

}  // namespace sg
