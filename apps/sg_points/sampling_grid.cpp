#include "sampling_grid.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <vector>

#include "splitgrid/error.hpp"

#include <spdlog/fmt/fmt.h>

namespace sg::apps {
namespace {

constexpr GridCounts brick{16, 16, 8};
constexpr const char* axis_names[3] = {"x", "y", "z"};

std::string_view trimmed(std::string_view text)
{
    const auto first = text.find_first_not_of(" \t");
    if (first == std::string_view::npos) return {};
    const auto last = text.find_last_not_of(" \t");
    return text.substr(first, last - first + 1);
}

std::uint32_t bricks_along(const SamplingGrid& grid, int axis)
{
    return (grid.counts[axis] + brick[axis] - 1) / brick[axis];
}

}  // namespace

std::string parse_grid_counts(std::string_view text, GridCounts& counts)
{
    const std::string shown(text);
    GridCounts parsed{};
    std::string_view rest = text;
    for (int a = 0; a < 3; ++a) {
        const std::size_t comma = rest.find(',');
        if ((a < 2) == (comma == std::string_view::npos))
            return fmt::format(
                "'{}' is not NX,NY,NZ: give three point counts separated by "
                "commas, e.g. 96,96,96",
                shown);
        const std::string_view field = trimmed(rest.substr(0, comma));
        std::uint64_t value = 0;
        const char* end = field.data() + field.size();
        const auto [ptr, ec] = std::from_chars(field.data(), end, value);
        if (field.empty() || ec != std::errc{} || ptr != end || value < 1 ||
            value > max_grid_points)
            return fmt::format("'{}': the {} count '{}' is not a whole number in [1, {}]", shown,
                               axis_names[a], field, max_grid_points);
        parsed[a] = static_cast<std::uint32_t>(value);
        rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
    }
    const std::uint64_t points = std::uint64_t{parsed[0]} * parsed[1] * parsed[2];
    if (points > max_grid_points) {
        const auto side =
            static_cast<std::uint64_t>(std::cbrt(static_cast<double>(max_grid_points)));
        return fmt::format("'{}' is {} points, more than the limit of {} ({},{},{} fits)", shown,
                           points, max_grid_points, side, side, side);
    }
    counts = parsed;
    return {};
}

Vec3f SamplingGrid::point(std::uint64_t n) const noexcept
{
    const std::uint64_t i = n % counts[0];
    const std::uint64_t j = n / counts[0] % counts[1];
    const std::uint64_t k = n / counts[0] / counts[1];
    return {static_cast<float>(origin[0] + static_cast<double>(i) * spacing[0]),
            static_cast<float>(origin[1] + static_cast<double>(j) * spacing[1]),
            static_cast<float>(origin[2] + static_cast<double>(k) * spacing[2])};
}

SamplingGrid grid_around(const Aabb& box, const GridCounts& counts, double padding)
{
    double diagonal_squared = 0.0;
    for (int a = 0; a < 3; ++a) {
        const double extent = static_cast<double>(box.upper[a]) - box.lower[a];
        diagonal_squared += extent * extent;
    }
    const double pad = padding * std::sqrt(diagonal_squared);
    SamplingGrid grid;
    grid.counts = counts;
    for (int a = 0; a < 3; ++a) {
        const double lower = static_cast<double>(box.lower[a]) - pad;
        const double upper = static_cast<double>(box.upper[a]) + pad;
        if (!(std::abs(lower) <= std::numeric_limits<float>::max() &&
              std::abs(upper) <= std::numeric_limits<float>::max()))
            throw ConfigError(
                fmt::format("--padding {}: the widened box reaches beyond the "
                            "float32 range on {}",
                            padding, axis_names[a]));
        const double extent = upper - lower;
        if (counts[a] == 1) {
            grid.origin[a] = 0.5 * (lower + upper);
            grid.spacing[a] = extent > 0.0 ? extent : std::sqrt(diagonal_squared);
            continue;
        }
        if (!(extent > 0.0))
            throw ConfigError(
                fmt::format("--grid: the mesh is flat along {} and --padding is "
                            "0, so its {} points would coincide; give --padding "
                            "above 0 or 1 point along {}",
                            axis_names[a], counts[a], axis_names[a]));
        grid.origin[a] = lower;
        grid.spacing[a] = extent / static_cast<double>(counts[a] - 1);
    }
    return grid;
}

PointBlocks brick_blocks(const SamplingGrid& grid)
{
    PointBlocks blocks;
    blocks.point_count = static_cast<std::size_t>(grid.point_count());
    const std::uint32_t bx = bricks_along(grid, 0);
    const std::uint32_t by = bricks_along(grid, 1);
    blocks.block_count = std::size_t{bx} * by * bricks_along(grid, 2);
    blocks.fill = [grid, bx, by](std::size_t block, std::vector<Vec3f>& points,
                                 std::vector<std::size_t>& index) {
        const std::array<std::size_t, 3> b{block % bx, block / bx % by, block / bx / by};
        std::array<std::size_t, 3> first{}, last{};
        for (int a = 0; a < 3; ++a) {
            first[a] = b[a] * brick[a];
            last[a] = std::min<std::size_t>(first[a] + brick[a], grid.counts[a]);
        }
        points.clear();
        index.clear();
        for (std::size_t k = first[2]; k < last[2]; ++k)
            for (std::size_t j = first[1]; j < last[1]; ++j)
                for (std::size_t i = first[0]; i < last[0]; ++i) {
                    const std::size_t n = i + grid.counts[0] * (j + grid.counts[1] * k);
                    index.push_back(n);
                    points.push_back(grid.point(n));
                }
    };
    return blocks;
}

}  // namespace sg::apps
