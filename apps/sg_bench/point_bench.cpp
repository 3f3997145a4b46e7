#include "point_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "bench_run.hpp"
#include "cli_common.hpp"
#include "splitgrid/brute_force.hpp"
#include "splitgrid/closest_point.hpp"

namespace sg::bench {
namespace {

using apps::seconds_since;
using Clock = std::chrono::steady_clock;

// Queries per task, as the ray workloads' (bench_run.cpp): the virtual call and the task cost
// vanish, two threads share the work evenly, and a closest point batch is long enough to be
// answered in Morton order (closest_point.hpp).
constexpr std::size_t query_grain = 1024;

// Points an inside test's timed pass answers at least (run_inside_test).
constexpr std::size_t inside_pass_points = 200'000;

// Runs `query(inputs, answers)` over `inputs` in chunks on `threads` threads; returns the wall
// time in seconds.
template <class Input, class Answer, class Query>
double pass(std::span<const Input> inputs, std::vector<Answer>& answers, unsigned threads,
            const Query& query)
{
    answers.assign(inputs.size(), Answer{});
    tbb::task_arena arena(static_cast<int>(threads));
    const auto start = Clock::now();
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, inputs.size(), query_grain),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              query(inputs.subspan(r.begin(), r.size()),
                                    std::span<Answer>(answers).subspan(r.begin(), r.size()));
                          });
    });
    return seconds_since(start);
}

// Evenly spaced indices of `count` of `size` items.
std::vector<std::size_t> even_sample(std::size_t size, std::size_t count)
{
    count = std::min(count, size);
    std::vector<std::size_t> indices;
    for (std::size_t k = 0; k < count; ++k) indices.push_back(k * size / count);
    return indices;
}

// Whether two closest points agree: the same distance, bit for bit, when both are ours (a tie
// between triangles is no disagreement); within 1e-5 relative (plus 2^-40 of the scene's
// magnitude, the error bound of closest_point.hpp) against a peer's double computation.
bool same_distance(const ClosestPoint& a, const ClosestPoint& b, bool exact, double magnitude)
{
    if (exact) return a.distance == b.distance;
    return std::abs(double(a.distance) - double(b.distance)) <=
           1e-5 * std::max(double(a.distance), double(b.distance)) + std::ldexp(magnitude, -40);
}

double mean_of(const std::vector<std::int32_t>& v)
{
    double sum = 0.0;
    for (const std::int32_t x : v) sum += x;
    return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}
double mean_of(const std::vector<float>& v)
{
    double sum = 0.0;
    for (const float x : v) sum += x;
    return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}
double mean_of(const std::vector<ClosestPoint>& v)
{
    double sum = 0.0;
    for (const ClosestPoint& c : v) sum += c.distance;
    return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

// One workload: its queries, the oracle's answers for a sample, and the answers of the first
// method that answered it, which every later method is compared with.
template <class Input, class Answer>
struct QueryWorkload {
    PointWorkloadResult result;
    std::vector<Input> inputs;
    std::vector<std::size_t> sample;  // indices the oracle decided
    std::vector<Answer> expected;     // the oracle's answer for each of `sample`
    std::vector<Answer> reference;
    bool has_reference = false;
    std::string unavailable;  // "" when the workload runs, else why no method runs it
};

}  // namespace

struct PointBench::State {
    MeshView mesh;
    PointPlan plan;
    std::vector<unsigned> thread_counts;
    std::uint32_t repeats = 1;
    PointLog log;
    EdgeReport edges;
    double magnitude = 0.0;  // largest coordinate magnitude of the scene's box
    std::vector<QueryWorkload<Ray, std::int32_t>> counts;
    std::vector<QueryWorkload<Vec3f, float>> occupancy;
    std::vector<QueryWorkload<Vec3f, ClosestPoint>> closest;

    void say(const std::string& line) const
    {
        if (log) log(line);
    }

    // Measures one method on one workload (PointBench::measure).
    template <class Input, class Answer, class Query, class Same>
    void run(QueryWorkload<Input, Answer>& w, const std::string& method, std::string unavailable,
             const Query& query, const Same& same)
    {
        PointMethodResult r;
        r.method = method;
        if (unavailable.empty()) unavailable = w.unavailable;
        if (!unavailable.empty()) {
            r.status = "n/a: " + unavailable;
            w.result.methods.push_back(r);
            return;
        }
        const std::string what = method + " " + w.result.query + " (" + w.result.points + ")";
        say(what + ": checking " + std::to_string(w.inputs.size()) + " answers");
        std::vector<Answer> answers;
        const std::span<const Input> inputs(w.inputs);
        pass(inputs, answers, thread_counts.back(), query);
        for (std::size_t k = 0; k < w.sample.size(); ++k)
            r.oracle_disagreements += same(w.expected[k], answers[w.sample[k]]) ? 0 : 1;
        if (w.has_reference) {
            for (std::size_t i = 0; i < answers.size(); ++i)
                r.reference_disagreements += same(w.reference[i], answers[i]) ? 0 : 1;
        } else {
            w.result.mean_answer = mean_of(answers);
            w.reference = std::move(answers);
            w.has_reference = true;
        }
        if (r.oracle_disagreements > 0) {
            r.status = "wrong";
            say(what + ": " + std::to_string(r.oracle_disagreements) + " of " +
                std::to_string(w.sample.size()) + " answers unlike the oracle's: not timed");
            w.result.methods.push_back(r);
            return;
        }
        for (const unsigned threads : thread_counts) {
            std::vector<double> rates;
            for (std::uint32_t k = 0; k < repeats; ++k) {
                const double seconds = pass(inputs, answers, threads, query);
                rates.push_back(seconds > 0.0 ? static_cast<double>(inputs.size()) / seconds : 0.0);
            }
            r.queries_per_s.push_back(median(rates));
        }
        w.result.methods.push_back(r);
    }
};

PointBench::PointBench(const MeshView& mesh, std::span<const Ray> incoherent, const PointPlan& plan,
                       std::vector<unsigned> thread_counts, std::uint32_t repeats,
                       std::uint32_t seed, PointLog log)
    : state_(std::make_unique<State>())
{
    State& s = *state_;
    s.mesh = mesh;
    s.plan = plan;
    s.thread_counts = std::move(thread_counts);
    s.repeats = std::max<std::uint32_t>(1, repeats);
    s.log = std::move(log);
    s.edges = edge_report(mesh);
    const Aabb box = bounds(mesh);
    for (int k = 0; k < 3; ++k)
        s.magnitude =
            std::max({s.magnitude, std::abs(double(box.lower[k])), std::abs(double(box.upper[k]))});
    const std::size_t triangles = std::max<std::size_t>(1, mesh.triangle_count());
    const std::size_t point_sample =
        std::max<std::size_t>(20, std::min<std::uint64_t>(plan.oracle_points,
                                                          plan.oracle_budget / triangles));

    if (plan.count_rays > 0) {
        QueryWorkload<Ray, std::int32_t> w;
        w.result.query = "count";
        w.result.points = "incoherent";
        w.inputs.assign(incoherent.begin(),
                        incoherent.begin() + static_cast<std::ptrdiff_t>(
                                                 std::min(plan.count_rays, incoherent.size())));
        // Counting a ray against every triangle costs about what brute-force closest hits do:
        // the ray workloads' budget of 4e8 tests.
        w.sample = even_sample(w.inputs.size(),
                               std::max<std::size_t>(20, std::min<std::uint64_t>(plan.oracle_points,
                                                                                 400'000'000 /
                                                                                     triangles)));
        w.expected.resize(w.sample.size());
        s.say("count: brute force on " + std::to_string(w.sample.size()) + " rays");
        tbb::parallel_for(std::size_t{0}, w.sample.size(), [&](std::size_t k) {
            w.expected[k] = count_intersections_brute_force(mesh, w.inputs[w.sample[k]]);
        });
        w.result.queries = w.inputs.size();
        w.result.oracle_queries = w.sample.size();
        s.counts.push_back(std::move(w));
    }

    const double band = occupancy_band(box);
    for (const char* set : {"random", "near"}) {
        const bool random = std::string(set) == "random";
        // The same seeds for both queries: the closest points are the first of the occupancy
        // points (point k of a set does not depend on the set's size).
        const std::uint32_t set_seed = seed + (random ? 2 : 3);
        auto make_points = [&](std::size_t n) {
            return random ? random_points(box, n, set_seed) : near_points(mesh, n, set_seed);
        };
        if (plan.occupancy_points > 0) {
            QueryWorkload<Vec3f, float> w;
            w.result.query = "occupancy";
            w.result.points = set;
            if (!s.edges.is_closed()) {
                w.unavailable =
                    "mesh not closed (" + std::to_string(s.edges.open_edges) + " open edges)";
            } else {
                w.inputs = make_points(plan.occupancy_points);
                const std::vector<std::size_t> candidates =
                    even_sample(w.inputs.size(), point_sample);
                s.say(std::string("occupancy (") + set + "): winding numbers of " +
                      std::to_string(candidates.size()) + " points");
                std::vector<Side> sides(candidates.size());
                std::vector<float> distances(candidates.size());
                tbb::parallel_for(std::size_t{0}, candidates.size(), [&](std::size_t k) {
                    const Vec3f p = w.inputs[candidates[k]];
                    sides[k] = side_by_winding_number(mesh, p);
                    distances[k] = closest_point_brute_force(mesh, p).distance;
                });
                for (std::size_t k = 0; k < candidates.size(); ++k) {
                    if (sides[k] == Side::undecided || !(distances[k] > band)) {
                        ++w.result.oracle_left_out;
                        continue;
                    }
                    w.sample.push_back(candidates[k]);
                    w.expected.push_back(sides[k] == Side::inside ? 1.0f : 0.0f);
                }
            }
            w.result.queries = w.inputs.size();
            w.result.oracle_queries = w.sample.size();
            s.occupancy.push_back(std::move(w));
        }
        if (plan.closest_points > 0) {
            QueryWorkload<Vec3f, ClosestPoint> w;
            w.result.query = "closest";
            w.result.points = set;
            w.inputs = make_points(plan.closest_points);
            w.sample = even_sample(w.inputs.size(), point_sample);
            w.expected.resize(w.sample.size());
            s.say(std::string("closest (") + set + "): brute force on " +
                  std::to_string(w.sample.size()) + " points");
            tbb::parallel_for(std::size_t{0}, w.sample.size(), [&](std::size_t k) {
                w.expected[k] = closest_point_brute_force(mesh, w.inputs[w.sample[k]]);
            });
            w.result.queries = w.inputs.size();
            w.result.oracle_queries = w.sample.size();
            s.closest.push_back(std::move(w));
        }
    }
}

PointBench::~PointBench() = default;

void PointBench::measure(const std::string& method, const PointQueries& queries)
{
    State& s = *state_;
    for (auto& w : s.counts)
        s.run(
            w, method, queries.unavailable(PointQuery::count),
            [&](std::span<const Ray> rays, std::span<std::int32_t> out) {
                queries.count_intersections(rays, out);
            },
            [](std::int32_t a, std::int32_t b) { return a == b; });
    for (auto& w : s.occupancy)
        s.run(
            w, method, queries.unavailable(PointQuery::occupancy),
            [&](std::span<const Vec3f> points, std::span<float> out) {
                queries.occupancy(points, out, TriangleTest::watertight);
            },
            [](float a, float b) { return a == b; });
    const bool exact = queries.exact_distances();
    for (auto& w : s.closest)
        s.run(
            w, method, queries.unavailable(PointQuery::closest),
            [&](std::span<const Vec3f> points, std::span<ClosestPoint> out) {
                queries.closest_points(points, out);
            },
            [&](const ClosestPoint& a, const ClosestPoint& b) {
                return same_distance(a, b, exact, s.magnitude);
            });
}

void PointBench::skip(const std::string& method, const std::string& why)
{
    State& s = *state_;
    auto add = [&](auto& workloads) {
        for (auto& w : workloads) {
            PointMethodResult r;
            r.method = method;
            r.status = "n/a: " + why;
            w.result.methods.push_back(r);
        }
    };
    add(s.counts);
    add(s.occupancy);
    add(s.closest);
}

const EdgeReport& PointBench::edges() const noexcept { return state_->edges; }

const std::vector<Vec3f>& PointBench::occupancy_points(const std::string& set) const
{
    static const std::vector<Vec3f> none;
    for (const auto& w : state_->occupancy)
        if (w.result.points == set) return w.inputs;
    return none;
}

const std::vector<Vec3f>& PointBench::closest_points(const std::string& set) const
{
    static const std::vector<Vec3f> none;
    for (const auto& w : state_->closest)
        if (w.result.points == set) return w.inputs;
    return none;
}

std::vector<PointWorkloadResult> PointBench::results() const
{
    std::vector<PointWorkloadResult> out;
    for (const auto& w : state_->counts) out.push_back(w.result);
    for (const auto& w : state_->occupancy) out.push_back(w.result);
    for (const auto& w : state_->closest) out.push_back(w.result);
    return out;
}

std::unique_ptr<CgalPeer> timed_cgal_build(const MeshView& mesh, std::uint32_t repeats,
                                           CgalSceneResult& result)
{
    std::unique_ptr<CgalPeer> peer = build_cgal(mesh);  // untimed: the first touch of memory
    std::vector<double> mesh_seconds, side_of_seconds, tree_seconds;
    for (std::uint32_t k = 0; k < std::max<std::uint32_t>(1, repeats); ++k) {
        peer.reset();
        peer = build_cgal(mesh);
        mesh_seconds.push_back(peer->mesh_seconds());
        side_of_seconds.push_back(peer->side_of_seconds());
        tree_seconds.push_back(peer->tree_seconds());
    }
    result.built = true;
    result.refused_faces = peer->refused_faces();
    result.closed = peer->is_closed();
    result.mesh_seconds = median(mesh_seconds);
    result.side_of_seconds = median(side_of_seconds);
    result.tree_seconds = median(tree_seconds);
    return peer;
}

InsideTestResult run_inside_test(const InsideSet& set, const PointQueries& splitgrid,
                                 const PointQueries* cgal, std::uint32_t repeats)
{
    InsideTestResult result;
    result.set = set.name;
    result.scene = set.scene;
    result.oracle = set.oracle;
    result.points = set.points.size();
    for (const Side side : set.expected) {
        result.inside += side == Side::inside ? 1 : 0;
        result.undecided += side == Side::undecided ? 1 : 0;
    }
    const std::span<const Vec3f> points(set.points);
    auto measure = [&](const std::string& method, const PointQueries* queries, TriangleTest test) {
        InsideMethodResult r;
        r.method = method;
        const std::string unavailable =
            queries ? queries->unavailable(PointQuery::occupancy) : "this sg-bench has no CGAL";
        if (!unavailable.empty()) {
            r.status = "n/a: " + unavailable;
            result.methods.push_back(r);
            return;
        }
        const auto query = [&](std::span<const Vec3f> p, std::span<float> out) {
            queries->occupancy(p, out, test);
        };
        std::vector<float> answers;
        pass(points, answers, 1, query);
        for (std::size_t k = 0; k < answers.size(); ++k) {
            if (set.expected[k] == Side::undecided) continue;
            r.wrong += answers[k] == (set.expected[k] == Side::inside ? 1.0f : 0.0f) ? 0 : 1;
        }
        // A set holds a few thousand points, answered in milliseconds: a timed pass answers it
        // `laps` times over, at least inside_pass_points points, so the clock's resolution and
        // a single interruption weigh little.
        const std::size_t laps =
            std::max<std::size_t>(1, inside_pass_points / std::max<std::size_t>(1, points.size()));
        std::vector<double> rates;
        for (std::uint32_t k = 0; k < std::max<std::uint32_t>(1, repeats); ++k) {
            double seconds = 0.0;
            for (std::size_t lap = 0; lap < laps; ++lap) seconds += pass(points, answers, 1, query);
            rates.push_back(seconds > 0.0 ? static_cast<double>(laps * points.size()) / seconds
                                          : 0.0);
        }
        r.points_per_s = median(rates);
        result.methods.push_back(r);
    };
    measure("splitgrid", &splitgrid, TriangleTest::watertight);
    measure("splitgrid_no_tie_break", &splitgrid, TriangleTest::watertight_no_tie_break);
    if (has_cgal()) measure("cgal", cgal, TriangleTest::watertight);
    return result;
}

}  // namespace sg::bench
