#include "point_report.hpp"

#include "bench_report.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>

namespace sg::bench {
namespace {

using apps::Json;

const PointMethodResult* find_method(const PointWorkloadResult& w, const std::string& name)
{
    for (const PointMethodResult& m : w.methods)
        if (m.method == name) return &m;
    return nullptr;
}

// "ok", or the status with the disagreements that made it.
std::string status_text(const PointMethodResult& m, std::size_t sample)
{
    if (m.status == "wrong")
        return fmt::format("wrong on {} of {}", m.oracle_disagreements, sample);
    return m.status;
}

}  // namespace

void add_point_json(Json& s, const SceneResult& scene, const BenchPlan& plan)
{
    s["edges"] = {{"counted", scene.edges_counted},
                  {"edges", scene.edges.edges},
                  {"open_edges", scene.edges.open_edges},
                  {"nonmanifold_edges", scene.edges.nonmanifold_edges},
                  {"closed", scene.edges_counted && scene.edges.is_closed()}};
    s["cgal"] = {{"built", scene.cgal.built},
                 {"refused_faces", scene.cgal.refused_faces},
                 {"closed", scene.cgal.closed},
                 {"mesh_seconds", scene.cgal.mesh_seconds},
                 {"side_of_seconds", scene.cgal.side_of_seconds},
                 {"tree_seconds", scene.cgal.tree_seconds}};
    Json workloads = Json::array();
    for (const PointWorkloadResult& w : scene.point_workloads) {
        Json methods = Json::array();
        for (const PointMethodResult& m : w.methods)
            methods.push_back({{"method", m.method},
                               {"status", m.status},
                               {"queries_per_s", by_threads(m.queries_per_s, plan)},
                               {"oracle_disagreements", m.oracle_disagreements},
                               {"reference_disagreements", m.reference_disagreements}});
        workloads.push_back({{"query", w.query},
                             {"points", w.points},
                             {"queries", w.queries},
                             {"oracle_queries", w.oracle_queries},
                             {"oracle_left_out", w.oracle_left_out},
                             {"mean_answer", w.mean_answer},
                             {"methods", methods}});
    }
    s["point_workloads"] = workloads;
}

Json inside_tests_json(const std::vector<InsideTestResult>& tests)
{
    Json all = Json::array();
    for (const InsideTestResult& t : tests) {
        Json methods = Json::array();
        for (const InsideMethodResult& m : t.methods)
            methods.push_back({{"method", m.method},
                               {"status", m.status},
                               {"wrong", m.wrong},
                               {"points_per_s", m.points_per_s}});
        all.push_back({{"set", t.set},
                       {"scene", t.scene},
                       {"oracle", t.oracle},
                       {"points", t.points},
                       {"inside", t.inside},
                       {"undecided", t.undecided},
                       {"methods", methods}});
    }
    return all;
}

std::string point_tables(const BenchResults& results, const BenchPlan& plan)
{
    std::string out;
    for (const SceneResult& scene : results.scenes) {
        if (scene.point_workloads.empty()) continue;
        out += fmt::format("\n{}: point and multi-hit workloads ({}", scene.scene,
                           scene.edges.is_closed()
                               ? "closed mesh"
                               : fmt::format("not closed: {} open edges", scene.edges.open_edges));
        if (scene.cgal.built)
            out += fmt::format(
                "; CGAL: {} faces refused, build {:.3f} s mesh + {:.3f} s "
                "Side_of_triangle_mesh + {:.3f} s AABB tree",
                scene.cgal.refused_faces, scene.cgal.mesh_seconds, scene.cgal.side_of_seconds,
                scene.cgal.tree_seconds);
        out += ")\n";
        out += fmt::format("  {:<20} {:<16}", "workload", "method");
        for (const unsigned t : plan.thread_counts)
            out += fmt::format(" {:>10}", fmt::format("k/s {}t", t));
        for (const unsigned t : plan.thread_counts)
            out += fmt::format(" {:>9}", fmt::format("/CGAL {}t", t));
        out += fmt::format(" {:>10} {:>9}\n", "oracle", "vs first");
        for (const PointWorkloadResult& w : scene.point_workloads) {
            const PointMethodResult* cgal = find_method(w, "cgal");
            const bool cgal_timed = cgal && !cgal->queries_per_s.empty();
            for (const PointMethodResult& m : w.methods) {
                out += fmt::format("  {:<20} {:<16}", w.query + " " + w.points, m.method);
                if (m.queries_per_s.empty()) {
                    out += " " + status_text(m, w.oracle_queries) + "\n";
                    continue;
                }
                for (const double q : m.queries_per_s) out += fmt::format(" {:>10.1f}", q * 1e-3);
                for (std::size_t k = 0; k < m.queries_per_s.size(); ++k)
                    out +=
                        cgal_timed && cgal->queries_per_s[k] > 0.0
                            ? fmt::format(" {:>8.2f}x", m.queries_per_s[k] / cgal->queries_per_s[k])
                            : fmt::format(" {:>9}", "-");
                out += fmt::format(" {:>10} {:>9}\n",
                                   fmt::format("{}/{}", m.oracle_disagreements, w.oracle_queries),
                                   m.reference_disagreements);
            }
        }
    }
    if (!out.empty())
        out +=
            "\n  k/s = thousands of queries per second (median of passes); /CGAL = ratio to "
            "CGAL on the same\n  queries and threads; oracle = answers unlike brute force on "
            "its sample (occupancy: the winding\n  number, points in the band left out); vs "
            "first = all answers unlike the first method's.\n";
    if (!results.inside_tests.empty()) {
        out +=
            "\ninside tests: wrong answers against the oracle (thousands of points/s, 1 thread)\n";
        std::size_t width = 3;
        for (const InsideTestResult& t : results.inside_tests)
            width = std::max(width, t.set.size());
        out += fmt::format("  {:<{}} {:>7} {:>7} {:>9}", "set", width, "points", "inside",
                           "undecided");
        for (const InsideMethodResult& m : results.inside_tests.front().methods)
            out += fmt::format(" {:>24}", m.method);
        out += "\n";
        for (const InsideTestResult& t : results.inside_tests) {
            out += fmt::format("  {:<{}} {:>7} {:>7} {:>9}", t.set, width, t.points, t.inside,
                               t.undecided);
            for (const InsideMethodResult& m : t.methods)
                out += fmt::format(" {:>24}", m.status == "ok" ? fmt::format("{} ({:.0f})", m.wrong,
                                                                             m.points_per_s * 1e-3)
                                                               : m.status.substr(0, 24));
            out += "\n";
        }
    }
    return out;
}

}  // namespace sg::bench
