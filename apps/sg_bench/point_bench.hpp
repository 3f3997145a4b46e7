#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "bench_structure.hpp"
#include "cgal_peer.hpp"
#include "point_sets.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/mesh_edges.hpp"

/// The point and multi-hit workloads of sg-bench (docs/BENCH.md, "Point and multi-hit
/// workloads"): the hit count of every incoherent ray, inside or outside and the closest point
/// of random and near points, for each of our structures and CGAL (cgal_peer.hpp), every
/// method's answers checked before its speed is read; and the inside tests, where rays from
/// the points meet edges and vertices.
namespace sg::bench {

/// What the point workloads run.
struct PointPlan {
    std::size_t count_rays = 200'000;  ///< first incoherent rays counted (0: no count workload)
    std::size_t occupancy_points = 100'000;  ///< per point set (0: no occupancy workload)
    std::size_t closest_points = 10'000;     ///< per point set (0: no closest point workload)
    std::size_t oracle_points = 1000;        ///< brute-force sample per workload, at most
    /// Point/triangle pairs of a point workload's sample, at most (at least 20 points).
    std::uint64_t oracle_budget = 100'000'000;
    std::size_t inside_vertices = 100;  ///< scan vertices per inside test (0: no inside tests)

    [[nodiscard]] bool any() const noexcept
    {
        return count_rays > 0 || occupancy_points > 0 || closest_points > 0;
    }
};

/// One method (one of our structures, or "cgal") on one point or multi-hit workload.
struct PointMethodResult {
    std::string method;
    /// "ok"; "wrong" (answers unlike the oracle's on its sample: not timed); or "n/a: <why>".
    std::string status = "ok";
    std::vector<double> queries_per_s;  ///< per thread count, median of passes; empty unless ok
    std::size_t oracle_disagreements = 0;
    /// Every query against the first method that answered the workload: exactly for our
    /// structures (counts, sides, distances), distances within 1e-5 relative for CGAL.
    std::size_t reference_disagreements = 0;
};

/// One point or multi-hit workload of a scene.
struct PointWorkloadResult {
    std::string query;   ///< "count", "occupancy" or "closest"
    std::string points;  ///< "incoherent" (count's rays), "random" or "near"
    std::size_t queries = 0;
    std::size_t oracle_queries = 0;  ///< the sample compared with the oracle
    /// Sample points the oracle leaves out (occupancy): within compute_occupancy's band of the
    /// surface, or not decided by the winding number.
    std::size_t oracle_left_out = 0;
    /// The first method's answers: mean hits per ray, fraction inside, or mean distance.
    double mean_answer = 0.0;
    std::vector<PointMethodResult> methods;
};

/// CGAL on one scene (all zero and `built` false without CGAL or point workloads).
struct CgalSceneResult {
    bool built = false;
    std::size_t refused_faces = 0;
    bool closed = false;
    double mesh_seconds = 0.0;     ///< median of the timed builds: the Surface_mesh
    double side_of_seconds = 0.0;  ///< Side_of_triangle_mesh and its tree
    double tree_seconds = 0.0;     ///< the closest point AABB tree and its search tree
};

/// One method on one inside test set.
struct InsideMethodResult {
    std::string method;         ///< "splitgrid", "splitgrid_no_tie_break" or "cgal"
    std::string status = "ok";  ///< or "n/a: <why>"
    std::size_t wrong = 0;      ///< answers unlike the oracle's (undecided points left out)
    double points_per_s = 0.0;  ///< one thread, median of passes
};

/// One inside test set.
struct InsideTestResult {
    std::string set;
    std::string scene;
    std::string oracle;
    std::size_t points = 0;
    std::size_t inside = 0;     ///< by the oracle
    std::size_t undecided = 0;  ///< left out: the oracle does not decide them
    std::vector<InsideMethodResult> methods;
};

/// Progress lines, as BenchLog (bench_run.hpp).
using PointLog = std::function<void(const std::string& line)>;

/// The point and multi-hit workloads of one scene: the rays and points, and the oracle's
/// answers for a sample of each, are made once; then each method is measured on all of them.
class PointBench {
public:
    /// `incoherent`: the scene's incoherent rays (the first plan.count_rays are counted).
    /// Occupancy runs only where the mesh is closed (edge_report); elsewhere every method's
    /// status there is "n/a: mesh not closed".
    PointBench(const MeshView& mesh, std::span<const Ray> incoherent, const PointPlan& plan,
               std::vector<unsigned> thread_counts, std::uint32_t repeats, std::uint32_t seed,
               PointLog log);
    ~PointBench();
    PointBench(const PointBench&) = delete;
    PointBench& operator=(const PointBench&) = delete;

    /// Measures `method` on every workload: per workload one untimed pass on the last thread
    /// count, whose answers are compared with the oracle's sample and the first method's; a
    /// method that disagrees with the oracle is "wrong" and not timed; otherwise
    /// `repeats` timed passes per thread count, in chunks of 1,024 queries as the rays.
    void measure(const std::string& method, const PointQueries& queries);

    /// Records `method` as answering none of the workloads, for the reason `why`.
    void skip(const std::string& method, const std::string& why);

    [[nodiscard]] const EdgeReport& edges() const noexcept;
    /// The random and near points (empty where their workloads do not run).
    [[nodiscard]] const std::vector<Vec3f>& occupancy_points(const std::string& set) const;
    [[nodiscard]] const std::vector<Vec3f>& closest_points(const std::string& set) const;
    [[nodiscard]] std::vector<PointWorkloadResult> results() const;

private:
    struct State;
    std::unique_ptr<State> state_;
};

/// Builds CGAL over `mesh` once untimed and `repeats` times timed (medians), keeping the last.
[[nodiscard]] std::unique_ptr<CgalPeer> timed_cgal_build(const MeshView& mesh,
                                                         std::uint32_t repeats,
                                                         CgalSceneResult& result);

/// The inside test `set` for Split Grid (`splitgrid`: its watertight test and
/// TriangleTest::watertight_no_tie_break) and CGAL (`cgal`, nullptr where absent): answers
/// unlike the oracle's, and points per second on one thread (median of `repeats` passes after
/// an untimed one; a pass answers the set as many times as it takes to reach 200,000 points). Every method is timed, wrong or not: the chart puts speed against wrong
/// answers, as the watertightness workload's does.
[[nodiscard]] InsideTestResult run_inside_test(const InsideSet& set, const PointQueries& splitgrid,
                                               const PointQueries* cgal, std::uint32_t repeats);

}  // namespace sg::bench
