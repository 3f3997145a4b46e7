#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "point_queries.hpp"
#include "points_options.hpp"
#include "sampling_grid.hpp"
#include "splitgrid/mesh_edges.hpp"

/// What sg-points reports after its work: the counts of the answers, as the summary line on
/// stdout or as one JSON object (docs/STATS_JSON.md).
namespace sg::apps {

/// Counts over the answers of one run.
struct AnswerCounts {
    std::size_t points = 0;
    std::size_t nonfinite = 0;  ///< points with a NaN or infinite coordinate (answered NaN)
    std::size_t inside = 0;     ///< occupancy 1, or a negative signed distance
    std::size_t outside = 0;    ///< occupancy 0, or a finite signed distance >= 0
    std::size_t beyond = 0;     ///< farther than --max-distance (answered +infinity)
    /// The least and greatest finite answer of the distance queries (signed for
    /// signed-distance); none when there is no finite answer.
    std::optional<float> least;
    std::optional<float> greatest;
};

/// Counts `answers` of `query`; `nonfinite` comes from the points' check.
[[nodiscard]] AnswerCounts count_answers(PointQuery query, const PointAnswers& answers,
                                         std::size_t nonfinite);

/// Everything the report names besides the counts.
struct PointsRun {
    const PointsOptions* options = nullptr;
    bool points_from_text = false;     ///< --points: a text file
    std::optional<SamplingGrid> grid;  ///< --grid: where the points lay
    std::optional<EdgeReport> edges;   ///< for the queries that cast rays
    std::string isa;                   ///< the instruction set the kernels ran with
    int threads = 1;
    double seconds = 0.0;
};

/// Prints the report: the JSON object with --json, else the summary line (not with -q).
void report_points(const PointsRun& run, const AnswerCounts& counts);

}  // namespace sg::apps
