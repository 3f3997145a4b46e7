#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_run.hpp"
#include "cli_common.hpp"
#include "dynamic.hpp"

/// sg-bench's command line: its flags, and the plans they make (main.cpp runs them).
namespace sg::bench {

/// The command line as given. Lists stay text until resolve_options: each is one token, so
/// that it never swallows the MESH arguments that follow.
struct BenchOptions {
    std::vector<std::filesystem::path> meshes;
    std::filesystem::path out = "sg-bench-results";
    bool quick = false;
    std::string structures_text;
    std::string threads_text;
    std::filesystem::path scale_model;
    std::string scale_sizes_text;
    std::string arena_sizes_text;
    std::vector<std::filesystem::path> dynamic_rigid;
    std::vector<std::filesystem::path> dynamic_deform;
    std::uint32_t dynamic_frames = 30;
    std::size_t dynamic_triangles = 1'000'000;
    std::string dynamic_rays_text = "1e4,1e5,1e6";
    std::string dynamic_structures_text;
    bool dynamic_every_frame = false;
    bool no_sweep = false;
    bool no_charts = false;
    std::filesystem::path charts_script = SG_BENCH_CHARTS_SCRIPT;
    BenchPlan plan;
    apps::LogOptions log;
};

/// Describes sg-bench on `app` (help, --version) and declares its flags, writing into `o`.
void add_bench_options(CLI::App& app, BenchOptions& o);

/// What a run measures, made from the parsed options.
struct ResolvedOptions {
    BenchPlan plan;               ///< the static scenes' plan, lists resolved
    DynamicPlan dynamic_plan;     ///< when has_dynamic
    bool has_dynamic = false;     ///< --dynamic-rigid or --dynamic-deform given
    std::vector<std::size_t> arena_sizes;
};

/// Applies --quick's defaults (to the flags `app` did not see) and resolves the lists of `o`.
/// Throws CLI::ValidationError naming the flag for a bad list, or when nothing is to be
/// measured.
[[nodiscard]] ResolvedOptions resolve_options(const CLI::App& app, BenchOptions& o);

}  // namespace sg::bench
