#include "bench_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "build_memory.hpp"
#include "cli_common.hpp"
#include "point_files.hpp"
#include "splitgrid/arena_scene.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/mesh_edges.hpp"
#include "splitgrid/mesh_order.hpp"
#include "splitgrid/traverse.hpp"

namespace sg::bench {
namespace {

using apps::per_triangle;
using apps::seconds_since;
using Clock = std::chrono::steady_clock;

// Rays per task: large enough that the virtual batch call and the task cost vanish, small
// enough that two threads share the work evenly.
constexpr std::size_t trace_grain = 1024;

/// The answers of one pass over a workload.
struct Answers {
    std::vector<Hit> hits;           // closest-hit workloads
    std::vector<std::uint8_t> occluded;  // any-hit workloads
};

// Traces `rays` with `threads` threads and returns the wall time in seconds.
double trace(const BenchStructure& s, std::span<const Ray> rays, bool any_hit, unsigned threads,
             const QueryVariant& variant, Answers& answers)
{
    if (any_hit) answers.occluded.assign(rays.size(), 0);
    else answers.hits.assign(rays.size(), Hit{});
    tbb::task_arena arena(static_cast<int>(threads));
    const auto start = Clock::now();
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), trace_grain),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              const auto part = rays.subspan(r.begin(), r.size());
                              if (any_hit)
                                  s.occluded(part, std::span(answers.occluded).subspan(r.begin(), r.size()));
                              else
                                  s.intersect(part, std::span(answers.hits).subspan(r.begin(), r.size()),
                                              variant);
                          });
    });
    return seconds_since(start);
}

double mrays(std::size_t rays, double seconds)
{
    return seconds > 0.0 ? static_cast<double>(rays) / seconds * 1e-6 : 0.0;
}

std::size_t count_disagreements(const Answers& reference, const Answers& other, bool any_hit,
                                bool exact)
{
    std::size_t n = 0;
    if (any_hit) {
        for (std::size_t k = 0; k < reference.occluded.size(); ++k)
            n += reference.occluded[k] != other.occluded[k] ? 1 : 0;
    } else {
        for (std::size_t k = 0; k < reference.hits.size(); ++k)
            n += same_hit(reference.hits[k], other.hits[k], exact) ? 0 : 1;
    }
    return n;
}

double hit_fraction(const Answers& a, bool any_hit)
{
    std::size_t hits = 0, n = 0;
    if (any_hit) {
        for (std::uint8_t o : a.occluded) hits += o;
        n = a.occluded.size();
    } else {
        for (const Hit& h : a.hits) hits += h.is_hit() ? 1 : 0;
        n = a.hits.size();
    }
    return n ? static_cast<double>(hits) / static_cast<double>(n) : 0.0;
}

/// Brute-force answers for an evenly spaced sample of a workload.
struct OracleSample {
    std::vector<std::size_t> indices;
    Answers answers;
};

OracleSample oracle_sample(const MeshView& mesh, const Workload& w, std::size_t count)
{
    OracleSample o;
    count = std::min(count, w.rays.size());
    for (std::size_t k = 0; k < count; ++k) o.indices.push_back(k * w.rays.size() / count);
    if (w.any_hit) o.answers.occluded.resize(count);
    else o.answers.hits.resize(count);
    tbb::parallel_for(std::size_t{0}, count, [&](std::size_t k) {
        const Ray& r = w.rays[o.indices[k]];
        if (w.any_hit) o.answers.occluded[k] = occluded_brute_force(mesh, r) ? 1 : 0;
        else o.answers.hits[k] = intersect_brute_force(mesh, r);
    });
    return o;
}

std::size_t oracle_disagreements(const OracleSample& o, const Answers& a, bool any_hit, bool exact)
{
    std::size_t n = 0;
    for (std::size_t k = 0; k < o.indices.size(); ++k) {
        const std::size_t i = o.indices[k];
        if (any_hit) n += o.answers.occluded[k] != a.occluded[i] ? 1 : 0;
        else n += same_hit(o.answers.hits[k], a.hits[i], exact) ? 0 : 1;
    }
    return n;
}

// Mean traversal work per ray over the workload: every ray, or an even stride of at most
// work_sample_rays of them (the same rays for every structure). Not the oracle sample, which
// holds a few dozen rays on the largest scenes.
constexpr std::size_t work_sample_rays = std::size_t{1} << 17;

void count_work(const BenchStructure& s, const Workload& w, WorkloadResult& wr)
{
    const std::size_t stride =
        std::max<std::size_t>(1, (w.rays.size() + work_sample_rays - 1) / work_sample_rays);
    std::vector<Ray> sample;
    for (std::size_t i = 0; i < w.rays.size(); i += stride) sample.push_back(w.rays[i]);
    std::uint64_t nodes = 0, cells = 0, triangles = 0;
    // Counters are 32-bit per query: summed per chunk into 64-bit totals.
    for (std::size_t k = 0; k < sample.size(); k += 256) {
        TraversalCounters c;
        const std::span<const Ray> part(sample.data() + k, std::min<std::size_t>(256, sample.size() - k));
        if (!s.count_work(part, w.any_hit, c)) return;
        nodes += c.nodes_visited;
        cells += c.cells_visited;
        triangles += c.triangles_tested;
    }
    if (sample.empty()) return;
    const auto n = static_cast<double>(sample.size());
    wr.counted = true;
    wr.nodes_per_ray = static_cast<double>(nodes) / n;
    wr.cells_per_ray = static_cast<double>(cells) / n;
    wr.triangles_per_ray = static_cast<double>(triangles) / n;
}

std::size_t mesh_bytes(const MeshView& mesh)
{
    return mesh.vertices.size() * sizeof(Vec3f) + mesh.triangles.size() * sizeof(Triangle);
}

std::string threads_text(unsigned t) { return std::to_string(t) + (t == 1 ? " thread" : " threads"); }

/// A structure, the median of its timed builds and the memory of its untimed one.
struct TimedBuild {
    std::unique_ptr<BenchStructure> built;
    double seconds = 0.0;
    BuildMemory memory;
};

// Builds `name` `repeats` times (at least once) on `threads` threads and keeps the last build
// and the median time. Every structure is timed the same way: the one built before is
// released first, so a build reuses memory the process already holds instead of faulting in
// new pages beside a live structure; and with `warm_up_threads` > 0, one untimed build on that
// many threads goes first, so costs a library pays once per process (its thread pool, its
// first pages) are not charged to one thread count (docs/notebook/build.md, "Build time:
// first builds", has the figures). The untimed build is the one whose peak memory is measured
// (build_memory.hpp): counting every allocation would slow the timed ones.
TimedBuild timed_build(const std::string& name, const MeshView& mesh,
                       const StructureConfigs& configs, unsigned threads, std::uint32_t repeats,
                       unsigned warm_up_threads, std::unique_ptr<BenchStructure> previous = {})
{
    previous.reset();
    TimedBuild out;
    if (warm_up_threads > 0) {
        const BuildMemoryWindow window;
        const auto warm = build_structure(name, mesh, configs, warm_up_threads);
        out.memory.peak_bytes = warm->own_build_peak_bytes().value_or(window.peak_bytes());
        if (window.high_water_reset())
            out.memory.process_high_water_bytes = BuildMemoryWindow::process_high_water_bytes();
    }
    std::vector<double> times;
    for (std::uint32_t k = 0; k < std::max<std::uint32_t>(1, repeats); ++k) {
        out.built.reset();
        out.built = build_structure(name, mesh, configs, threads);
        times.push_back(out.built->build_seconds());
    }
    out.seconds = median(times);
    return out;
}

class Runner {
public:
    Runner(const BenchPlan& plan, const BenchLog& log) : plan_(plan), log_(log) {}

    SceneResult run_scene(const BenchScene& scene, std::vector<Workload>* keep_workloads)
    {
        const MeshView mesh = scene.mesh.view();
        SceneResult result;
        result.scene = scene.name;
        result.source = scene.source;
        result.triangles = mesh.triangle_count();
        result.vertices = mesh.vertices.size();
        say(scene.name + ": " + std::to_string(result.triangles) + " triangles");

        // The workloads come from the first structure (the Split Grid unless the plan says
        // otherwise); every structure then traces the very same rays.
        // That structure is released once they are made, so that no build below runs beside it.
        const auto start = Clock::now();
        std::vector<Workload> workloads = make_scene_workloads(
            mesh, *build_structure(plan_.structures.front(), mesh, plan_.configs, 0), plan_.sizes,
            plan_.seed);
        result.workload_seconds = seconds_since(start);
        for (const Workload& w : workloads) {
            result.workload_names.push_back(w.name);
            result.workload_rays.push_back(w.rays.size());
        }
        say(scene.name + ": workloads made in " + fixed(result.workload_seconds, 2) + " s");

        const std::size_t oracle_count = std::max<std::size_t>(
            20, std::min<std::size_t>(plan_.oracle_rays,
                                      plan_.oracle_budget / std::max<std::size_t>(1, result.triangles)));
        std::vector<OracleSample> oracles;
        for (const Workload& w : workloads) oracles.push_back(oracle_sample(mesh, w, oracle_count));

        std::unique_ptr<PointBench> points;
        if (plan_.points.any()) {
            const auto incoherent =
                std::find_if(workloads.begin(), workloads.end(),
                             [](const Workload& w) { return w.name == "incoherent"; });
            points = std::make_unique<PointBench>(
                mesh, std::span<const Ray>(incoherent->rays), plan_.points, plan_.thread_counts,
                plan_.trace_repeats, plan_.seed,
                [&](const std::string& line) { say(scene.name + ": " + line); });
            result.edges_counted = true;
            result.edges = points->edges();
        }

        std::vector<Answers> reference_answers(workloads.size());
        for (const std::string& name : plan_.structures) {
            StructureResult sr;
            sr.structure = name;
            std::unique_ptr<BenchStructure> built;
            for (unsigned threads : plan_.thread_counts) {
                say(scene.name + ": building " + name + " on " + threads_text(threads));
                // The untimed build goes before the first thread count, on the last (the one the
                // targets are read on), and its memory is the structure's peak build memory.
                const bool first = threads == plan_.thread_counts.front();
                TimedBuild timed = timed_build(name, mesh, plan_.configs, threads, plan_.build_repeats,
                                               first ? plan_.thread_counts.back() : 0, std::move(built));
                built = std::move(timed.built);
                sr.build_seconds.push_back(timed.seconds);
                if (first) sr.build_memory = timed.memory;
            }
            sr.structure_bytes = built->structure_bytes();
            sr.total_bytes = sr.structure_bytes + mesh_bytes(mesh);
            sr.references = built->reference_count();
            const bool exact = name != "embree";
            for (std::size_t wi = 0; wi < workloads.size(); ++wi) {
                const Workload& w = workloads[wi];
                WorkloadResult wr;
                wr.workload = w.name;
                wr.rays = w.rays.size();
                wr.any_hit = w.any_hit;
                Answers answers;
                for (unsigned threads : plan_.thread_counts) {
                    say(scene.name + ": " + name + " traces " + w.name + " on " + threads_text(threads));
                    std::vector<double> rates;
                    for (std::uint32_t k = 0; k < plan_.trace_repeats; ++k)
                        rates.push_back(mrays(w.rays.size(),
                                              trace(*built, w.rays, w.any_hit, threads, {}, answers)));
                    wr.mrays_per_s.push_back(median(rates));
                }
                wr.hit_fraction = hit_fraction(answers, w.any_hit);
                wr.oracle_rays = oracles[wi].indices.size();
                count_work(*built, w, wr);
                wr.oracle_disagreements = oracle_disagreements(oracles[wi], answers, w.any_hit, exact);
                if (name == plan_.structures.front()) reference_answers[wi] = std::move(answers);
                else
                    wr.reference_disagreements =
                        count_disagreements(reference_answers[wi], answers, w.any_hit, exact);
                sr.workloads.push_back(wr);
            }
            if (points) {
                if (const PointQueries* queries = built->point_queries())
                    points->measure(name, *queries);
                else
                    points->skip(name, "no hit counts or point queries (Debian's Embree 3 lacks "
                                       "the filter functions a hit count needs)");
            }
            result.structures.push_back(std::move(sr));
        }
        const bool inside_test = plan_.points.inside_vertices > 0 &&
                                 (points ? points->edges() : edge_report(mesh)).is_closed();
        std::unique_ptr<CgalPeer> cgal;
        if (has_cgal() && (points || inside_test)) {
            say(scene.name + ": building CGAL's Surface_mesh and trees");
            cgal = timed_cgal_build(mesh, plan_.build_repeats, result.cgal);
            if (points) points->measure("cgal", *cgal);
        }
        if (points) result.point_workloads = points->results();
        if (inside_test) {
            say(scene.name + ": inside test near " + std::to_string(plan_.points.inside_vertices) +
                " vertices");
            const InsideSet set = near_vertex_set(mesh, scene.name, plan_.points.inside_vertices);
            const auto grid = build_structure("splitgrid", mesh, plan_.configs, 0);
            inside_tests_.push_back(run_inside_test(set, *grid->point_queries(), cgal.get(),
                                                    plan_.trace_repeats));
            if (!plan_.save_points.empty()) save_inside_set(plan_.save_points, set);
        }
        if (!plan_.save_points.empty()) {
            save_scene(plan_.save_points, scene.name, mesh, plan_.configs.split_grid);
            if (points) save_point_sets(plan_.save_points, scene.name, *points);
        }
        if (keep_workloads) *keep_workloads = std::move(workloads);
        return result;
    }

    /// The inside tests of the tessellated cube and the icosphere, then those of the closed
    /// scenes made by run_scene.
    std::vector<InsideTestResult> run_inside_tests()
    {
        std::vector<InsideTestResult> out;
        const Mesh cube = inside_test_cube();
        const Mesh sphere = inside_test_icosphere();
        const std::pair<const Mesh*, std::vector<InsideSet>> shapes[] = {
            {&cube, cube_inside_sets(cube)}, {&sphere, icosphere_inside_sets(sphere)}};
        for (const auto& [shape, sets] : shapes) {
            const MeshView mesh = shape->view();
            const auto grid = build_structure("splitgrid", mesh, plan_.configs, 0);
            std::unique_ptr<CgalPeer> cgal;
            if (has_cgal()) cgal = build_cgal(mesh);
            for (const InsideSet& set : sets) {
                say("inside test " + set.name + ": " + std::to_string(set.points.size()) +
                    " points");
                out.push_back(run_inside_test(set, *grid->point_queries(), cgal.get(),
                                              plan_.trace_repeats));
                if (!plan_.save_points.empty()) save_inside_set(plan_.save_points, set);
            }
            if (!plan_.save_points.empty() && !sets.empty())
                save_scene(plan_.save_points, sets.front().scene, mesh, plan_.configs.split_grid);
        }
        out.insert(out.end(), inside_tests_.begin(), inside_tests_.end());
        return out;
    }

    std::vector<AccuracyResult> run_accuracy()
    {
        std::vector<AccuracyResult> out;
        const struct {
            const char* name;
            Vec3f centre;
        } positions[] = {{"origin", {0.0f, 0.0f, 0.0f}}, {"far", {148376.0f, 1234.0f, -223423.0f}}};
        constexpr float radius = 1000.0f;
        for (const auto& p : positions) {
            const Mesh sphere = closed_sphere(p.centre, radius, plan_.watertight_triangles);
            const std::vector<Ray> rays =
                interior_rays(sphere, p.centre, radius, plan_.watertight_rays, plan_.seed + 7);
            say(std::string("watertightness (") + p.name + "): " +
                std::to_string(sphere.triangles.size()) + " triangles, " +
                std::to_string(rays.size()) + " rays from inside");
            for (const std::string& name : plan_.structures) {
                const bool embree = name == "embree";
                std::vector<std::pair<std::string, bool>> embree_modes{{"default", false},
                                                                       {"robust", true}};
                const std::size_t runs = embree ? embree_modes.size() : all_variants().size();
                for (std::size_t v = 0; v < runs; ++v) {
                    StructureConfigs configs = plan_.configs;
                    QueryVariant variant;
                    std::string variant_label;
                    if (embree) {
                        configs.embree_robust = embree_modes[v].second;
                        variant_label = embree_modes[v].first;
                    } else {
                        variant = all_variants()[v];
                        variant_label = variant_name(variant);
                    }
                    const auto built = build_structure(name, sphere.view(), configs, 0);
                    Answers answers;
                    std::vector<double> rates;
                    for (std::uint32_t k = 0; k < plan_.trace_repeats; ++k)
                        rates.push_back(mrays(rays.size(), trace(*built, rays, false, 1, variant, answers)));
                    AccuracyResult a;
                    a.structure = name;
                    a.variant = variant_label;
                    a.position = p.name;
                    a.rays = rays.size();
                    for (std::size_t k = 0; k < answers.hits.size(); ++k) {
                        if (answers.hits[k].is_hit()) continue;
                        ++a.misses;
                        const std::size_t kind = interior_ray_kind(k);
                        (kind == 0 ? a.misses_random : kind == 1 ? a.misses_vertex : a.misses_edge)++;
                    }
                    a.mrays_per_s = median(rates);
                    say("  " + name + " " + variant_label + ": " + std::to_string(a.misses) +
                        " misses, " + fixed(a.mrays_per_s, 2) + " Mrays/s");
                    out.push_back(a);
                }
            }
        }
        return out;
    }

    std::vector<SweepResult> run_sweep(const BenchScene& scene, const Workload& path)
    {
        const MeshView mesh = scene.mesh.view();
        const std::span<const Ray> rays(path.rays.data(), std::min(path.rays.size(), plan_.sweep_rays));
        const unsigned threads = plan_.thread_counts.back();
        struct Point {
            std::string parameter;
            std::string value;
            BuildConfig config;
        };
        std::vector<Point> points;
        const BuildConfig base = plan_.configs.split_grid;
        points.push_back({"default", "", base});
        auto vary = [&](const std::string& parameter, const std::string& value, auto set) {
            BuildConfig c = base;
            set(c);
            points.push_back({parameter, value, c});
        };
        for (std::uint32_t v : {16u, 32u, 128u, 256u})
            vary("resolution_max", std::to_string(v), [&](BuildConfig& c) { c.resolution_max = v; });
        for (double v : {12.0, 24.0, 96.0, 192.0})
            vary("resolution_sigma", fixed(v, 0), [&](BuildConfig& c) { c.resolution_sigma = v; });
        for (std::uint32_t v : {1u, 4u})
            vary("resolution_min", std::to_string(v), [&](BuildConfig& c) { c.resolution_min = v; });
        for (std::uint32_t v : {4u, 8u, 32u, 64u})
            vary("leaf_size", std::to_string(v), [&](BuildConfig& c) { c.leaf_size = v; });
        for (std::uint32_t v : {4u, 8u, 16u})
            vary("max_depth", std::to_string(v), [&](BuildConfig& c) { c.max_depth = v; });
        for (double v : {0.0, 0.5, 2.0})
            vary("min_cell_width", fixed(v, 1), [&](BuildConfig& c) { c.min_cell_width = v; });
        vary("bounding_planes", "off", [](BuildConfig& c) { c.bounding_planes = false; });
        vary("bounding_nodes", "off", [](BuildConfig& c) { c.bounding_nodes = false; });
        vary("clip_triangles", "off", [](BuildConfig& c) { c.clip_triangles = false; });

        std::vector<SweepResult> out;
        Answers default_answers;
        for (const Point& p : points) {
            StructureConfigs configs = plan_.configs;
            configs.split_grid = p.config;
            say("sweep on " + scene.name + ": " + p.parameter + (p.value.empty() ? "" : " = " + p.value));
            TimedBuild timed = timed_build("splitgrid", mesh, configs, threads, plan_.build_repeats,
                                           p.parameter == "default" ? threads : 0);
            const std::unique_ptr<BenchStructure> built = std::move(timed.built);
            Answers answers;
            std::vector<double> rates;
            for (std::uint32_t k = 0; k < plan_.trace_repeats; ++k)
                rates.push_back(mrays(rays.size(), trace(*built, rays, false, threads, {}, answers)));
            SweepResult r;
            r.parameter = p.parameter;
            r.value = p.value;
            r.config = p.config;
            r.build_seconds = timed.seconds;
            r.mrays_per_s = median(rates);
            r.bytes_per_triangle =
                per_triangle(built->structure_bytes() + mesh_bytes(mesh), mesh.triangle_count());
            r.references_per_triangle = per_triangle(built->reference_count(), mesh.triangle_count());
            if (p.parameter == "default") default_answers = answers;
            else r.disagreements = count_disagreements(default_answers, answers, false, true);
            out.push_back(r);
        }
        return out;
    }

    std::vector<ScaleResult> run_scale(const BenchScene& model)
    {
        std::vector<ScaleResult> out;
        const unsigned threads = plan_.thread_counts.back();
        for (std::size_t size : plan_.scale_sizes) {
            const Mesh scene = scale_scene(model.mesh.view(), size, plan_.seed);
            const MeshView mesh = scene.view();
            for (const std::string& name : plan_.structures) {
                say("scale " + std::to_string(mesh.triangle_count()) + " triangles: building " + name);
                TimedBuild timed = timed_build(name, mesh, plan_.configs, threads, 1, threads);
                const std::unique_ptr<BenchStructure> built = std::move(timed.built);
                ScaleResult r;
                r.structure = name;
                r.triangles = mesh.triangle_count();
                r.build_seconds = timed.seconds;
                r.build_memory = timed.memory;
                r.structure_bytes_per_triangle = per_triangle(built->structure_bytes(), r.triangles);
                r.total_bytes_per_triangle =
                    per_triangle(built->structure_bytes() + mesh_bytes(mesh), r.triangles);
                r.references_per_triangle = per_triangle(built->reference_count(), r.triangles);
                out.push_back(r);
            }
        }
        return out;
    }

private:
    void say(const std::string& line) const
    {
        if (log_) log_(line);
    }
    static std::string fixed(double v, int digits)
    {
        std::ostringstream s;
        s.setf(std::ios::fixed);
        s.precision(digits);
        s << v;
        return s.str();
    }

    const BenchPlan& plan_;
    const BenchLog& log_;
    std::vector<InsideTestResult> inside_tests_;  // of the closed scenes, in scene order
};

}  // namespace

double median(std::vector<double> values)
{
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

Mesh scale_scene(const MeshView& model, std::size_t triangles, std::uint32_t seed)
{
    const std::size_t n = model.triangle_count();
    if (n == 0 || triangles == 0) throw InputError("scale scene: no triangles to make it from");
    if (triangles < n) {
        // The triangles whose centroids lie nearest to the first triangle's: a connected
        // patch of real surface, not a random subset.
        auto centroid = [&](std::size_t t) {
            const auto k = static_cast<std::uint32_t>(t);
            return (model.vertex(k, 0) + model.vertex(k, 1) + model.vertex(k, 2)) * (1.0f / 3.0f);
        };
        const Vec3f seed_point = centroid(n / 2);
        std::vector<std::pair<float, std::uint32_t>> by_distance(n);
        for (std::size_t t = 0; t < n; ++t) {
            const Vec3f d = centroid(t) - seed_point;
            by_distance[t] = {dot(d, d), static_cast<std::uint32_t>(t)};
        }
        std::nth_element(by_distance.begin(), by_distance.begin() + static_cast<std::ptrdiff_t>(triangles),
                         by_distance.end());
        // The patch's triangles in the model's order, with only their own vertices, so that
        // bytes per triangle count no unused ones.
        std::vector<std::uint32_t> ids(triangles);
        for (std::size_t k = 0; k < triangles; ++k) ids[k] = by_distance[k].second;
        std::sort(ids.begin(), ids.end());
        return extract_triangles(model, ids);
    }
    ArenaConfig config;
    config.copies = static_cast<std::uint32_t>(
        std::max<std::size_t>(1, (triangles + n / 2) / n));
    config.seed = seed;
    return make_arena_scene(model, config);
}

bool same_hit(const Hit& a, const Hit& b, bool exact)
{
    if (a.is_hit() != b.is_hit()) return false;
    if (!a.is_hit()) return true;
    if (a.t == b.t || a.triangle == b.triangle) return true;
    if (exact) return false;
    return std::abs(a.t - b.t) <= 1e-4f * std::max(1.0f, std::abs(a.t));
}

double trace_closest(const BenchStructure& s, std::span<const Ray> rays, unsigned threads,
                     std::vector<Hit>& hits)
{
    Answers answers;
    answers.hits = std::move(hits);
    const double seconds = trace(s, rays, false, threads, QueryVariant{}, answers);
    hits = std::move(answers.hits);
    return seconds;
}

BenchResults run_bench(const std::vector<BenchScene>& scenes, const BenchScene& scale_model,
                       const BenchPlan& plan, const BenchLog& log)
{
    if (plan.structures.empty()) throw ConfigError("no structures to measure");
    if (plan.thread_counts.empty()) throw ConfigError("no thread counts to measure");
    Runner runner(plan, log);
    BenchResults results;
    std::vector<Workload> first_workloads;
    for (std::size_t k = 0; k < scenes.size(); ++k)
        results.scenes.push_back(runner.run_scene(scenes[k], k == 0 ? &first_workloads : nullptr));
    if (plan.points.inside_vertices > 0) results.inside_tests = runner.run_inside_tests();
    if (plan.watertight_rays > 0) results.accuracy = runner.run_accuracy();
    if (plan.sweep && !scenes.empty()) {
        results.sweep_scene = scenes.front().name;
        results.sweep = runner.run_sweep(scenes.front(), first_workloads.at(1));
    }
    if (!plan.scale_sizes.empty() && !scale_model.mesh.triangles.empty()) {
        results.scale_model = scale_model.name;
        results.scale = runner.run_scale(scale_model);
    }
    return results;
}

}  // namespace sg::bench
