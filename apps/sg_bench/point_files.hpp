#pragma once

#include <filesystem>
#include <string>

#include "point_bench.hpp"
#include "point_sets.hpp"
#include "splitgrid/build_config.hpp"
#include "splitgrid/mesh.hpp"

/// sg-bench --save-points: the point sets it measured, as files that scripts read
/// (scripts/bench_inside_open3d.py, scripts/bench_python.py --points) to ask other libraries
/// the same questions: every file in the formats of docs/FORMAT.md, written atomically into a
/// folder that must exist.
namespace sg::bench {

/// `<scene>.sg`: the scene's mesh exactly as sg-bench measured it, with a Split Grid built
/// from `config` (readable by splitgrid.load and sg-points).
void save_scene(const std::filesystem::path& dir, const std::string& scene, const MeshView& mesh,
                const BuildConfig& config);

/// `<scene>.random.points` and `<scene>.near.points` (point files, FORMAT.md 6.1): the point
/// workloads' points (the occupancy workload's where it ran; the closest point workload's are
/// the first of them).
void save_point_sets(const std::filesystem::path& dir, const std::string& scene,
                     const PointBench& points);

/// `<set>.points` (a point file) and `<set>.expected` (an occupancy file, FORMAT.md 6.2: the
/// oracle's answer, 1 inside, 0 outside, NaN where it decides nothing) of an inside test; its
/// scene is `<set.scene>.sg` (save_scene).
void save_inside_set(const std::filesystem::path& dir, const InsideSet& set);

}  // namespace sg::bench
