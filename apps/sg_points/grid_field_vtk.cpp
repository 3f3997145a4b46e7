#include <cstdint>
#include <limits>

#include "grid_field.hpp"
#include "splitgrid/viz/image_field.hpp"
#include "splitgrid/viz/library_versions.hpp"

namespace sg::apps {
namespace {

/// The array of the queries answered by one float per point.
const char* value_array_name(PointQuery query) noexcept
{
    switch (query) {
    case PointQuery::occupancy:
        return "occupancy";
    case PointQuery::signed_distance:
        return "signed_distance";
    case PointQuery::distance:
    case PointQuery::closest:
        return "distance";
    }
    return "?";
}

}  // namespace

std::string why_no_grid_field() { return {}; }

std::vector<LibraryVersion> grid_field_libraries() { return viz::viz_library_versions(); }

void write_grid_field(OutputFile& output, const SamplingGrid& grid, PointQuery query,
                      const PointAnswers& answers, const GridFieldFacts& facts)
{
    viz::ImageField field;
    field.geometry = {grid.counts, grid.origin, grid.spacing};
    field.text_facts = facts.texts;
    field.number_facts = facts.numbers;
    if (query != PointQuery::closest) {
        field.floats.push_back({value_array_name(query), answers.values, 1});
        viz::write_image_field(output, field);
        return;
    }
    // The closest point record split into arrays ParaView colours and glyphs by.
    const std::size_t n = answers.closest.size();
    std::vector<float> distance(n);
    std::vector<std::uint32_t> triangle(n);
    std::vector<float> point(3 * n, std::numeric_limits<float>::quiet_NaN());
    for (std::size_t i = 0; i < n; ++i) {
        const ClosestPoint& c = answers.closest[i];
        distance[i] = c.distance;
        triangle[i] = c.triangle;
        if (!c.is_hit()) continue;
        for (int a = 0; a < 3; ++a) point[3 * i + static_cast<std::size_t>(a)] = c.point[a];
    }
    field.floats.push_back({value_array_name(query), distance, 1});
    field.floats.push_back({"closest_point", point, 3});
    field.ids.push_back({"triangle_id", triangle});
    viz::write_image_field(output, field);
}

}  // namespace sg::apps
