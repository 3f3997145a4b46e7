#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "bench_structure.hpp"
#include "point_bench.hpp"
#include "splitgrid/mesh.hpp"
#include "workloads.hpp"

/// The measurements of sg-bench: what is run, in which order, and the plain result records
/// that bench_report.cpp writes as a table, CSV and JSON (docs/BENCH.md gives the schema).
namespace sg::bench {

/// A scene to measure: a mesh and where it came from.
struct BenchScene {
    std::string name;    ///< short name for tables and file names (file stem, or "arena_1e6")
    std::string source;  ///< the mesh file, or how the scene was generated
    Mesh mesh;
};

/// Everything that decides what sg-bench measures.
struct BenchPlan {
    std::vector<std::string> structures;   ///< subset of structure_names(), report order
    std::vector<unsigned> thread_counts;   ///< e.g. {1, 2}
    std::uint32_t build_repeats = 3;       ///< builds per structure and thread count (median)
    std::uint32_t trace_repeats = 3;       ///< passes per workload and thread count (median)
    WorkloadSizes sizes;                   ///< the scene workloads
    std::size_t oracle_rays = 1000;        ///< brute-force sample per workload (at most)
    std::uint64_t oracle_budget = 400'000'000;  ///< ray/triangle tests per sample at most
    std::size_t watertight_triangles = 100'000;  ///< sphere of the accuracy workload
    std::size_t watertight_rays = 1'000'000;     ///< per sphere position
    bool sweep = true;                     ///< run the Split Grid parameter sweep
    std::size_t sweep_rays = 300'000;      ///< path rays traced per sweep point
    std::vector<std::size_t> scale_sizes;  ///< triangle counts of the memory-scaling series
    std::uint32_t seed = 1;
    /// Order of the scenes' triangles: "file" (as read), "morton" or "shuffled" (sg-bench
    /// --mesh-order).
    std::string mesh_order = "file";
    StructureConfigs configs;
    PointPlan points;  ///< the point and multi-hit workloads, and the inside tests
    /// Where --save-points writes the point sets and their scenes (point_files.hpp); empty:
    /// nowhere.
    std::filesystem::path save_points;
};

/// Median of `values` (the mean of the two middle ones for an even count); 0 when empty.
[[nodiscard]] double median(std::vector<double> values);

/// One workload traced by one structure.
struct WorkloadResult {
    std::string workload;
    std::size_t rays = 0;
    bool any_hit = false;
    double hit_fraction = 0.0;          ///< rays that hit (closest-hit) or are occluded
    std::vector<double> mrays_per_s;    ///< per BenchPlan::thread_counts entry, median of passes
    std::size_t oracle_rays = 0;        ///< brute-force sample size
    std::size_t oracle_disagreements = 0;
    std::size_t reference_disagreements = 0;  ///< against the first structure, on all rays
    /// Mean work per ray over the oracle sample (TraversalCounters; what each structure calls
    /// a node and a cell is in its header); all 0 for Embree, which does not count.
    bool counted = false;
    double nodes_per_ray = 0.0;
    double cells_per_ray = 0.0;
    double triangles_per_ray = 0.0;
};

/// Memory of one build (build_memory.hpp), on the plan's last thread count.
struct BuildMemory {
    /// Highest number of bytes the build held at once; the input mesh not counted.
    std::size_t peak_bytes = 0;
    /// The process's resident high-water mark during the build (everything sg-bench holds:
    /// meshes and workloads too); 0 where it could not be reset before the build.
    std::size_t process_high_water_bytes = 0;
};

/// One structure on one scene.
struct StructureResult {
    std::string structure;
    std::vector<double> build_seconds;  ///< per thread count, median of builds
    BuildMemory build_memory;
    std::size_t structure_bytes = 0;
    std::size_t total_bytes = 0;        ///< structure + the mesh's vertex and index arrays
    std::size_t references = 0;
    std::vector<WorkloadResult> workloads;
};

struct SceneResult {
    std::string scene;
    std::string source;
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    double workload_seconds = 0.0;  ///< time to make the workloads
    std::vector<std::string> workload_names;
    std::vector<std::size_t> workload_rays;
    std::vector<StructureResult> structures;
    /// The point and multi-hit workloads (empty when the plan runs none), the mesh's edges
    /// (counted where they run: occupancy needs a closed mesh) and CGAL's builds.
    std::vector<PointWorkloadResult> point_workloads;
    bool edges_counted = false;
    EdgeReport edges;
    CgalSceneResult cgal;
};

/// One structure and query variant on the watertightness workload at one sphere position.
struct AccuracyResult {
    std::string structure;
    std::string variant;
    std::string position;  ///< "origin" or "far" (centre (148376, 1234, -223423))
    std::size_t rays = 0;
    std::size_t misses = 0;
    /// Misses among the rays in random directions, aimed at vertices, aimed at edge
    /// midpoints (interior_rays: 4/6, 1/6 and 1/6 of the rays).
    std::size_t misses_random = 0;
    std::size_t misses_vertex = 0;
    std::size_t misses_edge = 0;
    double mrays_per_s = 0.0;  ///< one thread, median of passes
    [[nodiscard]] double misses_per_million() const noexcept
    {
        return rays ? 1e6 * static_cast<double>(misses) / static_cast<double>(rays) : 0.0;
    }
};

/// One point of the Split Grid parameter sweep.
struct SweepResult {
    std::string parameter;  ///< which field was changed ("default" for the baseline point)
    std::string value;
    BuildConfig config;
    double build_seconds = 0.0;  ///< last thread count of the plan, median
    double mrays_per_s = 0.0;    ///< path workload sample, last thread count, median
    double bytes_per_triangle = 0.0;  ///< structure + mesh
    double references_per_triangle = 0.0;
    std::size_t disagreements = 0;    ///< against the default point, on the same rays
};

/// One structure at one size of the memory-scaling series.
struct ScaleResult {
    std::string structure;
    std::size_t triangles = 0;
    double build_seconds = 0.0;  ///< last thread count of the plan, one build
    BuildMemory build_memory;
    double structure_bytes_per_triangle = 0.0;
    double total_bytes_per_triangle = 0.0;
    double references_per_triangle = 0.0;
};

struct BenchResults {
    std::vector<SceneResult> scenes;
    /// The inside tests: the tessellated cube's and the icosphere's sets, then one per closed
    /// scene (empty with plan.points.inside_vertices 0).
    std::vector<InsideTestResult> inside_tests;
    std::vector<AccuracyResult> accuracy;
    std::string sweep_scene;
    std::vector<SweepResult> sweep;
    std::string scale_model;
    std::vector<ScaleResult> scale;
};

/// Reports progress: one line per step ("dragon: building kd_tree on 2 threads").
using BenchLog = std::function<void(const std::string& line)>;

/// Measures every scene (builds, memory, workloads with timing and correctness, the point
/// workloads with CGAL where this build has it, the inside test of a closed scene), then the
/// inside tests of the tessellated cube and the icosphere, the accuracy workload, the sweep on
/// `scenes.front()`, and the scale series made from `scale_model` (skipped when it has no
/// triangles or plan.scale_sizes is empty).
[[nodiscard]] BenchResults run_bench(const std::vector<BenchScene>& scenes,
                                     const BenchScene& scale_model, const BenchPlan& plan,
                                     const BenchLog& log);

/// Same closest hit. Exact (our structures, which share the watertight test): both miss, or
/// the same t (the same triangle, or a tie between two at exactly that t). Otherwise (Embree,
/// whose test differs): the same triangle, or t within 1e-4 relative.
[[nodiscard]] bool same_hit(const Hit& a, const Hit& b, bool exact);

/// Closest hits of `rays` into `hits` (resized to match), traced with `threads` threads as
/// every workload is; returns the wall time in seconds.
double trace_closest(const BenchStructure& s, std::span<const Ray> rays, unsigned threads,
                     std::vector<Hit>& hits);

/// A scene of `triangles` triangles made from `model`: a patch of the model (its triangles
/// nearest to one surface point) when it has more, otherwise an arena of copies
/// (make_arena_scene) with the nearest whole number of copies.
[[nodiscard]] Mesh scale_scene(const MeshView& model, std::size_t triangles, std::uint32_t seed);

}  // namespace sg::bench
