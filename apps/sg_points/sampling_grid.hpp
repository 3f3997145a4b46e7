#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "point_queries.hpp"
#include "splitgrid/aabb.hpp"
#include "splitgrid/vec3.hpp"

/// The regular grid of points sg-points --grid answers its query on: NX x NY x NZ points over
/// the mesh's bounding box widened on every side by a share of its diagonal, x fastest (the
/// order of VTK image data).
namespace sg::apps {

/// The most points --grid takes: 2^26 (406^3). A field of the queries answered by one float
/// keeps 4 bytes per point (VTK's writer compresses block by block), the closest point query
/// about 60 (its record, then the field's arrays): at the limit about 0.3 GB and 4 GB of
/// memory (docs/TOOLS.md gives the measured figures), and a minute or more of work.
inline constexpr std::uint64_t max_grid_points = std::uint64_t{1} << 26;

/// Points per axis.
using GridCounts = std::array<std::uint32_t, 3>;

/// Parses "NX,NY,NZ" (three whole numbers >= 1 separated by commas, blanks around them
/// allowed) whose product is at most max_grid_points. Returns an empty string and sets
/// `counts`, or returns what is wrong: "'96,96' is not NX,NY,NZ: ...".
[[nodiscard]] std::string parse_grid_counts(std::string_view text, GridCounts& counts);

/// Where the points lie: point (i, j, k) at origin + (i, j, k) * spacing, in double, then
/// rounded to float for the query.
struct SamplingGrid {
    GridCounts counts{1, 1, 1};
    std::array<double, 3> origin{};
    std::array<double, 3> spacing{1.0, 1.0, 1.0};

    [[nodiscard]] std::uint64_t point_count() const noexcept
    {
        return std::uint64_t{counts[0]} * counts[1] * counts[2];
    }
    /// The point of index n = i + NX (j + NY k).
    [[nodiscard]] Vec3f point(std::uint64_t n) const noexcept;
};

/// The grid of `counts` points over `box` widened on every side by `padding` times its
/// diagonal: the first and last points of an axis lie on the widened box's faces; an axis of
/// one point has it at the box's centre (a slice), with the widened box's extent as its
/// spacing. Throws ConfigError if an axis of several points has no extent (a flat mesh
/// with padding 0) or the widened box is not finite in float.
[[nodiscard]] SamplingGrid grid_around(const Aabb& box, const GridCounts& counts, double padding);

/// The grid's points in blocks of bricks (16 x 16 x 8 points, fewer at the grid's far
/// sides), so that each block holds neighbouring points.
[[nodiscard]] PointBlocks brick_blocks(const SamplingGrid& grid);

}  // namespace sg::apps
