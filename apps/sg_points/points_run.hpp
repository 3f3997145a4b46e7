#pragma once

#include "points_options.hpp"

namespace sg::apps {

/// The work of sg-points once its command line is parsed: refuses an output over an input,
/// reserves the output, reads the .sg file and the points (or lays out the grid), answers
/// the query in parallel, writes the answers (a point result file, or with --grid VTK image
/// data) and reports. Throws what run_tool turns into exit codes.
void run_points(const PointsOptions& options);

}  // namespace sg::apps
