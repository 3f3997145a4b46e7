// End-to-end tests of sg-bench: a quick run on a real model writes a results.json whose
// figures match what is counted here independently (the imported mesh, the image size, the
// structures asked for), a CSV with one row per scene, structure and workload, and PNG charts
// that VTK can read; bad flags and inputs fail with one line and leave no output folder.
// No timing is asserted: speed lives in the benchmark's own output.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "support/crossings_oracle.hpp"
#include "support/leaf_triangles.hpp"
#include "splitgrid/closed_shapes.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "splitgrid/formats/point_file.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/query.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#ifdef SG_RENDER_EXE
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkImageData.h>
#endif

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Small sizes so that the run also fits the sanitizer tree's CI budget.
std::vector<std::string> quick_args(const fs::path& model, const fs::path& out)
{
    return {"--quick", "--width", "64", "--height", "48", "--incoherent-rays", "4000",
            "--watertight-triangles", "2000", "--watertight-rays", "3000", "--sweep-rays", "3000",
            "--scale-sizes", "300,3000", "--threads", "1,2", "-o", out.string(), model.string()};
}

TEST(SgBench, QuickRunWritesResultsThatMatchTheInputs)
{
    ScratchDir scratch;
    const fs::path model = assimp_model("PLY/Wuson.ply");
    const fs::path out = scratch / "bench";
    const ToolRun run = run_tool(SG_BENCH_EXE, quick_args(model, out), scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);

    const json j = json::parse(read_text(out / "results.json"));
    EXPECT_EQ(j.at("schema_version"), 1);
    EXPECT_EQ(j.at("tool"), "sg-bench");
    // The instruction set the tool's kernels ran on is the one this process's would (the same
    // processor and the same SG_ISA, if set).
    EXPECT_EQ(j.at("machine").at("kernel_isa"), std::string(isa_name(kernel_isa())));
    EXPECT_EQ(j.at("plan").at("thread_counts"), json::array({1, 2}));
    const std::size_t triangles = import_mesh(model).mesh.triangles.size();
    ASSERT_EQ(j.at("scenes").size(), 1u);
    const json& scene = j.at("scenes")[0];
    EXPECT_EQ(scene.at("triangles"), triangles);
    EXPECT_EQ(scene.at("scene"), "Wuson");

    // Every structure this build has, each with the four workloads; the primary workload is
    // one ray per pixel.
    std::set<std::string> structures;
    for (const json& s : scene.at("structures")) {
        structures.insert(s.at("structure"));
        ASSERT_EQ(s.at("workloads").size(), 4u);
        EXPECT_EQ(s.at("workloads")[0].at("workload"), "primary");
        EXPECT_EQ(s.at("workloads")[0].at("rays"), 64 * 48);
        EXPECT_GT(s.at("total_bytes_per_triangle").get<double>(),
                  s.at("structure_bytes_per_triangle").get<double>());
        // Peak build memory: counted (not 0), and for our structures at least the structure
        // the build ends up holding, which the counting allocator saw allocated. (Embree's
        // structure bytes are everything its device holds, so they may include what the
        // device allocated before the build.)
        EXPECT_GT(s.at("peak_build_bytes").get<std::size_t>(), 0u) << s.at("structure");
        if (s.at("structure") != "embree") {
            EXPECT_GE(s.at("peak_build_bytes").get<std::size_t>(),
                      s.at("structure_bytes").get<std::size_t>()) << s.at("structure");
        }
        for (const json& w : s.at("workloads")) {
            EXPECT_GT(w.at("mrays_per_s").at("1").get<double>(), 0.0);
            EXPECT_GT(w.at("mrays_per_s").at("2").get<double>(), 0.0);
            EXPECT_GT(w.at("oracle_rays").get<int>(), 0);
            // Our structures share the watertight test: brute force must agree exactly.
            if (s.at("structure") != "embree") {
                EXPECT_EQ(w.at("oracle_disagreements"), 0) << s.at("structure") << " " << w.at("workload");
                EXPECT_EQ(w.at("reference_disagreements"), 0) << s.at("structure") << " " << w.at("workload");
            }
        }
    }
    for (const char* name : {"splitgrid", "splitgrid_poster", "uniform_grid", "kd_tree", "bvh"})
        EXPECT_TRUE(structures.count(name)) << name;
    // The poster's structure is what sg-build --preset poster makes of the same mesh.
    const fs::path poster = scratch / "poster.sg";
    const ToolRun build = run_tool(
        SG_BUILD_EXE, {model.string(), "-o", poster.string(), "--preset", "poster", "-q"}, scratch);
    ASSERT_EQ(build.exit_code, 0) << describe(build);
    const SplitGrid poster_grid = read_sg_file(poster).grid;
    for (const json& s : scene.at("structures")) {
        if (s.at("structure") != "splitgrid_poster") continue;
        EXPECT_EQ(s.at("references"), test::counted_references(poster_grid));
        EXPECT_EQ(s.at("structure_bytes"), poster_grid.memory_bytes());
    }
#ifdef SG_BENCH_HAS_EMBREE
    EXPECT_TRUE(structures.count("embree"));
#endif

    // Watertightness: our watertight variants never leak; two positions per variant.
    std::size_t accuracy_rows = 0;
    for (const json& a : j.at("accuracy")) {
        ++accuracy_rows;
        EXPECT_EQ(a.at("rays"), 3000);
        if (a.at("variant") == "watertight") {
            EXPECT_EQ(a.at("misses"), 0) << a.at("structure");
        }
    }
    EXPECT_EQ(accuracy_rows, 2 * (4 * 5 + (structures.count("embree") ? 2 : 0)));
    EXPECT_GT(j.at("sweep").at("points").size(), 10u);
    for (const json& p : j.at("sweep").at("points")) EXPECT_EQ(p.at("disagreements"), 0) << p;
    // The scale series: 300 (a patch of the model) and 3000 triangles per structure.
    std::set<std::size_t> sizes;
    for (const json& p : j.at("scale").at("points")) {
        sizes.insert(p.at("triangles").get<std::size_t>());
        if (p.at("structure") != "embree") {
            EXPECT_GE(p.at("peak_build_bytes_per_triangle").get<double>(),
                      p.at("structure_bytes_per_triangle").get<double>()) << p;
        }
    }
    EXPECT_EQ(sizes.size(), 2u);
    EXPECT_EQ(*sizes.begin(), 300u);

    // CSV: a header and one row per structure and workload.
    const std::string csv = read_text(out / "results.csv");
    EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')),
              1 + 4 * structures.size());
    EXPECT_EQ(csv.rfind("scene,triangles,structure,build_seconds_1t,build_seconds_2t,", 0), 0u);

    for (const char* chart : {"figure3.png", "speed_vs_accuracy.png", "sweep_build_vs_trace.png",
                              "memory_scaling.png"}) {
        ASSERT_TRUE(fs::exists(out / chart)) << chart << "\n" << run.err;
#ifdef SG_RENDER_EXE
        vtkNew<vtkPNGReader> reader;
        reader->SetFileName((out / chart).c_str());
        reader->Update();
        int dims[3];
        reader->GetOutput()->GetDimensions(dims);
        EXPECT_GT(dims[0], 300) << chart;
        EXPECT_GT(dims[1], 200) << chart;
#endif
    }
    // The table on stdout names every structure; nothing else goes there. stderr ends with
    // the list of the files written.
    for (const std::string& s : structures)
        EXPECT_NE(run.out.find("  " + s + " "), std::string::npos) << s;
    EXPECT_EQ(run.out.find("wrote"), std::string::npos) << run.out;
    EXPECT_EQ(run.out.find("info"), std::string::npos) << run.out;
    EXPECT_EQ(run.out.rfind("\nWuson (", 0), 0u) << run.out;
    const std::size_t list = run.err.find("s and wrote:\n");
    ASSERT_NE(list, std::string::npos) << run.err;
    for (const char* file : {"results.json", "results.csv", "figure3.png", "speed_vs_accuracy.png",
                             "sweep_build_vs_trace.png", "memory_scaling.png"})
        EXPECT_NE(run.err.find("info:   " + (out / file).string() + "\n", list), std::string::npos)
            << file << " not listed in\n" << run.err;
    // Every chart was made but the dynamic workload's, which this run does not measure.
    const std::size_t missing = run.err.find("info: no ");
    ASSERT_NE(missing, std::string::npos) << run.err;
    EXPECT_EQ(run.err.find("info: no dynamic.png: it needs the dynamic workload"), missing)
        << run.err;
    EXPECT_EQ(run.err.find("info: no ", missing + 1), std::string::npos) << run.err;

    // The report made from these results names files without the machine's folders.
    const fs::path report = scratch / "RESULTS.md";
    const std::string command = "/usr/bin/python3 " SG_SCRIPTS_DIR "/bench_report.py '" +
                                (out / "results.json").string() + "' '" + out.string() +
                                "' '' > '" + report.string() + "'";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    const std::string markdown = read_text(report);
    // (Debian's assimp-testmodels, where the model comes from, is named by the package.)
    EXPECT_NE(markdown.find("Source: assimp-testmodels: PLY/Wuson.ply."), std::string::npos)
        << markdown;
    EXPECT_EQ(markdown.find(model.parent_path().string()), std::string::npos) << markdown;
    EXPECT_EQ(markdown.find(scratch.path().string()), std::string::npos) << markdown;
    // Its peak build memory table gives the Split Grid's figure of the JSON, per triangle.
    const std::size_t memory = markdown.find("## Peak build memory");
    ASSERT_NE(memory, std::string::npos) << markdown;
    const std::size_t row = markdown.find("| Wuson (", memory);
    ASSERT_NE(row, std::string::npos) << markdown;
    double split_grid_peak = 0.0;
    for (const json& s : scene.at("structures"))
        if (s.at("structure") == "splitgrid") split_grid_peak = s.at("peak_build_bytes_per_triangle");
    std::ostringstream peak_text;
    peak_text.setf(std::ios::fixed);
    peak_text.precision(1);
    peak_text << "| " << split_grid_peak << " ";
    EXPECT_EQ(markdown.find(peak_text.str(), row), markdown.find(" | ", row) + 1)
        << peak_text.str() << " first after the scene in\n" << markdown.substr(row, 400);

#ifdef SG_BENCH_HAS_EMBREE
    // The build targets, from figures set here: the scene made large enough to count in the
    // medians, build times and peaks chosen so that every ratio is known.
    json big = j;
    json& big_scene = big.at("scenes")[0];
    big_scene["triangles"] = 200000;
    auto set_build = [&](const std::string& name, double one, double two, std::size_t peak) {
        for (json& s : big_scene.at("structures"))
            if (s.at("structure") == name) {
                s["build_seconds"] = {{"1", one}, {"2", two}};
                s["peak_build_bytes"] = peak;
            }
    };
    set_build("splitgrid", 3.8, 2.0, 300);
    set_build("bvh", 1.9, 1.0, 100);
    set_build("embree", 1.0, 0.5, 200);
    const fs::path big_json = scratch / "big.json";
    write_text(big_json, big.dump());
    const fs::path big_report = scratch / "BIG.md";
    const std::string big_command = "/usr/bin/python3 " SG_SCRIPTS_DIR "/bench_report.py '" +
                                    big_json.string() + "' '" + out.string() + "' '' > '" +
                                    big_report.string() + "'";
    ASSERT_EQ(std::system(big_command.c_str()), 0) << big_command;
    const std::string targets = read_text(big_report);
    for (const char* line :
         {"| Split Grid build speed / Embree MEDIUM | 0.18 | 0.25 |",
          "| Split Grid build speed / our BVH | 0.64 | 0.50 |",
          "| speed-up from 1 to 2 threads, every scene (range) | 1.65-1.99 | 1.90-1.90 |",
          "| peak build memory / Embree's peak | not measured | 1.50 |"})
        EXPECT_NE(targets.find(line), std::string::npos) << line << " in\n" << targets;
#endif
}

TEST(SgBench, ScenesGetUniqueNamesAndMissingChartsAreNamed)
{
    // Two scene files that share their name, one of them given twice; no sweep, no
    // watertightness workload and no scale series, so only figure3.png can be drawn.
    ScratchDir scratch;
    for (const char* folder : {"a", "b"}) {
        fs::create_directory(scratch / folder);
        fs::copy_file(assimp_model("PLY/Wuson.ply"), scratch / folder / "scene.ply");
    }
    const fs::path out = scratch / "bench";
    const std::string a = (scratch / "a" / "scene.ply").string();
    const std::string b = (scratch / "b" / "scene.ply").string();
    const ToolRun run = run_tool(
        SG_BENCH_EXE,
        {"--quick", "--width", "32", "--height", "24", "--incoherent-rays", "1000", "--threads",
         "1", "--structures", "splitgrid,bvh", "--no-sweep", "--watertight-rays", "0", "-o",
         out.string(), a, b, a},
        scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);

    const json j = json::parse(read_text(out / "results.json"));
    std::vector<std::string> names;
    for (const json& scene : j.at("scenes")) names.push_back(scene.at("scene"));
    EXPECT_EQ(names, (std::vector<std::string>{"a_scene", "b_scene", "a_scene_2"}));
    const std::string csv = read_text(out / "results.csv");
    for (const std::string& name : names)
        EXPECT_NE(csv.find("\n" + name + ","), std::string::npos) << name << " in\n" << csv;

    for (const char* missing : {"speed_vs_accuracy.png", "sweep_build_vs_trace.png",
                                "memory_scaling.png"}) {
        EXPECT_NE(run.err.find(std::string("info: no ") + missing + ": it needs "),
                  std::string::npos)
            << missing << " not explained in\n" << run.err;
        EXPECT_FALSE(fs::exists(out / missing)) << missing;
    }
    EXPECT_NE(run.err.find("--no-sweep"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("--scale-sizes"), std::string::npos) << run.err;
    ASSERT_TRUE(fs::exists(out / "figure3.png")) << run.err;
    // The list of files written is what the folder holds.
    const std::size_t list = run.err.find("s and wrote:\n");
    ASSERT_NE(list, std::string::npos) << run.err;
    std::vector<std::string> listed;
    std::istringstream lines(run.err.substr(list));
    std::string line;
    std::getline(lines, line);
    while (std::getline(lines, line))
        if (line.rfind("info:   ", 0) == 0) listed.push_back(fs::path(line.substr(8)).filename());
    std::sort(listed.begin(), listed.end());
    EXPECT_EQ(listed, folder_entries(out));
    EXPECT_EQ(run.out.find("wrote"), std::string::npos) << run.out;
}

TEST(SgBench, MortonOrderIsTheSameSceneUnderOtherIds)
{
    // --mesh-order morton renumbers the triangles of every scene: the same triangles, and
    // every structure's closest and any hits still those of brute force on the renumbered mesh.
    ScratchDir scratch;
    const fs::path model = assimp_model("PLY/Wuson.ply");
    const fs::path out = scratch / "bench";
    const ToolRun run = run_tool(
        SG_BENCH_EXE,
        {"--quick", "--width", "32", "--height", "24", "--incoherent-rays", "2000", "--threads",
         "1", "--structures", "splitgrid,bvh,kd_tree", "--no-sweep", "--watertight-rays", "0",
         "--mesh-order", "morton", "-o", out.string(), model.string()},
        scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    EXPECT_NE(run.err.find("put in morton order"), std::string::npos) << run.err;

    const json j = json::parse(read_text(out / "results.json"));
    EXPECT_EQ(j.at("plan").at("mesh_order"), "morton");
    const ImportedMesh imported = import_mesh(model);
    const json& scene = j.at("scenes").at(0);
    EXPECT_EQ(scene.at("triangles"), imported.mesh.triangles.size());
    EXPECT_EQ(scene.at("vertices"), imported.mesh.vertices.size());
    ASSERT_EQ(scene.at("structures").size(), 3u);
    for (const json& structure : scene.at("structures"))
        for (const json& workload : structure.at("workloads")) {
            EXPECT_GT(workload.at("oracle_rays").get<std::size_t>(), 0u);
            EXPECT_EQ(workload.at("oracle_disagreements"), 0)
                << structure.at("structure") << " " << workload.at("workload");
            EXPECT_EQ(workload.at("reference_disagreements"), 0)
                << structure.at("structure") << " " << workload.at("workload");
        }
}

TEST(SgBench, DynamicRunRebuildsOrRefitsEveryStructureOnEveryFrame)
{
    // Only dynamic scenes: the static part is left out, and every way of following the
    // moving mesh (rebuilds, refits) answers every frame's rays like the reference, our BVH
    // refitted (which tests/libsplitgrid/bvh_test.cpp checks against brute force).
    ScratchDir scratch;
    const fs::path model = assimp_model("PLY/Wuson.ply");
    const std::size_t model_triangles = import_mesh(model).mesh.triangles.size();
    const fs::path out = scratch / "bench";
    const ToolRun run = run_tool(
        SG_BENCH_EXE,
        {"--threads", "2", "--dynamic-frames", "3", "--dynamic-rays", "3000,500,3000",
         "--dynamic-every-frame",
         "--dynamic-triangles", std::to_string(2 * model_triangles + 1), "--dynamic-rigid",
         model.string(), "--dynamic-deform", model.string(), "-o", out.string()},
        scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const json j = json::parse(read_text(out / "results.json"));
    EXPECT_TRUE(j.at("scenes").empty());
    const json& dynamic = j.at("dynamic");
    ASSERT_EQ(dynamic.size(), 2u);
    std::vector<std::string> expected{"splitgrid", "splitgrid_poster", "uniform_grid", "kd_tree",
                                      "bvh"};
#ifdef SG_BENCH_HAS_EMBREE
    expected.push_back("embree");
#endif
    expected.push_back("bvh_refit");
#ifdef SG_BENCH_HAS_EMBREE
    expected.push_back("embree_low");
    expected.push_back("embree_refit");
#endif
    for (const json& d : dynamic) {
        const bool rigid = d.at("motion") == "rigid";
        // Rigid: the fewest whole copies of the model that reach --dynamic-triangles.
        EXPECT_EQ(d.at("triangles").get<std::size_t>(), (rigid ? 3 : 1) * model_triangles);
        EXPECT_EQ(d.at("frames"), 3);
        EXPECT_EQ(d.at("ray_budgets"), json::array({500, 3000}));
        for (std::size_t b = 0; b < 2; ++b) {
            const double rays = d.at("rays_per_frame")[b];
            EXPECT_GT(rays, 0.0);
            EXPECT_LE(rays, d.at("ray_budgets")[b].get<double>());
        }
        std::vector<std::string> names;
        for (const json& s : d.at("structures")) {
            names.push_back(s.at("structure"));
            EXPECT_EQ(s.at("frames_run"), json::array({0, 1, 2})) << names.back();
            EXPECT_EQ(s.at("update_seconds").size(), 3u);
            ASSERT_EQ(s.at("trace_seconds").size(), 2u);
            EXPECT_EQ(s.at("trace_seconds")[1].size(), 3u);
            // Ours agree exactly with the reference; Embree's different triangle test may
            // differ on a few rays in a million, and these are a few thousand.
            EXPECT_EQ(s.at("disagreements"), 0) << d.at("scene") << " " << names.back();
        }
        EXPECT_EQ(names, expected);
    }
    // The table names both scenes.
    EXPECT_NE(run.out.find("Wuson_rigid ("), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("Wuson_deform ("), std::string::npos) << run.out;
#ifdef SG_RENDER_EXE
    vtkNew<vtkPNGReader> png;
    ASSERT_TRUE(png->CanReadFile((out / "dynamic.png").c_str())) << run.err;
#endif
}

// The point workload of `scene` named by query and points, and its method `name` (nullptr
// where absent).
const json* point_workload(const json& scene, const std::string& query, const std::string& points)
{
    for (const json& w : scene.at("point_workloads"))
        if (w.at("query") == query && w.at("points") == points) return &w;
    return nullptr;
}
const json* point_method(const json& workload, const std::string& name)
{
    for (const json& m : workload.at("methods"))
        if (m.at("method") == name) return &m;
    return nullptr;
}

// Inside (1) or outside (0) of the convex closed mesh `mesh`; -1 within 1e-6 of a face's
// plane (too close to call here).
int convex_side_of(const Mesh& mesh, Vec3f p)
{
    const ConvexSide side = convex_side(mesh.view(), p);
    return side.nearest_plane < 1e-6 ? -1 : (side.inside ? 1 : 0);
}

TEST(SgBench, PointWorkloadsCheckEveryMethodAndSaveTheirPoints)
{
    // A closed convex mesh (an icosphere, written as OBJ): every structure of ours and CGAL
    // answer every point workload, checked against brute force before they are timed; the
    // points saved with --save-points are those measured, and the inside tests' answers in
    // their files are what an independent test here gives.
    ScratchDir scratch;
    const Mesh ball = icosphere(3, 1.0f);
    write_text(scratch / "ball.obj", obj_of(ball));
    const fs::path out = scratch / "bench";
    const fs::path points = scratch / "points";
    const ToolRun run = run_tool(
        SG_BENCH_EXE,
        {"--quick", "--width", "32", "--height", "24", "--incoherent-rays", "3000",
         "--count-rays", "2500", "--occupancy-points", "3000", "--closest-points", "600",
         "--inside-vertices", "20", "--threads", "1,2", "--no-sweep", "--watertight-rays", "0",
         "--save-points", points.string(), "-o", out.string(), (scratch / "ball.obj").string()},
        scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const json j = json::parse(read_text(out / "results.json"));
    EXPECT_EQ(j.at("plan").at("count_rays"), 2500);
    EXPECT_EQ(j.at("plan").at("occupancy_points"), 3000);
    EXPECT_EQ(j.at("plan").at("closest_points"), 600);
    EXPECT_EQ(j.at("plan").at("inside_vertices"), 20);
    const json& scene = j.at("scenes").at(0);
    EXPECT_EQ(scene.at("edges").at("open_edges"), 0);
    EXPECT_EQ(scene.at("edges").at("edges"), ball.vertices.size() + ball.triangles.size() - 2);
    EXPECT_TRUE(scene.at("edges").at("closed").get<bool>());

    const std::vector<std::pair<std::string, std::string>> workloads{
        {"count", "incoherent"}, {"occupancy", "random"}, {"occupancy", "near"},
        {"closest", "random"}, {"closest", "near"}};
    ASSERT_EQ(scene.at("point_workloads").size(), workloads.size());
    for (const auto& [query, set] : workloads) {
        const json* w = point_workload(scene, query, set);
        ASSERT_NE(w, nullptr) << query << " " << set;
        EXPECT_EQ(w->at("queries"), query == "count" ? 2500 : query == "occupancy" ? 3000 : 600);
        EXPECT_GT(w->at("oracle_queries").get<std::size_t>(), 10u) << query << " " << set;
        for (const char* name :
             {"splitgrid", "splitgrid_poster", "uniform_grid", "kd_tree", "bvh"}) {
            const json* m = point_method(*w, name);
            ASSERT_NE(m, nullptr) << name;
            EXPECT_EQ(m->at("status"), "ok") << name << " " << query << " " << set;
            EXPECT_EQ(m->at("oracle_disagreements"), 0) << name << " " << query << " " << set;
            EXPECT_EQ(m->at("reference_disagreements"), 0) << name << " " << query << " " << set;
            EXPECT_GT(m->at("queries_per_s").at("1").get<double>(), 0.0);
            EXPECT_GT(m->at("queries_per_s").at("2").get<double>(), 0.0);
        }
        const json* embree = point_method(*w, "embree");
#ifdef SG_BENCH_HAS_EMBREE
        ASSERT_NE(embree, nullptr);
        EXPECT_EQ(embree->at("status").get<std::string>().rfind("n/a: ", 0), 0u);
        EXPECT_TRUE(embree->at("queries_per_s").empty());
#else
        EXPECT_EQ(embree, nullptr);
#endif
        const json* cgal = point_method(*w, "cgal");
#ifdef SG_BENCH_HAS_CGAL
        ASSERT_NE(cgal, nullptr);
        if (query == "count") {
            EXPECT_EQ(cgal->at("status").get<std::string>().rfind("n/a: ", 0), 0u);
        } else {
            EXPECT_EQ(cgal->at("status"), "ok") << query << " " << set;
            EXPECT_EQ(cgal->at("oracle_disagreements"), 0) << query << " " << set;
            EXPECT_GT(cgal->at("queries_per_s").at("2").get<double>(), 0.0);
        }
#else
        EXPECT_EQ(cgal, nullptr);
#endif
    }
#ifdef SG_BENCH_HAS_CGAL
    EXPECT_TRUE(scene.at("cgal").at("built").get<bool>());
    EXPECT_EQ(scene.at("cgal").at("refused_faces"), 0);
    EXPECT_TRUE(scene.at("cgal").at("closed").get<bool>());
    EXPECT_FALSE(j.at("cgal_version").get<std::string>().empty());
#endif

    // The saved scene is the mesh measured; the saved points are the workloads'.
    const SgContents saved = read_sg_file(points / "ball.sg");
    EXPECT_EQ(saved.mesh.triangles.size(), ball.triangles.size());
    const std::vector<Vec3f> random = read_point_file(points / "ball.random.points");
    const std::vector<Vec3f> near = read_point_file(points / "ball.near.points");
    ASSERT_EQ(random.size(), 3000u);
    ASSERT_EQ(near.size(), 3000u);
    // The fraction of random points inside is the one the planes of the faces give.
    std::size_t inside = 0, decided = 0;
    for (const Vec3f p : random) {
        const int side = convex_side_of(ball, p);
        inside += side == 1 ? 1 : 0;
        decided += side >= 0 ? 1 : 0;
    }
    EXPECT_NEAR(point_workload(scene, "occupancy", "random")->at("mean_answer").get<double>(),
                double(inside) / 3000.0, double(3000 - decided + 1) / 3000.0);
    // Near points lie within 1e-3 of the diagonal of the surface, on either side.
    const Aabb box = bounds(ball.view());
    const double diagonal = std::sqrt(3.0) * box.extent(0);
    const double mean_distance = point_workload(scene, "closest", "near")->at("mean_answer");
    EXPECT_GT(mean_distance, 0.0);
    EXPECT_LT(mean_distance, 1e-3 * diagonal);
    std::size_t near_inside = 0;
    for (const Vec3f p : near) near_inside += convex_side_of(ball, p) == 1 ? 1 : 0;
    EXPECT_GT(near_inside, 1000u);
    EXPECT_LT(near_inside, 2000u);

    // The inside tests: their files hold what the oracle says, which the test recomputes for
    // the cube (inside iff strictly within [0, 8]^3) and the icosphere (the faces' planes).
    std::vector<std::string> sets;
    for (const json& t : j.at("inside_tests")) {
        const std::string name = t.at("set");
        sets.push_back(name);
        const std::vector<Vec3f> p = read_point_file(points / (name + ".points"));
        const std::vector<float> expected = read_occupancy_file(points / (name + ".expected"));
        ASSERT_EQ(p.size(), t.at("points").get<std::size_t>()) << name;
        ASSERT_EQ(expected.size(), p.size()) << name;
        EXPECT_EQ(std::count(expected.begin(), expected.end(), 1.0f), t.at("inside").get<long>())
            << name;
        EXPECT_EQ(std::count_if(expected.begin(), expected.end(),
                                [](float e) { return std::isnan(e); }),
                  t.at("undecided").get<long>())
            << name;
        const std::string shape = t.at("scene");
        const Mesh cube = tessellated_cube(8);
        for (std::size_t k = 0; k < p.size(); ++k) {
            if (std::isnan(expected[k])) continue;
            int truth = -1;
            if (shape == "tessellated_cube") {
                const auto in = [](float c) { return c > 0.0f && c < 8.0f; };
                truth = in(p[k].x) && in(p[k].y) && in(p[k].z) ? 1 : 0;
            } else {
                truth = convex_side_of(shape == "icosphere" ? icosphere(2, 1.0f) : ball, p[k]);
            }
            if (truth >= 0) {
                EXPECT_EQ(expected[k], float(truth)) << name << " point " << k;
            }
        }
        EXPECT_TRUE(fs::exists(points / (shape + ".sg"))) << shape;
        // Split Grid's exact parity is right everywhere; the rule without the tie-break
        // counts a ray through an edge or a vertex once per triangle there, so on the points
        // whose rays are aimed at the cube's edges and vertices it is wrong.
        for (const json& m : t.at("methods")) {
            if (m.at("method") == "splitgrid" || m.at("method") == "cgal") {
                EXPECT_EQ(m.at("status"), "ok") << name << " " << m;
                EXPECT_EQ(m.at("wrong"), 0) << name << " " << m;
            }
            if (m.at("method") == "splitgrid_no_tie_break" && name == "cube_aimed") {
                EXPECT_GT(m.at("wrong").get<std::size_t>(), t.at("points").get<std::size_t>() / 2);
            }
            EXPECT_GT(m.at("points_per_s").get<double>(), 0.0) << name << " " << m;
        }
    }
    EXPECT_EQ(sets, (std::vector<std::string>{"cube_grid", "cube_aimed", "icosphere_grid",
                                              "icosphere_aimed", "ball_near_vertices"}));
    for (const char* chart : {"point_workloads.png", "inside_tests.png"})
        EXPECT_TRUE(fs::exists(out / chart)) << chart << "\n" << run.err;
    EXPECT_NE(run.out.find("ball: point and multi-hit workloads (closed mesh"), std::string::npos)
        << run.out;
    EXPECT_NE(run.out.find("\ninside tests: "), std::string::npos) << run.out;
}

TEST(SgBench, CgalAnswersWhatItCanAndSaysWhyNot)
{
#ifndef SG_BENCH_HAS_CGAL
    GTEST_SKIP() << "this sg-bench has no CGAL (SG_WITH_CGAL off)";
#else
    // An open box (a tessellated cube without its top): no occupancy for anyone, closest
    // points for all. Two tetrahedra that share an edge: closed (every edge in an even number
    // of triangles), so our parity answers, but the shared edge is non-manifold and
    // Surface_mesh refuses the faces that would make it so: CGAL answers nothing there, and
    // says why.
    ScratchDir scratch;
    Mesh box = tessellated_cube(2);
    std::erase_if(box.triangles, [&](const Triangle& t) {
        return box.vertices[t.v[0]].y == 2.0f && box.vertices[t.v[1]].y == 2.0f &&
               box.vertices[t.v[2]].y == 2.0f;
    });
    ASSERT_EQ(box.triangles.size(), 40u);
    write_text(scratch / "box.obj", obj_of(box));
    Mesh pair;
    pair.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}, {1, -1, 0}};
    // Outward-wound tetrahedra (0,1,2,3) and (0,1,5,4), both on the edge 0-1.
    pair.triangles = {Triangle{{0, 2, 1}}, Triangle{{0, 1, 3}}, Triangle{{1, 2, 3}},
                      Triangle{{0, 3, 2}}, Triangle{{0, 1, 4}}, Triangle{{1, 5, 4}},
                      Triangle{{0, 4, 5}}, Triangle{{0, 5, 1}}};
    write_text(scratch / "pair.obj", obj_of(pair));
    const fs::path out = scratch / "bench";
    const ToolRun run = run_tool(
        SG_BENCH_EXE,
        {"--quick", "--width", "16", "--height", "12", "--incoherent-rays", "500", "--threads",
         "1", "--structures", "splitgrid", "--no-sweep", "--watertight-rays", "0",
         "--inside-vertices", "0", "--occupancy-points", "500", "--closest-points", "200", "-o",
         out.string(), (scratch / "box.obj").string(), (scratch / "pair.obj").string()},
        scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const json j = json::parse(read_text(out / "results.json"));
    EXPECT_TRUE(j.at("inside_tests").empty());
    const json& open = j.at("scenes").at(0);
    EXPECT_EQ(open.at("edges").at("open_edges"), 8);  // the rim: 4 edges of length 1 a side
    EXPECT_EQ(open.at("cgal").at("refused_faces"), 0);
    EXPECT_FALSE(open.at("cgal").at("closed").get<bool>());
    for (const char* set : {"random", "near"}) {
        for (const char* name : {"splitgrid", "cgal"}) {
            const json* occupancy = point_method(*point_workload(open, "occupancy", set), name);
            ASSERT_NE(occupancy, nullptr);
            const std::string status = occupancy->at("status");
            EXPECT_EQ(status.rfind("n/a: mesh not closed", 0), 0u) << status;
            const json* closest = point_method(*point_workload(open, "closest", set), name);
            EXPECT_EQ(closest->at("status"), "ok") << *closest;
            EXPECT_EQ(closest->at("oracle_disagreements"), 0) << *closest;
        }
    }
    const json& tetrahedra = j.at("scenes").at(1);
    EXPECT_TRUE(tetrahedra.at("edges").at("closed").get<bool>());
    EXPECT_EQ(tetrahedra.at("edges").at("nonmanifold_edges"), 1);
    EXPECT_GT(tetrahedra.at("cgal").at("refused_faces").get<std::size_t>(), 0u);
    for (const char* query : {"occupancy", "closest"}) {
        const json* w = point_workload(tetrahedra, query, "random");
        EXPECT_EQ(point_method(*w, "splitgrid")->at("status"), "ok") << *w;
        EXPECT_EQ(point_method(*w, "splitgrid")->at("oracle_disagreements"), 0) << *w;
        const std::string cgal = point_method(*w, "cgal")->at("status");
        EXPECT_NE(cgal.find("faces refused by Surface_mesh (non-manifold"), std::string::npos)
            << cgal;
    }
    EXPECT_GT(point_workload(tetrahedra, "occupancy", "random")->at("mean_answer").get<double>(),
              0.0);
#endif
}

TEST(SgBench, BadFlagsAreUsageErrorsAndLeaveNothing)
{
    ScratchDir scratch;
    const fs::path model = assimp_model("PLY/Wuson.ply");
    const fs::path out = scratch / "bench";
    const std::vector<std::vector<std::string>> cases = {
        {"--structures", "splitgrid,octree", model.string(), "-o", out.string()},
        {"--threads", "0", model.string(), "-o", out.string()},
        {"--scale-sizes", "1e3,lots", model.string(), "-o", out.string()},
        {"-o", out.string()},
        {"--leaf-size", "0", model.string(), "-o", out.string()},
        {"--mesh-order", "zorder", model.string(), "-o", out.string()},
        {"--dynamic-structures", "bvh,octree", "--dynamic-deform", model.string(), "-o",
         out.string()},
        {"--dynamic-rays", "1e4,0", "--dynamic-deform", model.string(), "-o", out.string()},
        {"--dynamic-frames", "0", "--dynamic-deform", model.string(), "-o", out.string()},
        {"--dynamic-structures", "bvh,bvh", "--dynamic-deform", model.string(), "-o",
         out.string()},
        {"--occupancy-points", "-5", model.string(), "-o", out.string()},
        {"--inside-vertices", "many", model.string(), "-o", out.string()},
    };
    for (const auto& args : cases) {
        const ToolRun run = run_tool(SG_BENCH_EXE, args, scratch);
        EXPECT_EQ(run.exit_code, 1) << describe(run);
        EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
        EXPECT_EQ(run.err.rfind("error: ", 0), 0u) << run.err;
        EXPECT_FALSE(fs::exists(out));
    }
}

TEST(SgBench, BadInputIsExitTwoAndLeavesNothing)
{
    ScratchDir scratch;
    write_text(scratch / "garbage.obj", "this is not a mesh\n");
    const fs::path out = scratch / "bench";
    const fs::path missing_parent = scratch / "no" / "bench";
    struct Case {
        std::vector<std::string> args;
        std::string named;  // the file the one error line starts with
    };
    const std::vector<Case> cases = {
        {{(scratch / "missing.ply").string(), "-o", out.string()}, (scratch / "missing.ply").string()},
        {{(scratch / "garbage.obj").string(), "-o", out.string()}, (scratch / "garbage.obj").string()},
        {{assimp_model("PLY/Wuson.ply").string(), "-o", missing_parent.string()},
         missing_parent.string()},
        {{assimp_model("PLY/Wuson.ply").string(), "-o", out.string(), "--save-points",
          missing_parent.string()},
         missing_parent.string()},
    };
    for (const Case& c : cases) {
        const ToolRun run = run_tool(SG_BENCH_EXE, c.args, scratch);
        EXPECT_EQ(run.exit_code, 2) << describe(run);
        EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
        EXPECT_EQ(run.err.rfind("error: " + c.named + ": ", 0), 0u) << run.err;
        EXPECT_FALSE(fs::exists(out));
        EXPECT_FALSE(fs::exists(scratch / "no"));
    }
}

TEST(SgBench, HelpExplainsWorkloadsOutputsAndExitCodes)
{
    ScratchDir scratch;
    const ToolRun run = run_tool(SG_BENCH_EXE, {"--help"}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    for (const char* text : {"--quick", "--out", "--structures", "--threads", "--scale-sizes",
                             "--arena-sizes", "primary", "path", "incoherent", "shadow",
                             "results.json", "results.csv", "--leaf-size", "Exit codes:",
                             "--dynamic-rigid", "--dynamic-deform", "--dynamic-rays",
                             "dynamic.png", "--count-rays", "--occupancy-points",
                             "--closest-points", "--inside-vertices", "--save-points",
                             "point_workloads.png", "inside_tests.png", "CGAL"})
        EXPECT_NE(run.out.find(text), std::string::npos) << text << " missing";
}

}  // namespace
}  // namespace sg::test
