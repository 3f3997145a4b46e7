#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bench_run.hpp"
#include "bench_structure.hpp"
#include "dynamic_scene.hpp"

/// The dynamic workload of sg-bench: a scene whose vertices move every frame, and on every
/// frame each structure brought up to date (rebuilt, or refitted) and then one frame of the
/// path workload traced at several ray budgets. What it answers: up to how many rays per
/// frame a structure that builds fast beats one that traces fast (docs/BENCH.md, "Dynamic
/// scenes").
namespace sg::bench {

/// What the dynamic workload runs.
struct DynamicPlan {
    std::vector<std::string> structures;  ///< frame_structure_names() entries, no repeats
    std::uint32_t frames = 30;
    /// A structure whose update on frame 1 takes more than this many times the first
    /// structure's runs only on every tenth frame after it; 0 or less: never.
    double slow_factor = 10.0;
    std::vector<std::size_t> ray_budgets{10'000, 100'000, 1'000'000};
    unsigned threads = 1;                 ///< build and trace threads
    std::uint32_t bounces = 3;            ///< of the path rays
    std::uint32_t seed = 1;
    StructureConfigs configs;
};

/// One structure over the frames of one dynamic scene.
struct DynamicStructureResult {
    std::string structure;
    std::vector<std::uint32_t> frames;  ///< the frames it ran on (every frame, unless slow)
    std::vector<double> update_seconds; ///< per frame run: build, rebuild or refit
    /// Per ray budget, per frame run: seconds to trace that frame's rays.
    std::vector<std::vector<double>> trace_seconds;
    /// Closest hits that differ from the reference's (our BVH, refitted every frame), over
    /// every frame and budget: exactly for our structures, t within 1e-4 for Embree's.
    std::size_t disagreements = 0;
};

/// One dynamic scene.
struct DynamicResult {
    std::string scene;
    std::string source;
    std::string motion;
    std::size_t triangles = 0;
    std::uint32_t frames = 0;
    unsigned threads = 1;
    std::vector<std::size_t> ray_budgets;
    /// Per budget: the rays traced per frame (the budget, unless the frame's path rays fell
    /// short of it), averaged over the frames.
    std::vector<double> rays_per_frame;
    /// Per budget: the image the frame's path rays were made for (width x height).
    std::vector<std::pair<int, int>> images;
    std::vector<DynamicStructureResult> structures;
};

/// Runs `scene` for plan.frames frames. Per frame: the vertices move; the reference (our BVH,
/// refitted; not one of the measured structures) makes each budget's path rays and their
/// expected closest hits; then each structure in turn is updated (timed) and traces every
/// budget's rays (timed), its answers compared with the expected ones. A slow structure
/// (plan.slow_factor) runs on frames 0, 1 and every tenth after (said in its `frames`).
[[nodiscard]] DynamicResult run_dynamic(const DynamicScene& scene, const DynamicPlan& plan,
                                        const BenchLog& log);

/// Median over the frames after the first (the first is the initial build for everyone, and
/// pays for the first pages of memory); the first frame's value if there is no other.
[[nodiscard]] double steady_median(const std::vector<std::uint32_t>& frames,
                                   const std::vector<double>& values);

}  // namespace sg::bench
