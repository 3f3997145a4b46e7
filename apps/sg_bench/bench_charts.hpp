#pragma once

#include <filesystem>
#include <span>
#include <vector>

#include "bench_run.hpp"

/// The charts of an sg-bench run: which there are, which the run has data for, and the chart
/// script (scripts/bench_charts.py) that draws them from results.json.
namespace sg::bench {

/// A chart scripts/bench_charts.py draws, each from a part of the run (docs/BENCH.md).
struct Chart {
    const char* file;
    const char* needs;  ///< why it may be missing, for the notice
};

/// Every chart, in the order the script draws them.
[[nodiscard]] std::span<const Chart> charts() noexcept;

/// Whether the run measures what `chart` draws.
[[nodiscard]] bool chart_has_data(const Chart& chart, const BenchPlan& plan, bool has_scale_model,
                                  bool has_scenes, bool has_dynamic);

/// Runs `script` on `json` with Debian's python3 (where python3-matplotlib lives), writing
/// into the folder `out`; its stdout is read through a pipe and its "wrote PATH" lines become
/// the list returned (they are logged on stderr by the caller, so that stdout keeps only the
/// table); its stderr is sg-bench's. An interrupt kills the script and removes the temporary
/// files it leaves beside the charts. A failure, or a script still running after ten minutes,
/// is a warning, since the JSON and CSV are written already; nothing is returned then.
[[nodiscard]] std::vector<std::filesystem::path> make_charts(const std::filesystem::path& script,
                                                            const std::filesystem::path& json,
                                                            const std::filesystem::path& out);

}  // namespace sg::bench
