#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <string_view>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/closest_point.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/vec3.hpp"

#include <tbb/task_arena.h>

/// The queries of sg-points, run in parallel over blocks of points against the Split Grid of
/// a .sg file: what each query answers is the library's (occupancy.hpp, closest_point.hpp);
/// this file only cuts the points into blocks and gathers the answers in point order.
namespace sg::apps {

enum class PointQuery {
    occupancy,        ///< compute_occupancy: 1 inside, 0 outside
    distance,         ///< closest_points' distance
    signed_distance,  ///< signed_distances: negative inside
    closest,          ///< closest_points: triangle, distance, barycentrics, point
};

/// The query's name on the command line: "occupancy", "distance", "signed-distance",
/// "closest".
[[nodiscard]] std::string_view query_name(PointQuery query) noexcept;
/// Every query, in the order of the enumeration.
[[nodiscard]] std::span<const PointQuery> every_query() noexcept;

/// Whether the query casts rays (--nsamples): occupancy and signed-distance.
[[nodiscard]] bool casts_rays(PointQuery query) noexcept;
/// Whether the query measures distances (--max-distance): all but occupancy.
[[nodiscard]] bool measures_distance(PointQuery query) noexcept;

struct QuerySettings {
    PointQuery query = PointQuery::occupancy;
    std::uint32_t nsamples = 1;  ///< rays per point (odd), for casts_rays queries
    float max_distance = std::numeric_limits<float>::infinity();  ///< > 0
};

/// The answers, in point order: `values` for occupancy, distance and signed distance,
/// `closest` for the closest point query (the other vector stays empty).
struct PointAnswers {
    std::vector<float> values;
    std::vector<ClosestPoint> closest;
};

/// The points to answer, cut into blocks that one task answers together (so that the
/// library's searches for neighbouring points find the same nodes still in the cache).
struct PointBlocks {
    std::size_t point_count = 0;
    std::size_t block_count = 0;
    /// Sets `points` to the points of block `block` and `index` to the position of each in
    /// the answers.
    std::function<void(std::size_t block, std::vector<Vec3f>& points,
                       std::vector<std::size_t>& index)>
        fill;
};

/// Blocks of `points` (which must outlive them) taken along a Morton curve over `box`
/// (sg::morton_order), `block_size` points each.
[[nodiscard]] PointBlocks morton_blocks(std::span<const Vec3f> points, const Aabb& box,
                                        std::size_t block_size);

/// Points per block: a block of occupancy costs nsamples ray walks per point, a block of the
/// distance queries one search per point.
[[nodiscard]] std::size_t block_size_for(PointQuery query) noexcept;

/// Answers `settings.query` for every point of `blocks`, in the tasks of `arena`. The answers
/// do not depend on the blocks or the thread count. Throws ConfigError for an even nsamples
/// (as the library does).
[[nodiscard]] PointAnswers answer_points(const SgContents& contents, const QuerySettings& settings,
                                         const PointBlocks& blocks, tbb::task_arena& arena);

}  // namespace sg::apps
