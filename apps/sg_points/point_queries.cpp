#include "point_queries.hpp"

#include <algorithm>
#include <array>
#include <limits>

#include "splitgrid/mesh_order.hpp"
#include "splitgrid/occupancy.hpp"

#include <tbb/parallel_for.h>

namespace sg::apps {
namespace {

constexpr std::array<PointQuery, 4> queries{PointQuery::occupancy, PointQuery::distance,
                                            PointQuery::signed_distance, PointQuery::closest};

/// Answers one block of points into the answers at `index`.
void answer_block(const SgContents& contents, const QuerySettings& settings,
                  std::span<const Vec3f> points, std::span<const std::size_t> index,
                  PointAnswers& answers)
{
    const MeshView mesh = contents.mesh.view();
    switch (settings.query) {
    case PointQuery::occupancy:
    case PointQuery::signed_distance: {
        std::vector<float> values(points.size());
        if (settings.query == PointQuery::occupancy)
            compute_occupancy(contents.grid, mesh, points, std::span<float>(values),
                              settings.nsamples);
        else
            signed_distances(contents.grid, mesh, points, std::span<float>(values),
                             settings.nsamples, settings.max_distance);
        for (std::size_t k = 0; k < points.size(); ++k) answers.values[index[k]] = values[k];
        return;
    }
    case PointQuery::distance:
    case PointQuery::closest: {
        std::vector<ClosestPoint> closest(points.size());
        closest_points(contents.grid, mesh, points, std::span<ClosestPoint>(closest),
                       settings.max_distance);
        for (std::size_t k = 0; k < points.size(); ++k) {
            if (settings.query == PointQuery::distance)
                answers.values[index[k]] = closest[k].distance;
            else
                answers.closest[index[k]] = closest[k];
        }
        return;
    }
    }
}

}  // namespace

std::string_view query_name(PointQuery query) noexcept
{
    switch (query) {
    case PointQuery::occupancy:
        return "occupancy";
    case PointQuery::distance:
        return "distance";
    case PointQuery::signed_distance:
        return "signed-distance";
    case PointQuery::closest:
        return "closest";
    }
    return "?";
}

std::span<const PointQuery> every_query() noexcept { return queries; }

bool casts_rays(PointQuery query) noexcept
{
    return query == PointQuery::occupancy || query == PointQuery::signed_distance;
}

bool measures_distance(PointQuery query) noexcept { return query != PointQuery::occupancy; }

std::size_t block_size_for(PointQuery query) noexcept
{
    return query == PointQuery::occupancy ? 256 : 1024;
}

PointBlocks morton_blocks(std::span<const Vec3f> points, const Aabb& box, std::size_t block_size)
{
    // morton_order counts in 32 bits; a larger file is answered in its own order.
    std::vector<std::uint32_t> order;
    if (points.size() <= std::numeric_limits<std::uint32_t>::max())
        order = morton_order(points, box);
    PointBlocks blocks;
    blocks.point_count = points.size();
    blocks.block_count = (points.size() + block_size - 1) / block_size;
    blocks.fill = [points, block_size, order = std::move(order)](std::size_t block,
                                                                 std::vector<Vec3f>& out,
                                                                 std::vector<std::size_t>& index) {
        const std::size_t first = block * block_size;
        const std::size_t n = std::min(block_size, points.size() - first);
        out.resize(n);
        index.resize(n);
        for (std::size_t k = 0; k < n; ++k) {
            index[k] = order.empty() ? first + k : order[first + k];
            out[k] = points[index[k]];
        }
    };
    return blocks;
}

PointAnswers answer_points(const SgContents& contents, const QuerySettings& settings,
                           const PointBlocks& blocks, tbb::task_arena& arena)
{
    PointAnswers answers;
    if (settings.query == PointQuery::closest)
        answers.closest.resize(blocks.point_count);
    else
        answers.values.resize(blocks.point_count);
    arena.execute([&] {
        tbb::parallel_for(std::size_t{0}, blocks.block_count, [&](std::size_t block) {
            std::vector<Vec3f> points;
            std::vector<std::size_t> index;
            blocks.fill(block, points, index);
            answer_block(contents, settings, points, index, answers);
        });
    });
    return answers;
}

}  // namespace sg::apps
