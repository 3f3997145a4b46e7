// sg-bench's flags and what they resolve to (bench_options.hpp).

#include "bench_options.hpp"

#include "cgal_peer.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <system_error>

#include <spdlog/fmt/fmt.h>

namespace sg::bench {
namespace {

std::vector<std::string> split_list(const std::string& text)
{
    std::vector<std::string> items;
    std::string item;
    std::istringstream in(text);
    while (std::getline(in, item, ','))
        if (!item.empty()) items.push_back(item);
    return items;
}

/// "1e6" or "2500000" as a count of `what` (triangles, rays) in [1, 4e9]; a usage error
/// otherwise.
std::vector<std::size_t> counts_of(const std::string& text, const char* flag,
                                   const char* what = "triangle")
{
    std::vector<std::size_t> counts;
    for (const std::string& item : split_list(text)) {
        double value = 0.0;
        const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), value);
        if (ec != std::errc{} || ptr != item.data() + item.size() || !(value >= 1.0 && value <= 4e9))
            throw CLI::ValidationError(
                fmt::format("{}: {} is not a {} count in [1, 4e9]", flag, item, what));
        counts.push_back(static_cast<std::size_t>(std::llround(value)));
    }
    return counts;
}

/// The structures a comma-separated `text` names (all of `known` when it names none); a usage
/// error naming `flag` for a name not in `known`.
std::vector<std::string> structures_of(const std::string& text,
                                       const std::vector<std::string>& known, const char* flag)
{
    std::vector<std::string> names = split_list(text);
    if (names.empty()) return known;
    for (const std::string& name : names)
        if (std::find(known.begin(), known.end(), name) == known.end())
            throw CLI::ValidationError(
                fmt::format("{}: unknown structure '{}' (this build knows {})", flag, name,
                            fmt::join(known, ", ")));
    return names;
}

std::vector<unsigned> threads_of(const std::string& text)
{
    std::vector<unsigned> threads;
    for (const std::string& item : split_list(text)) {
        unsigned value = 0;
        const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), value);
        if (ec != std::errc{} || ptr != item.data() + item.size() || value < 1 || value > 1024)
            throw CLI::ValidationError(
                fmt::format("--threads: {} is not a thread count in [1, 1024]", item));
        threads.push_back(value);
    }
    return threads;
}

void apply_quick_defaults(const CLI::App& app, BenchOptions& o)
{
    auto unset = [&](const char* flag) { return app.count(flag) == 0; };
    BenchPlan& p = o.plan;
    if (unset("--width")) p.sizes.width = 160;
    if (unset("--height")) p.sizes.height = 120;
    if (unset("--incoherent-rays")) p.sizes.incoherent_rays = 20'000;
    if (unset("--build-repeats")) p.build_repeats = 1;
    if (unset("--trace-repeats")) p.trace_repeats = 1;
    if (unset("--oracle-rays")) p.oracle_rays = 100;
    if (unset("--watertight-triangles")) p.watertight_triangles = 10'000;
    if (unset("--watertight-rays")) p.watertight_rays = 20'000;
    if (unset("--sweep-rays")) p.sweep_rays = 20'000;
    if (unset("--count-rays")) p.points.count_rays = 2'000;
    if (unset("--occupancy-points")) p.points.occupancy_points = 2'000;
    if (unset("--closest-points")) p.points.closest_points = 500;
    if (unset("--inside-vertices")) p.points.inside_vertices = 10;
}

/// Embree and CGAL, for --version, where this build measures them.
std::vector<sg::LibraryVersion> peer_libraries()
{
    std::vector<sg::LibraryVersion> peers;
    if (has_embree()) peers.push_back({"Embree", embree_version()});
    if (has_cgal()) peers.push_back({"CGAL", cgal_version()});
    return peers;
}

/// The thread counts of --threads (or 1 and the hardware's), each at most the hardware's
/// threads (one warning otherwise, threads_to_use), without repeats.
std::vector<unsigned> thread_counts_of(const std::string& text)
{
    std::vector<unsigned> asked = threads_of(text);
    if (asked.empty()) {
        asked = {1};
        const unsigned hw = apps::threads_that_run(0);
        if (hw > 1) asked.push_back(hw);
    }
    std::vector<unsigned> counts;
    for (const unsigned t : asked) {
        const unsigned used = apps::threads_to_use(t);
        if (std::find(counts.begin(), counts.end(), used) == counts.end()) counts.push_back(used);
    }
    return counts;
}

}  // namespace

void add_bench_options(CLI::App& app, BenchOptions& o)
{
    apps::describe_tool(
        app,
        "Measures the Split Grid (built from the build flags, and as splitgrid_poster with the\n"
        "poster preset applied over them) against a uniform grid, a kd-tree, a BVH and Intel\n"
        "Embree on the same scenes and the same rays: build time (median of --build-repeats builds,\n"
        "after one untimed build) on each thread count, memory (structure, and structure + mesh,\n"
        "per triangle, and the most a build held at once), Mrays/s\n"
        "(median of --trace-repeats passes) for four workloads, and correctness (brute force\n"
        "on a sample of every workload, and every ray against the first structure). Then rays\n"
        "from inside a closed sphere for each triangle test and padding (leaks per million),\n"
        "a Split Grid parameter sweep on the first scene, and memory against scene size.\n"
        "Point workloads: hit counts of incoherent rays, inside or outside (closed meshes)\n"
        "and closest points of random and near points, for our structures and CGAL (when\n"
        "built with SG_WITH_CGAL), answers checked before speed; inside tests where rays\n"
        "meet edges and vertices (a tessellated cube, an icosphere, each closed scene).\n"
        "Dynamic scenes (--dynamic-rigid, --dynamic-deform; with them MESH may be left\n"
        "out): every frame, each structure rebuilt or refitted on the moved mesh, then one\n"
        "frame of path rays traced per --dynamic-rays budget; time per frame against rays.",
        "Workloads: primary (one ray per pixel of a --width x --height camera framing the\n"
        "scene), path (those rays plus up to --bounces diffuse bounces each, the paper's\n"
        "Figure 3 workload), incoherent (random origins in the scene box, random directions),\n"
        "shadow (any-hit rays from primary hits to a light above the scene).\n"
        "Outputs in -o/--output: results.json (docs/BENCH.md), results.csv, and the charts\n"
        "of scripts/bench_charts.py (python3-matplotlib): figure3.png, speed_vs_accuracy.png\n"
        "(not with --watertight-rays 0), sweep_build_vs_trace.png (not with --no-sweep) and\n"
        "memory_scaling.png (only with --scale-sizes), dynamic.png (only with a dynamic\n"
        "scene), point_workloads.png (not with --count-rays, --occupancy-points and\n"
        "--closest-points all 0) and inside_tests.png (not with --inside-vertices 0).\n"
        "stdout holds the table; progress,\n"
        "notices and the list of files written go to stderr. Timings depend on the\n"
        "machine's load: compare structures within one run.",
        peer_libraries());
    app.add_option("MESH", o.meshes, "Scenes to measure (any mesh Assimp reads)");
    apps::add_output_option(app, o.out,
                                apps::help_text("Output folder, created if missing (its "
                                                    "parent must exist).",
                                                    {}, o.out.string()),
                                false, "DIR");
    app.add_flag("--quick", o.quick,
                 "Small workloads and one repeat, for a smoke test in under a minute: 160x120 "
                 "images, 20k incoherent rays, 10k-triangle sphere; flags given explicitly win");
    app.add_option("--structures", o.structures_text,
                   apps::help_text("Structures to measure, comma-separated, the first being "
                                       "the reference of the cross-check.",
                                       {},
                                       "all this build has: " +
                                           fmt::format("{}", fmt::join(structure_names(), ","))))
        ->type_name("LIST");
    app.add_option("--threads", o.threads_text,
                   apps::help_text("Thread counts to build and trace with, comma-separated "
                                       "(above the hardware's threads: the hardware's, with a "
                                       "warning).",
                                       "[1, 1024] each", "1 and the hardware threads"))
        ->type_name("LIST");
    app.add_option("--scale-model", o.scale_model,
                   apps::help_text("Mesh the scale series and arena scenes are made from.",
                                       {}, "the first MESH"))
        ->type_name("MESH");
    app.add_option("--scale-sizes", o.scale_sizes_text,
                   apps::help_text("Triangle counts of the memory-against-size series (and "
                                       "its chart), comma-separated, e.g. 1e3,1e4,1e5,1e6,1e7. "
                                       "Below the model's size a patch of it, above it copies "
                                       "in an arena.",
                                       {}, "none"))
        ->type_name("LIST");
    app.add_option("--arena-sizes", o.arena_sizes_text,
                   apps::help_text("Also measure arena scenes of these triangle counts "
                                       "(copies of the scale model on a floor, "
                                       "make_arena_scene), e.g. 2.5e6,1e7.",
                                       {}, "none"))
        ->type_name("LIST");
    apps::add_count_option(app, "--width", o.plan.sizes.width, 1, 16384,
                               "Image width of the primary and path rays.");
    apps::add_count_option(app, "--height", o.plan.sizes.height, 1, 16384, "Image height.");
    apps::add_count_option(app, "--bounces", o.plan.sizes.bounces, 0, 64,
                               "Diffuse bounces of the path workload.");
    apps::add_count_option(app, "--incoherent-rays", o.plan.sizes.incoherent_rays, 1,
                               std::uint64_t{1} << 30, "Rays of the incoherent workload.");
    apps::add_count_option(app, "--build-repeats", o.plan.build_repeats, 1, 1000,
                               "Builds per structure and thread count.");
    apps::add_count_option(app, "--trace-repeats", o.plan.trace_repeats, 1, 1000,
                               "Passes per workload and thread count.");
    apps::add_count_option(app, "--oracle-rays", o.plan.oracle_rays, 0,
                               std::uint64_t{1} << 24,
                               "Brute-force sample per workload, point workloads too (fewer on "
                               "big scenes: at most 4e8 ray/triangle tests or 1e8 point/triangle "
                               "pairs per sample, at least 20).");
    apps::add_count_option(app, "--watertight-triangles", o.plan.watertight_triangles, 100,
                               std::uint64_t{1} << 26,
                               "Triangles of the closed sphere of the watertightness workload.");
    apps::add_count_option(app, "--watertight-rays", o.plan.watertight_rays, 0,
                               std::uint64_t{1} << 30,
                               "Rays from inside the sphere, per position (0 skips the "
                               "workload and its chart).");
    apps::add_count_option(app, "--sweep-rays", o.plan.sweep_rays, 1, std::uint64_t{1} << 30,
                               "Path rays traced per sweep point.");
    apps::add_count_option(app, "--count-rays", o.plan.points.count_rays, 0,
                           std::uint64_t{1} << 30,
                           "Rays of the count workload: the first of the incoherent rays, each "
                           "ray's hits counted (count_intersections; 0 skips it).");
    apps::add_count_option(app, "--occupancy-points", o.plan.points.occupancy_points, 0,
                           std::uint64_t{1} << 30,
                           "Points of each occupancy workload (random in the box, near the "
                           "surface; closed meshes only; 0 skips them).");
    apps::add_count_option(app, "--closest-points", o.plan.points.closest_points, 0,
                           std::uint64_t{1} << 30,
                           "Points of each closest point workload (random, near; 0 skips "
                           "them).");
    apps::add_count_option(app, "--inside-vertices", o.plan.points.inside_vertices, 0,
                           std::uint64_t{1} << 20,
                           "Vertices of a closed scene the inside test takes points near (0 "
                           "skips the inside tests, the cube's and the icosphere's too).");
    app.add_option("--save-points", o.plan.save_points,
                   apps::help_text("Also write the point sets measured into this folder "
                                   "(created if missing; its parent must exist): each scene as "
                                   "a .sg file, its points as point files, the inside tests' "
                                   "points with the oracle's answers, for "
                                   "scripts/bench_inside_open3d.py and scripts/bench_python.py "
                                   "--points.",
                                   {}, "none"))
        ->type_name("DIR");
    app.add_option("--dynamic-rigid", o.dynamic_rigid,
                   apps::help_text("Dynamic workload: copies of this mesh (enough for "
                                       "--dynamic-triangles) turning and circling on an arena, "
                                       "every structure rebuilt or refitted on each frame and "
                                       "tracing a frame of path rays (repeatable).",
                                       {}, "none"))
        ->type_name("MESH");
    app.add_option("--dynamic-deform", o.dynamic_deform,
                   apps::help_text("Dynamic workload: this mesh twisting and swelling "
                                       "(repeatable).",
                                       {}, "none"))
        ->type_name("MESH");
    apps::add_count_option(app, "--dynamic-frames", o.dynamic_frames, 1, 100'000,
                               "Frames of each dynamic scene.");
    apps::add_count_option(app, "--dynamic-triangles", o.dynamic_triangles, 1,
                               std::uint64_t{1} << 31,
                               "Fewest triangles of a --dynamic-rigid scene.");
    app.add_option("--dynamic-rays", o.dynamic_rays_text,
                   apps::help_text("Path rays traced per frame, comma-separated: each "
                                       "budget is one frame of the path workload, traced "
                                       "after the update.",
                                       {}, o.dynamic_rays_text))
        ->type_name("LIST");
    app.add_option("--dynamic-structures", o.dynamic_structures_text,
                   apps::help_text("Structures of the dynamic workload, comma-separated "
                                       "(the first is the yardstick of the slow rule; the rays "
                                       "come from our BVH, refitted): any of --structures "
                                       "(rebuilt each frame), bvh_refit, embree_low, "
                                       "embree_refit.",
                                       {},
                                       fmt::format("{}", fmt::join(frame_structure_names(), ","))))
        ->type_name("LIST");
    app.add_flag("--dynamic-every-frame", o.dynamic_every_frame,
                 "Run every dynamic structure on every frame (by default one whose update on "
                 "frame 1 takes over 10x the first structure's runs on every tenth frame only)");
    app.add_flag("--no-sweep", o.no_sweep, "Skip the Split Grid parameter sweep (and its chart)");
    app.add_flag("--no-charts", o.no_charts, "Write results.json and results.csv only");
    app.add_option("--charts-script", o.charts_script,
                   apps::help_text("The chart script.", {}, o.charts_script.string()))
        ->type_name("FILE");
    app.add_option("--mesh-order", o.plan.mesh_order,
                   apps::help_text(
                       "Order of every scene's triangles (and of the vertices, by first use), "
                       "the same arrays for every structure: shows how much a structure that "
                       "reads the mesh through triangle ids depends on it. file: as the file "
                       "gives them. morton: along a Morton curve of the triangles' centroids, "
                       "near in space near in memory (morton_order). shuffled: at random "
                       "(with --seed), near in space far apart in memory.",
                       {}, "file"))
        ->check(CLI::IsMember({"file", "morton", "shuffled"}))
        ->type_name("NAME");
    apps::add_count_option(app, "--seed", o.plan.seed, 0,
                               std::numeric_limits<std::uint32_t>::max(),
                               "Seed of every random workload.");
    apps::add_build_config_flags(app, o.plan.configs.split_grid, false);
    apps::add_log_flags(app, o.log);
}

ResolvedOptions resolve_options(const CLI::App& app, BenchOptions& o)
{
    if (o.quick) apply_quick_defaults(app, o);
    ResolvedOptions r;
    r.plan = o.plan;
    BenchPlan& plan = r.plan;
    plan.sweep = !o.no_sweep;
    plan.points.oracle_points = plan.oracle_rays;
    plan.structures = structures_of(o.structures_text, structure_names(), "--structures");
    plan.thread_counts = thread_counts_of(o.threads_text);
    plan.scale_sizes = counts_of(o.scale_sizes_text, "--scale-sizes");
    r.arena_sizes = counts_of(o.arena_sizes_text, "--arena-sizes");
    r.has_dynamic = !o.dynamic_rigid.empty() || !o.dynamic_deform.empty();
    if (o.meshes.empty() && (r.arena_sizes.empty() || o.scale_model.empty()) && !r.has_dynamic)
        throw CLI::ValidationError("give at least one MESH (or --arena-sizes with --scale-model, "
                                   "or a dynamic scene)");
    if (!r.has_dynamic) return r;
    DynamicPlan& dynamic_plan = r.dynamic_plan;
    dynamic_plan.structures = structures_of(o.dynamic_structures_text, frame_structure_names(),
                                            "--dynamic-structures");
    for (auto s = dynamic_plan.structures.begin(); s != dynamic_plan.structures.end(); ++s) {
        if (std::find(dynamic_plan.structures.begin(), s, *s) != s)
            throw CLI::ValidationError(fmt::format("--dynamic-structures: '{}' given twice", *s));
    }
    dynamic_plan.frames = o.dynamic_frames;
    if (o.dynamic_every_frame) dynamic_plan.slow_factor = 0.0;
    // Ascending and without repeats: the largest budget is the last (the per-ray cost of
    // the chart and report is read from it).
    std::vector<std::size_t> budgets = counts_of(o.dynamic_rays_text, "--dynamic-rays", "ray");
    std::sort(budgets.begin(), budgets.end());
    budgets.erase(std::unique(budgets.begin(), budgets.end()), budgets.end());
    if (budgets.empty()) throw CLI::ValidationError("--dynamic-rays: give at least one ray count");
    dynamic_plan.ray_budgets = budgets;
    dynamic_plan.threads = plan.thread_counts.back();
    dynamic_plan.bounces = plan.sizes.bounces;
    dynamic_plan.seed = plan.seed;
    dynamic_plan.configs = plan.configs;
    return r;
}

}  // namespace sg::bench
