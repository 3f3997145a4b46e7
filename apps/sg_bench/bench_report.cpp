#include "bench_report.hpp"

#include <algorithm>
#include <sstream>

#include "cgal_peer.hpp"
#include "point_report.hpp"
#include "splitgrid/version.hpp"

#include <spdlog/fmt/fmt.h>

namespace sg::bench {
namespace {

using apps::Json;
using apps::per_triangle;

const StructureResult* find_structure(const SceneResult& scene, const std::string& name)
{
    for (const StructureResult& s : scene.structures)
        if (s.structure == name) return &s;
    return nullptr;
}

}  // namespace

Json by_threads(const std::vector<double>& values, const BenchPlan& plan)
{
    Json j = Json::object();
    for (std::size_t k = 0; k < values.size() && k < plan.thread_counts.size(); ++k)
        j[std::to_string(plan.thread_counts[k])] = values[k];
    return j;
}

Json results_json(const BenchResults& results, const BenchPlan& plan, const RunInfo& info)
{
    Json j;
    j["schema_version"] = apps::json_schema_version;
    j["tool"] = "sg-bench";
    j["splitgrid_version"] = version_string;
    j["embree_version"] = embree_version();
    j["cgal_version"] = cgal_version();
    j["machine"] = {{"cpu", info.machine},
                    {"hardware_threads", info.hardware_threads},
                    {"compiler", info.compiler},
                    {"kernel_isa", info.kernel_isa}};
    j["run_seconds"] = info.seconds;
    j["plan"] = {{"quick", info.quick},
                 {"structures", plan.structures},
                 {"thread_counts", plan.thread_counts},
                 {"build_repeats", plan.build_repeats},
                 {"trace_repeats", plan.trace_repeats},
                 {"image_width", plan.sizes.width},
                 {"image_height", plan.sizes.height},
                 {"bounces", plan.sizes.bounces},
                 {"incoherent_rays", plan.sizes.incoherent_rays},
                 {"oracle_rays", plan.oracle_rays},
                 {"oracle_budget", plan.oracle_budget},
                 {"watertight_triangles", plan.watertight_triangles},
                 {"watertight_rays", plan.watertight_rays},
                 {"sweep_rays", plan.sweep_rays},
                 {"scale_sizes", plan.scale_sizes},
                 {"seed", plan.seed},
                 {"mesh_order", plan.mesh_order},
                 {"count_rays", plan.points.count_rays},
                 {"occupancy_points", plan.points.occupancy_points},
                 {"closest_points", plan.points.closest_points},
                 {"point_oracle_points", plan.points.oracle_points},
                 {"point_oracle_budget", plan.points.oracle_budget},
                 {"inside_vertices", plan.points.inside_vertices},
                 {"split_grid_config", apps::to_json(plan.configs.split_grid)}};

    Json scenes = Json::array();
    for (const SceneResult& scene : results.scenes) {
        Json s;
        s["scene"] = scene.scene;
        s["source"] = scene.source;
        s["triangles"] = scene.triangles;
        s["vertices"] = scene.vertices;
        s["workload_seconds"] = scene.workload_seconds;
        Json workloads = Json::array();
        for (std::size_t k = 0; k < scene.workload_names.size(); ++k)
            workloads.push_back({{"name", scene.workload_names[k]}, {"rays", scene.workload_rays[k]}});
        s["workloads"] = workloads;
        Json structures = Json::array();
        for (const StructureResult& sr : scene.structures) {
            Json st;
            st["structure"] = sr.structure;
            st["build_seconds"] = by_threads(sr.build_seconds, plan);
            st["structure_bytes"] = sr.structure_bytes;
            st["total_bytes"] = sr.total_bytes;
            st["structure_bytes_per_triangle"] = per_triangle(sr.structure_bytes, scene.triangles);
            st["total_bytes_per_triangle"] = per_triangle(sr.total_bytes, scene.triangles);
            st["references"] = sr.references;
            st["references_per_triangle"] = per_triangle(sr.references, scene.triangles);
            st["peak_build_bytes"] = sr.build_memory.peak_bytes;
            st["peak_build_bytes_per_triangle"] = per_triangle(sr.build_memory.peak_bytes, scene.triangles);
            st["process_high_water_bytes"] = sr.build_memory.process_high_water_bytes;
            Json wl = Json::array();
            for (const WorkloadResult& w : sr.workloads)
                wl.push_back({{"workload", w.workload},
                              {"rays", w.rays},
                              {"any_hit", w.any_hit},
                              {"hit_fraction", w.hit_fraction},
                              {"mrays_per_s", by_threads(w.mrays_per_s, plan)},
                              {"oracle_rays", w.oracle_rays},
                              {"oracle_disagreements", w.oracle_disagreements},
                              {"reference_disagreements", w.reference_disagreements},
                              {"counted", w.counted},
                              {"nodes_per_ray", w.nodes_per_ray},
                              {"cells_per_ray", w.cells_per_ray},
                              {"triangles_per_ray", w.triangles_per_ray}});
            st["workloads"] = wl;
            structures.push_back(st);
        }
        s["structures"] = structures;
        add_point_json(s, scene, plan);
        scenes.push_back(s);
    }
    j["scenes"] = scenes;
    j["inside_tests"] = inside_tests_json(results.inside_tests);

    Json accuracy = Json::array();
    for (const AccuracyResult& a : results.accuracy)
        accuracy.push_back({{"structure", a.structure},
                            {"variant", a.variant},
                            {"position", a.position},
                            {"rays", a.rays},
                            {"misses", a.misses},
                            {"misses_per_million", a.misses_per_million()},
                            {"misses_random", a.misses_random},
                            {"misses_vertex", a.misses_vertex},
                            {"misses_edge", a.misses_edge},
                            {"mrays_per_s", a.mrays_per_s}});
    j["accuracy"] = accuracy;

    Json sweep = Json::array();
    for (const SweepResult& p : results.sweep)
        sweep.push_back({{"parameter", p.parameter},
                         {"value", p.value},
                         {"config", apps::to_json(p.config)},
                         {"build_seconds", p.build_seconds},
                         {"mrays_per_s", p.mrays_per_s},
                         {"total_bytes_per_triangle", p.bytes_per_triangle},
                         {"references_per_triangle", p.references_per_triangle},
                         {"disagreements", p.disagreements}});
    j["sweep"] = {{"scene", results.sweep_scene},
                  {"threads", plan.thread_counts.empty() ? 0u : plan.thread_counts.back()},
                  {"points", sweep}};

    Json scale = Json::array();
    for (const ScaleResult& r : results.scale)
        scale.push_back({{"structure", r.structure},
                         {"triangles", r.triangles},
                         {"build_seconds", r.build_seconds},
                         {"structure_bytes_per_triangle", r.structure_bytes_per_triangle},
                         {"total_bytes_per_triangle", r.total_bytes_per_triangle},
                         {"references_per_triangle", r.references_per_triangle},
                         {"peak_build_bytes_per_triangle",
                          per_triangle(r.build_memory.peak_bytes, r.triangles)},
                         {"process_high_water_bytes", r.build_memory.process_high_water_bytes}});
    j["scale"] = {{"model", results.scale_model}, {"points", scale}};
    return j;
}

std::string results_csv(const BenchResults& results, const BenchPlan& plan)
{
    std::string out = "scene,triangles,structure";
    for (unsigned t : plan.thread_counts) out += fmt::format(",build_seconds_{}t", t);
    out += ",structure_bytes_per_triangle,total_bytes_per_triangle,references_per_triangle,"
           "workload,rays,hit_fraction";
    for (unsigned t : plan.thread_counts) out += fmt::format(",mrays_per_s_{}t", t);
    out += ",oracle_rays,oracle_disagreements,reference_disagreements,"
           "peak_build_bytes_per_triangle,process_high_water_bytes\n";
    for (const SceneResult& scene : results.scenes)
        for (const StructureResult& sr : scene.structures)
            for (const WorkloadResult& w : sr.workloads) {
                out += fmt::format("{},{},{}", scene.scene, scene.triangles, sr.structure);
                for (double b : sr.build_seconds) out += fmt::format(",{:.6f}", b);
                out += fmt::format(",{:.3f},{:.3f},{:.4f},{},{},{:.6f}",
                                   per_triangle(sr.structure_bytes, scene.triangles),
                                   per_triangle(sr.total_bytes, scene.triangles),
                                   per_triangle(sr.references, scene.triangles), w.workload,
                                   w.rays, w.hit_fraction);
                for (double m : w.mrays_per_s) out += fmt::format(",{:.4f}", m);
                out += fmt::format(",{},{},{},{:.3f},{}\n", w.oracle_rays, w.oracle_disagreements,
                                   w.reference_disagreements,
                                   per_triangle(sr.build_memory.peak_bytes, scene.triangles),
                                   sr.build_memory.process_high_water_bytes);
            }
    return out;
}

std::string results_table(const BenchResults& results, const BenchPlan& plan)
{
    std::string out;
    const unsigned last_threads = plan.thread_counts.back();
    for (const SceneResult& scene : results.scenes) {
        out += fmt::format("\n{} ({} triangles, {})\n", scene.scene, scene.triangles, scene.source);
        out += fmt::format("  {:<16}", "structure");
        for (unsigned t : plan.thread_counts) out += fmt::format(" {:>9}", fmt::format("build {}t", t));
        out += fmt::format(" {:>8} {:>8}", "B/tri", "refs/tri");
        for (const std::string& w : scene.workload_names)
            out += fmt::format(" {:>16}", fmt::format("{} {}t", w, last_threads));
        out += fmt::format(" {:>9}\n", "disagree");
        const StructureResult* embree = find_structure(scene, "embree");
        for (const StructureResult& sr : scene.structures) {
            out += fmt::format("  {:<16}", sr.structure);
            for (double b : sr.build_seconds) out += fmt::format(" {:>8.3f}s", b);
            out += fmt::format(" {:>8.1f} {:>8.2f}", per_triangle(sr.total_bytes, scene.triangles),
                               per_triangle(sr.references, scene.triangles));
            std::size_t disagreements = 0;
            for (std::size_t k = 0; k < sr.workloads.size(); ++k) {
                const WorkloadResult& w = sr.workloads[k];
                const double m = w.mrays_per_s.back();
                std::string cell = fmt::format("{:.2f}", m);
                if (embree && embree != &sr && embree->workloads[k].mrays_per_s.back() > 0.0)
                    cell += fmt::format(" ({:.2f}x)", m / embree->workloads[k].mrays_per_s.back());
                out += fmt::format(" {:>16}", cell);
                disagreements += w.oracle_disagreements + w.reference_disagreements;
            }
            out += fmt::format(" {:>9}\n", disagreements);
        }
    }
    out += "\n  Mrays/s per workload; (x) = ratio to Embree; B/tri = structure + mesh bytes per "
           "triangle;\n  disagree = brute-force sample + all rays against the first structure "
           "(Embree: t within 1e-4).\n";

    if (!results.accuracy.empty()) {
        out += "\nwatertightness: rays from inside a closed sphere (misses per million, Mrays/s "
               "on 1 thread)\n";
        out += fmt::format("  {:<16} {:<24} {:>14} {:>14} {:>9}\n", "structure", "variant",
                           "origin", "far", "Mrays/s");
        for (const AccuracyResult& a : results.accuracy) {
            if (a.position != "origin") continue;
            const AccuracyResult* far = nullptr;
            for (const AccuracyResult& b : results.accuracy)
                if (b.position == "far" && b.structure == a.structure && b.variant == a.variant) far = &b;
            out += fmt::format("  {:<16} {:<24} {:>14.1f} {:>14.1f} {:>9.2f}\n", a.structure,
                               a.variant, a.misses_per_million(),
                               far ? far->misses_per_million() : 0.0, a.mrays_per_s);
        }
    }
    out += point_tables(results, plan);
    if (!results.sweep.empty()) {
        out += fmt::format("\nSplit Grid parameter sweep on {} ({} threads)\n", results.sweep_scene,
                           last_threads);
        out += fmt::format("  {:<18} {:>8} {:>10} {:>9} {:>8} {:>9} {:>9}\n", "parameter", "value",
                           "build s", "Mrays/s", "B/tri", "refs/tri", "disagree");
        for (const SweepResult& p : results.sweep)
            out += fmt::format("  {:<18} {:>8} {:>10.3f} {:>9.3f} {:>8.1f} {:>9.2f} {:>9}\n",
                               p.parameter, p.value, p.build_seconds, p.mrays_per_s,
                               p.bytes_per_triangle, p.references_per_triangle, p.disagreements);
    }
    if (!results.scale.empty()) {
        out += fmt::format("\nmemory against scene size (from {})\n", results.scale_model);
        out += fmt::format("  {:>10} {:<16} {:>10} {:>10} {:>9} {:>9}\n", "triangles", "structure",
                           "build s", "B/tri", "struct B", "refs/tri");
        for (const ScaleResult& r : results.scale)
            out += fmt::format("  {:>10} {:<16} {:>10.3f} {:>10.1f} {:>9.1f} {:>9.2f}\n",
                               r.triangles, r.structure, r.build_seconds,
                               r.total_bytes_per_triangle, r.structure_bytes_per_triangle,
                               r.references_per_triangle);
    }
    return out;
}

namespace {

// Steady-state medians of one structure: update, and trace and frame time per budget.
struct FrameMedians {
    double update = 0.0;
    std::vector<double> trace;
    std::vector<double> frame;
};

FrameMedians frame_medians(const DynamicStructureResult& s)
{
    FrameMedians m;
    m.update = steady_median(s.frames, s.update_seconds);
    for (const std::vector<double>& t : s.trace_seconds) {
        m.trace.push_back(steady_median(s.frames, t));
        std::vector<double> sums;
        for (std::size_t k = 0; k < t.size() && k < s.update_seconds.size(); ++k)
            sums.push_back(s.update_seconds[k] + t[k]);
        m.frame.push_back(steady_median(s.frames, sums));
    }
    return m;
}

}  // namespace

Json dynamic_json(const std::vector<DynamicResult>& results)
{
    Json all = Json::array();
    for (const DynamicResult& d : results) {
        Json j;
        j["scene"] = d.scene;
        j["source"] = d.source;
        j["motion"] = d.motion;
        j["triangles"] = d.triangles;
        j["frames"] = d.frames;
        j["threads"] = d.threads;
        j["ray_budgets"] = d.ray_budgets;
        j["rays_per_frame"] = d.rays_per_frame;
        Json images = Json::array();
        for (const auto& [w, h] : d.images) images.push_back({w, h});
        j["images"] = images;
        Json structures = Json::array();
        for (const DynamicStructureResult& s : d.structures) {
            const FrameMedians m = frame_medians(s);
            Json sj;
            sj["structure"] = s.structure;
            sj["frames_run"] = s.frames;
            sj["update_seconds"] = s.update_seconds;
            sj["trace_seconds"] = s.trace_seconds;
            sj["first_update_seconds"] = s.update_seconds.empty() ? 0.0 : s.update_seconds.front();
            sj["update_seconds_median"] = m.update;
            sj["trace_seconds_median"] = m.trace;
            sj["frame_seconds_median"] = m.frame;
            sj["disagreements"] = s.disagreements;
            structures.push_back(sj);
        }
        j["structures"] = structures;
        all.push_back(j);
    }
    return all;
}

std::string dynamic_table(const std::vector<DynamicResult>& results)
{
    std::string out;
    for (const DynamicResult& d : results) {
        out += fmt::format("\n{} ({} triangles, {} frames, {} thread{}; {})\n", d.scene,
                           d.triangles, d.frames, d.threads, d.threads == 1 ? "" : "s", d.source);
        out += fmt::format("  {:<16} {:>6} {:>9} {:>10}", "structure", "frames", "first s",
                           "update ms");
        for (const std::size_t b : d.ray_budgets)
            out += fmt::format(" {:>11}", fmt::format("trace {:g}", static_cast<double>(b)));
        for (const std::size_t b : d.ray_budgets)
            out += fmt::format(" {:>11}", fmt::format("frame {:g}", static_cast<double>(b)));
        out += fmt::format(" {:>9}\n", "disagree");
        for (const DynamicStructureResult& s : d.structures) {
            const FrameMedians m = frame_medians(s);
            out += fmt::format("  {:<16} {:>6} {:>9.3f} {:>10.2f}", s.structure, s.frames.size(),
                               s.update_seconds.empty() ? 0.0 : s.update_seconds.front(),
                               1e3 * m.update);
            for (const double t : m.trace) out += fmt::format(" {:>11.2f}", 1e3 * t);
            for (const double t : m.frame) out += fmt::format(" {:>11.2f}", 1e3 * t);
            out += fmt::format(" {:>9}\n", s.disagreements);
        }
    }
    if (!results.empty())
        out += "\n  ms per frame, medians over the frames after the first; first s = the "
               "first frame's build;\n  trace/frame N = tracing N path rays / update + tracing; "
               "disagree = closest hits unlike the reference's (our BVH, refitted).\n";
    return out;
}

}  // namespace sg::bench
