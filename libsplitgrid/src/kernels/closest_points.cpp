// Closest point queries for every structure (closest_point.hpp): the drivers around the point
// walks of src/kernels/*_point_walk.hpp.

#include <cmath>
#include <limits>
#include <vector>

#include "bvh_point_walk.hpp"
#include "kd_tree_point_walk.hpp"
#include "point_search.hpp"
#include "split_grid_point_walk.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/closest_point.hpp"
#include "splitgrid/mesh_order.hpp"
#include "splitgrid/occupancy.hpp"
#include "uniform_grid_point_walk.hpp"

namespace sg {
namespace {

using kernels::points::PointSearch;

/// Batches of fewer points are answered in their order.
constexpr std::size_t morton_batch = 32;

/// Largest coordinate magnitude of `box` (0 for an empty box): the M of the tolerance.
float magnitude(const Aabb& box) noexcept
{
    if (box.is_empty()) return 0.0f;
    float m = 0.0f;
    for (int k = 0; k < 3; ++k) m = std::max({m, std::abs(box.lower[k]), std::abs(box.upper[k])});
    return m;
}

const Aabb& root_box(const SplitGrid& grid) noexcept { return grid.root_box; }
template <class Structure>
const Aabb& root_box(const Structure& structure) noexcept
{
    return structure.box();
}

void walk(const SplitGrid& grid, const MeshView& mesh, PointSearch& search, float pad) noexcept
{
    kernels::points::SplitGridPointWalk(grid, mesh, search, pad).run();
}
void walk(const Bvh& bvh, const MeshView& mesh, PointSearch& search, float) noexcept
{
    kernels::points::walk_bvh(bvh, mesh, search);  // its boxes hold whole padded triangles
}
void walk(const KdTree& tree, const MeshView& mesh, PointSearch& search, float pad) noexcept
{
    kernels::points::walk_kd_tree(tree, mesh, search, pad);
}
void walk(const UniformGrid& grid, const MeshView& mesh, PointSearch& search, float pad) noexcept
{
    kernels::points::walk_uniform_grid(grid, mesh, search, pad);
}

ClosestPoint invalid_point() noexcept
{
    ClosestPoint out;
    out.distance = std::numeric_limits<float>::quiet_NaN();
    return out;
}

}  // namespace

template <class Structure>
void closest_points(const Structure& structure, const MeshView& mesh,
                    std::span<const Vec3f> points, std::span<ClosestPoint> out,
                    float max_distance) noexcept
{
    const Aabb& box = root_box(structure);
    const float m = magnitude(box);
    const float pad = box.is_empty() ? 0.0f : boundary_pad(box);
    auto answer = [&](std::size_t i) {
        if (!is_finite(points[i])) {
            out[i] = invalid_point();
            return;
        }
        PointSearch search(points[i], m, max_distance);
        walk(structure, mesh, search, pad);
        out[i] = search.result();
    };
    // Points taken along a Morton curve: each search then finds the nodes, leaves and corners
    // the one before it read still in the cache (docs/notebook/points.md, "Points in Morton
    // order"). Every answer is independent of the order.
    if (points.size() < morton_batch) {
        for (std::size_t i = 0; i < points.size(); ++i) answer(i);
        return;
    }
    for (const std::uint32_t i : morton_order(points, box)) answer(i);
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
    if (!is_finite(point)) return invalid_point();
    PointSearch search(point, magnitude(bounds(mesh)), max_distance);
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
