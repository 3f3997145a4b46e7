#pragma once

#include <string>
#include <vector>

#include "bench_run.hpp"
#include "cli_common.hpp"

/// The point and multi-hit workloads and the inside tests in sg-bench's outputs: their keys of
/// results.json (docs/BENCH.md gives every key) and their tables on stdout.
namespace sg::bench {

/// Adds a scene's "edges", "cgal" and "point_workloads" to its JSON object `s`.
void add_point_json(apps::Json& s, const SceneResult& scene, const BenchPlan& plan);

/// The "inside_tests" array.
[[nodiscard]] apps::Json inside_tests_json(const std::vector<InsideTestResult>& tests);

/// Per scene, each point workload's methods: thousands of queries per second on each thread
/// count, the ratio to CGAL on each, the oracle's and the reference's disagreements; then the
/// inside tests' wrong answers and speeds. Empty when the run measured none.
[[nodiscard]] std::string point_tables(const BenchResults& results, const BenchPlan& plan);

}  // namespace sg::bench
