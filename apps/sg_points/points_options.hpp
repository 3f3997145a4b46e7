#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>

#include "cli_common.hpp"
#include "point_queries.hpp"
#include "sampling_grid.hpp"

/// The command line of sg-points: its options, their help, and the checks of the options
/// together (exit code 1 for every refusal, before any file is touched).
namespace sg::apps {

/// The padding --grid puts around the mesh's box by default, as a share of its diagonal: a
/// few samples of the outside on every side, so that a contour at a small offset closes.
inline constexpr double default_grid_padding = 0.05;

struct PointsOptions {
    std::filesystem::path file;
    std::filesystem::path points;    ///< --points (empty with --grid)
    std::optional<GridCounts> grid;  ///< --grid
    double padding = default_grid_padding;
    std::filesystem::path out;
    PointQuery query = PointQuery::occupancy;
    std::uint32_t nsamples = 1;
    /// --max-distance; +infinity when not given.
    float max_distance = std::numeric_limits<float>::infinity();
    bool strict = false;
    std::uint32_t threads = 0;
    bool json = false;
    LogOptions log;

    [[nodiscard]] QuerySettings settings() const noexcept
    {
        return {query, nsamples, max_distance};
    }
};

/// Adds every option of sg-points to `app`, writing into `options` (which must outlive the
/// parse), and the checks made once the command line is parsed: one of --points and --grid;
/// --nsamples (odd) only for the queries that cast rays, --max-distance only for those that
/// measure distances, --padding only with --grid; --grid only where it can be written (a
/// build with VTK) and only to a .vti file. Each refusal is a CLI::ValidationError naming
/// the flag.
void add_points_options(CLI::App& app, PointsOptions& options);

}  // namespace sg::apps
