#pragma once

#include <string>

#include "bench_run.hpp"
#include "dynamic.hpp"
#include "cli_common.hpp"

/// sg-bench's outputs: the JSON document (docs/BENCH.md gives every key), the CSV table and
/// the readable summary on stdout. All three come from the same BenchResults.
namespace sg::bench {

/// What the report says about the run itself, besides the results.
struct RunInfo {
    bool quick = false;
    std::string machine;   ///< CPU model, as /proc/cpuinfo names it
    unsigned hardware_threads = 0;
    std::string compiler;
    std::string kernel_isa;  ///< instruction set of our structures' kernels (query.hpp)
    double seconds = 0.0;  ///< wall time of the whole run
};

/// {"1": x, "2": y}: `values` keyed by the plan's thread counts.
[[nodiscard]] apps::Json by_threads(const std::vector<double>& values, const BenchPlan& plan);

/// The whole run as JSON (schema_version 1).
[[nodiscard]] apps::Json results_json(const BenchResults& results, const BenchPlan& plan,
                                      const RunInfo& info);

/// One row per scene, structure and workload.
[[nodiscard]] std::string results_csv(const BenchResults& results, const BenchPlan& plan);

/// Fixed-width tables for a terminal: per scene the structures' build time, memory and
/// Mrays/s per workload with the ratio to Embree, then the accuracy, sweep and scale tables.
[[nodiscard]] std::string results_table(const BenchResults& results, const BenchPlan& plan);

/// The dynamic workload's scenes as JSON (the "dynamic" key; docs/BENCH.md).
[[nodiscard]] apps::Json dynamic_json(const std::vector<DynamicResult>& results);

/// Per dynamic scene and structure: update time, trace time and their sum per frame at each
/// ray budget (medians over the frames after the first).
[[nodiscard]] std::string dynamic_table(const std::vector<DynamicResult>& results);

}  // namespace sg::bench
