#include "splitgrid/closest_point.hpp"

#include <limits>
#include <vector>

#include "kernels/point_search.hpp"
#include "splitgrid/baselines/bvh.hpp"
#include "splitgrid/baselines/kd_tree.hpp"
#include "splitgrid/baselines/uniform_grid.hpp"
#include "splitgrid/mesh_order.hpp"
#include "splitgrid/occupancy.hpp"
#include "splitgrid/structure_queries.hpp"
#include "structure_box.hpp"

namespace sg {
namespace {

/// Batches of fewer points are answered in their order.
constexpr std::size_t morton_batch = 32;

}  // namespace

template <class Structure>
void closest_points(const Structure& structure, const MeshView& mesh,
                    std::span<const Vec3f> points, std::span<ClosestPoint> out,
                    float max_distance) noexcept
{
    // Points taken along a Morton curve: each search then finds the nodes, leaves and corners
    // the one before it read still in the cache (docs/notebook/points.md, "Points in Morton
    // order"). Every answer is independent of the order.
    std::vector<std::uint32_t> order;
    try {
        if (points.size() >= morton_batch) order = morton_order(points, detail::root_box(structure));
    } catch (...) {
        order.clear();  // no memory for the order: the points' own order answers the same
    }
    if (order.size() != points.size()) {
        order.resize(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) order[i] = static_cast<std::uint32_t>(i);
    }
    detail::closest_point_hits(structure, mesh, points, order, out, max_distance);
}

template <class Structure>
void signed_distances(const Structure& structure, const MeshView& mesh,
                      std::span<const Vec3f> points, std::span<float> out, std::uint32_t nsamples,
                      float max_distance)
{
    // The side only where a distance was found; one batch of occupancy for those points.
    std::vector<ClosestPoint> closest(points.size());
    closest_points(structure, mesh, points, std::span<ClosestPoint>(closest), max_distance);
    std::vector<Vec3f> near;
    std::vector<std::size_t> index;
    for (std::size_t i = 0; i < points.size(); ++i) {
        out[i] = closest[i].distance;
        if (closest[i].is_hit()) {
            near.push_back(points[i]);
            index.push_back(i);
        }
    }
    std::vector<float> inside(near.size());
    compute_occupancy(structure, mesh, std::span<const Vec3f>(near), std::span<float>(inside),
                      nsamples);
    for (std::size_t j = 0; j < near.size(); ++j)
        if (inside[j] == 1.0f) out[index[j]] = -out[index[j]];
}

ClosestPoint closest_point_brute_force(const MeshView& mesh, Vec3f point,
                                       float max_distance) noexcept
{
    if (!is_finite(point)) {
        ClosestPoint out;
        out.distance = std::numeric_limits<float>::quiet_NaN();
        return out;
    }
    kernels::points::PointSearch search(point, detail::box_magnitude(bounds(mesh)), max_distance);
    for (std::uint32_t tri = 0; tri < mesh.triangle_count(); ++tri) search.offer(mesh, tri);
    return search.result();
}

#define SG_INSTANTIATE_POINT_QUERIES(Structure)                                                 \
    template void closest_points(const Structure&, const MeshView&, std::span<const Vec3f>,      \
                                 std::span<ClosestPoint>, float) noexcept;                      \
    template void signed_distances(const Structure&, const MeshView&, std::span<const Vec3f>,    \
                                   std::span<float>, std::uint32_t, float);
SG_INSTANTIATE_POINT_QUERIES(SplitGrid)
SG_INSTANTIATE_POINT_QUERIES(Bvh)
SG_INSTANTIATE_POINT_QUERIES(KdTree)
SG_INSTANTIATE_POINT_QUERIES(UniformGrid)
#undef SG_INSTANTIATE_POINT_QUERIES

}  // namespace sg
