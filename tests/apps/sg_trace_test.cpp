// End-to-end tests of sg-trace: hits read back from its output against brute force over the
// mesh stored in the .sg file, for 1 and 2 threads, closest and any hit; bad inputs.

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "app_test_support.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/formats/ray_file.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/traverse.hpp"
#include "support/random_scene.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// A ray set mixing the cases traversal gets wrong first: rays aimed at triangles (mostly
/// hits), random rays (many misses), axis-parallel rays (zero direction components), and
/// [t_min, t_max] windows that end exactly at, or start just past, the first hit.
std::vector<Ray> make_rays(const MeshView& mesh, std::uint32_t seed)
{
    Aabb box = bounds(mesh);
    // Start rays from a box somewhat larger than the scene so some origins are outside.
    const Vec3f pad = (box.upper - box.lower) * 0.25f;
    box.lower = box.lower - pad;
    box.upper = box.upper + pad;

    std::vector<Ray> rays = rays_at_triangles(seed, 2000, box, mesh);
    const std::vector<Ray> random = random_rays(seed + 1, 1000, box);
    rays.insert(rays.end(), random.begin(), random.end());

    std::mt19937 rng(seed + 2);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int i = 0; i < 600; ++i) {
        Ray ray;
        const Vec3f centre = (box.lower + box.upper) * 0.5f;
        const Vec3f half = (box.upper - box.lower) * 0.3f;
        ray.origin = {centre.x + half.x * (2 * unit(rng) - 1), centre.y + half.y * (2 * unit(rng) - 1),
                      centre.z + half.z * (2 * unit(rng) - 1)};
        const int axis = i % 3;
        ray.direction[axis] = (i / 3) % 2 == 0 ? 1.0f : -1.0f;
        rays.push_back(ray);
    }
    // Windows around the true first hit of some of the aimed rays.
    for (std::size_t i = 0; i < 400; ++i) {
        Ray ray = rays[i];
        const Hit first = intersect_brute_force(mesh, ray);
        if (!first.is_hit()) continue;
        if (i % 2 == 0) {
            ray.t_max = first.t;  // closed interval: the hit at t_max counts
        } else {
            ray.t_min = first.t * 1.0001f + 1e-6f;  // starts past the first hit
        }
        rays.push_back(ray);
    }
    return rays;
}

/// Compares sg-trace's closest hits with brute force; returns a description of the first
/// few disagreements (empty if none) and counts hits in `hit_count`.
std::string compare_closest(const MeshView& mesh, const std::vector<Ray>& rays,
                            const std::vector<Hit>& hits, std::size_t& hit_count)
{
    std::ostringstream report;
    std::size_t mismatches = 0;
    hit_count = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit expected = intersect_brute_force(mesh, rays[i]);
        const Hit& got = hits[i];
        bool ok = expected.is_hit() == got.is_hit();
        if (ok && expected.is_hit()) {
            ++hit_count;
            // The same triangle, or a tie: another triangle at the same distance. Either way
            // the distance must be equal, since both use the same watertight test.
            ok = expected.t == got.t;
        }
        if (!ok && ++mismatches <= 5)
            report << "ray " << i << ": expected triangle " << expected.triangle << " t "
                   << expected.t << ", got triangle " << got.triangle << " t " << got.t << "\n";
    }
    if (mismatches != 0) report << mismatches << " of " << rays.size() << " rays disagree\n";
    return report.str();
}

class SgTrace : public ::testing::Test {
protected:
    /// Traces `rays` through `sg_file` with sg-trace and returns the hits read back.
    std::vector<Hit> trace(const fs::path& sg_file, const std::vector<Ray>& rays,
                           const std::vector<std::string>& extra, const std::string& tag)
    {
        const fs::path ray_file = scratch_ / (tag + ".rays");
        const fs::path hit_file = scratch_ / (tag + ".hits");
        write_ray_file(ray_file, rays);
        std::vector<std::string> args = {sg_file.string(), "--rays", ray_file.string(), "--out",
                                         hit_file.string()};
        args.insert(args.end(), extra.begin(), extra.end());
        last_run_ = run_tool(SG_TRACE_EXE, args, scratch_);
        EXPECT_EQ(last_run_.exit_code, 0) << describe(last_run_);
        if (last_run_.exit_code != 0) return {};
        return read_hit_file(hit_file);
    }

    void check_closest_and_any_hit(const fs::path& sg_file)
    {
        const SgContents contents = read_sg_file(sg_file);
        const MeshView mesh = contents.mesh.view();
        const std::vector<Ray> rays = make_rays(mesh, 11);

        const std::vector<Hit> one = trace(sg_file, rays, {"--threads", "1"}, "one");
        const std::vector<Hit> two = trace(sg_file, rays, {"--threads", "2", "--json"}, "two");
        ASSERT_EQ(one.size(), rays.size());
        ASSERT_EQ(two.size(), rays.size());
        EXPECT_EQ(read_text(scratch_ / "one.hits"), read_text(scratch_ / "two.hits"))
            << "the hit file must not depend on the thread count";

        std::size_t hit_count = 0;
        EXPECT_EQ(compare_closest(mesh, rays, one, hit_count), "");
        // Premise: the ray set exercises both outcomes substantially.
        EXPECT_GT(hit_count, rays.size() / 4);
        EXPECT_LT(hit_count, rays.size());

        const json j = json::parse(last_run_.out);
        EXPECT_EQ(j.at("ray_count"), rays.size());
        EXPECT_EQ(j.at("hit_count"), hit_count);
        EXPECT_EQ(j.at("threads"), 2);
        EXPECT_EQ(j.at("mode"), "closest_hit");

        for (const char* threads : {"1", "2"}) {
            const std::vector<Hit> any =
                trace(sg_file, rays, {"--any-hit", "--threads", threads}, "any");
            ASSERT_EQ(any.size(), rays.size());
            std::size_t mismatches = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) {
                const bool expected = occluded_brute_force(mesh, rays[i]);
                const Hit& got = any[i];
                const bool record_ok = (got.triangle == 0 || got.triangle == invalid_triangle) &&
                                       got.t == 0.0f && got.u == 0.0f && got.v == 0.0f;
                if (!record_ok || expected != (got.triangle == 0)) ++mismatches;
            }
            EXPECT_EQ(mismatches, 0u) << "any-hit disagreements with " << threads << " threads";
        }
    }

    ScratchDir scratch_;
    ToolRun last_run_;
};

TEST_F(SgTrace, RealModelBuiltBySgBuildMatchesBruteForce)
{
    const fs::path model = assimp_model("Collada/duck.dae");
    ASSERT_TRUE(fs::exists(model)) << model << ": install assimp-testmodels";
    const fs::path sg_file = scratch_ / "duck.sg";
    const ToolRun build = run_tool(SG_BUILD_EXE, {model.string(), "-o", sg_file.string()}, scratch_);
    ASSERT_EQ(build.exit_code, 0) << describe(build);
    check_closest_and_any_hit(sg_file);
}

TEST_F(SgTrace, RandomSceneWithPlanesMatchesBruteForce)
{
    // Written by the library, with small leaves and a plane lying exactly on y = 0 and one
    // on x = 4, so that axis-parallel rays run inside planes and along cell boundaries.
    Mesh mesh = random_triangles(3, 2000, Aabb{{0, 0, 0}, {8, 8, 8}}, 1.0f);
    append(mesh, axis_plane(1, 0.0f, 8));
    append(mesh, axis_plane(0, 4.0f, 8));
    BuildConfig config;
    config.leaf_size = 2;
    SgContents contents;
    contents.grid = build_split_grid(mesh.view(), config);
    contents.mesh = std::move(mesh);
    contents.source_name = "random";
    const fs::path sg_file = scratch_ / "random.sg";
    write_sg_file(sg_file, contents);
    check_closest_and_any_hit(sg_file);
}

// SG_ISA chooses the kernels sg-trace runs, and its --json names them ("isa"); a name of no
// instruction set gets a one-line warning on stderr and the best kernels. Every instruction
// set writes the same hit file, byte for byte, and brute force agrees with it.
TEST_F(SgTrace, InstructionSetIsNamedAndAnUnknownOneIsReported)
{
    const Mesh mesh = random_triangles(5, 1500, Aabb{{0, 0, 0}, {8, 8, 8}}, 1.0f);
    SgContents contents;
    contents.grid = build_split_grid(mesh.view(), BuildConfig{});
    contents.mesh = mesh;
    contents.source_name = "random";
    const fs::path sg_file = scratch_ / "random.sg";
    write_sg_file(sg_file, contents);
    const std::vector<Ray> rays = make_rays(mesh.view(), 21);
    const fs::path ray_file = scratch_ / "isa.rays";
    write_ray_file(ray_file, rays);
    const auto run = [&](const std::string& isa, const std::string& tag) {
        return run_tool(SG_TRACE_EXE,
                        {sg_file.string(), "--rays", ray_file.string(), "--out",
                         (scratch_ / (tag + ".hits")).string(), "--json"},
                        scratch_, {}, {"SG_ISA=" + isa});
    };
    const ToolRun best = run("", "best");
    ASSERT_EQ(best.exit_code, 0) << describe(best);
    EXPECT_EQ(best.err, "");
    const std::string best_isa = json::parse(best.out).at("isa");

    const ToolRun scalar = run("scalar", "scalar");
    ASSERT_EQ(scalar.exit_code, 0) << describe(scalar);
    EXPECT_EQ(scalar.err, "");
    EXPECT_EQ(json::parse(scalar.out).at("isa"), "scalar");
    std::size_t hit_count = 0;
    EXPECT_EQ(compare_closest(mesh.view(), rays, read_hit_file(scratch_ / "scalar.hits"),
                              hit_count),
              "");
    EXPECT_GT(hit_count, rays.size() / 4);
    EXPECT_EQ(read_text(scratch_ / "scalar.hits"), read_text(scratch_ / "best.hits"))
        << "scalar and " << best_isa << " kernels wrote different hit files";

    const ToolRun unknown = run("avx2x", "unknown");
    ASSERT_EQ(unknown.exit_code, 0) << describe(unknown);
    EXPECT_NE(unknown.err.find("SG_ISA=avx2x is not one of scalar, sse2, avx2, avx512; using " +
                               best_isa),
              std::string::npos)
        << unknown.err;
    EXPECT_EQ(std::count(unknown.err.begin(), unknown.err.end(), '\n'), 1) << unknown.err;
    EXPECT_EQ(json::parse(unknown.out).at("isa"), best_isa);
}

TEST_F(SgTrace, EmptyRaySetGivesEmptyHitFile)
{
    const fs::path model = assimp_model("OFF/Cube.off");
    ASSERT_TRUE(fs::exists(model));
    const fs::path sg_file = scratch_ / "cube.sg";
    ASSERT_EQ(run_tool(SG_BUILD_EXE, {model.string(), "-o", sg_file.string()}, scratch_).exit_code, 0);
    EXPECT_TRUE(trace(sg_file, {}, {}, "empty").empty());
    EXPECT_TRUE(fs::exists(scratch_ / "empty.hits"));
    EXPECT_NE(last_run_.out.find("rays/s"), std::string::npos) << last_run_.out;
}

// --- bad inputs: exit code 2, a message naming the file, and no hit file ---

class SgTraceBadInput : public ::testing::Test {
protected:
    void SetUp() override
    {
        const fs::path model = assimp_model("OFF/Cube.off");
        ASSERT_TRUE(fs::exists(model));
        ASSERT_EQ(run_tool(SG_BUILD_EXE, {model.string(), "-o", sg_file_.string()}, scratch_)
                      .exit_code,
                  0);
        Ray ray;
        ray.origin = {0.1f, 0.2f, -5.0f};
        ray.direction = {0.0f, 0.0f, 1.0f};
        write_ray_file(good_rays_, std::vector<Ray>(10, ray));
    }

    void expect_refused(const fs::path& sg_file, const fs::path& ray_file, const std::string& named)
    {
        const ToolRun run = run_tool(SG_TRACE_EXE,
                                     {sg_file.string(), "--rays", ray_file.string(), "--out",
                                      hits_.string()},
                                     scratch_);
        EXPECT_EQ(run.exit_code, 2) << describe(run);
        EXPECT_NE(run.err.find(named), std::string::npos) << "stderr must name " << named << ":\n"
                                                          << run.err;
        EXPECT_FALSE(fs::exists(hits_));
    }

    ScratchDir scratch_;
    fs::path sg_file_ = scratch_ / "cube.sg";
    fs::path good_rays_ = scratch_ / "good.rays";
    fs::path hits_ = scratch_ / "out.hits";
};

TEST_F(SgTraceBadInput, GoodInputsWork)
{
    // Control for the cases below: the same command with good files succeeds.
    const ToolRun run = run_tool(
        SG_TRACE_EXE, {sg_file_.string(), "--rays", good_rays_.string(), "--out", hits_.string()},
        scratch_);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const std::vector<Hit> hits = read_hit_file(hits_);
    ASSERT_EQ(hits.size(), 10u);
    EXPECT_TRUE(hits[0].is_hit()) << "a ray through the cube's centre region hits it";
}

TEST_F(SgTraceBadInput, RayFileWithBadMagic)
{
    std::string bytes = read_text(good_rays_);
    bytes[3] = 'X';
    write_text(scratch_ / "magic.rays", bytes);
    expect_refused(sg_file_, scratch_ / "magic.rays", "magic.rays");
}

TEST_F(SgTraceBadInput, TruncatedRayFile)
{
    const std::string bytes = read_text(good_rays_);
    write_text(scratch_ / "short.rays", bytes.substr(0, bytes.size() - 5));
    expect_refused(sg_file_, scratch_ / "short.rays", "short.rays");
}

TEST_F(SgTraceBadInput, RayFileCountLargerThanFile)
{
    std::string bytes = read_text(good_rays_);
    bytes[8] = static_cast<char>(0xFF);  // low byte of the uint64 count: 255 rays claimed
    write_text(scratch_ / "count.rays", bytes);
    expect_refused(sg_file_, scratch_ / "count.rays", "count.rays");
}

TEST_F(SgTraceBadInput, EmptyRayFile)
{
    write_text(scratch_ / "empty.rays", "");
    expect_refused(sg_file_, scratch_ / "empty.rays", "empty.rays");
}

TEST_F(SgTraceBadInput, MissingRayFile)
{
    expect_refused(sg_file_, scratch_ / "missing.rays", "missing.rays");
}

TEST_F(SgTraceBadInput, MissingSgFile)
{
    expect_refused(scratch_ / "missing.sg", good_rays_, "missing.sg");
}

TEST_F(SgTraceBadInput, TruncatedSgFile)
{
    const std::string bytes = read_text(sg_file_);
    write_text(scratch_ / "half.sg", bytes.substr(0, bytes.size() / 2));
    expect_refused(scratch_ / "half.sg", good_rays_, "half.sg");
}

TEST_F(SgTraceBadInput, MeshInsteadOfSgFile)
{
    expect_refused(assimp_model("OFF/Cube.off"), good_rays_, "Cube.off");
}

// --- invalid rays: counted, warned about and written as misses; --strict refuses them ---

class SgTraceInvalidRays : public SgTraceBadInput {
protected:
    void SetUp() override
    {
        SgTraceBadInput::SetUp();
        // Ten good rays at even positions, ten invalid ones of every kind at odd positions.
        std::vector<Ray> bad = invalid_rays();
        const float inf = std::numeric_limits<float>::infinity();
        bad.push_back(Ray{{0, 0, 0}, {inf, 0, 0}, 0, inf});
        bad.push_back(Ray{{0, 0, 0}, {0, 0, 0}, 1, 2});
        ASSERT_EQ(bad.size(), 10u);
        Ray good;
        good.origin = {0.1f, 0.2f, -5.0f};
        good.direction = {0.0f, 0.0f, 1.0f};
        for (std::size_t i = 0; i < 20; ++i) rays_.push_back(i % 2 == 0 ? good : bad[i / 2]);
        write_ray_file(mixed_, rays_);
    }

    ToolRun trace_mixed(std::vector<std::string> extra)
    {
        std::vector<std::string> args = {sg_file_.string(), "--rays", mixed_.string(), "--out",
                                         hits_.string()};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_tool(SG_TRACE_EXE, args, scratch_);
    }

    std::vector<Ray> rays_;
    fs::path mixed_ = scratch_ / "mixed.rays";
};

TEST_F(SgTraceInvalidRays, AreCountedWarnedAboutAndWrittenAsMisses)
{
    const ToolRun run = trace_mixed({});
    ASSERT_EQ(run.exit_code, 0) << describe(run) << "\nthe file is well formed: not exit 2";
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_EQ(run.err.rfind("warning: " + mixed_.string() + ": 10 of 20 rays are invalid (NaN",
                            0),
              0u)
        << run.err;
    EXPECT_NE(run.err.find("the first is ray 1"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("written as misses"), std::string::npos) << run.err;
    EXPECT_NE(run.out.find("10 hits (50.0%), 10 invalid rays"), std::string::npos) << run.out;

    const std::vector<Hit> hits = read_hit_file(hits_);
    ASSERT_EQ(hits.size(), rays_.size());
    for (std::size_t i = 0; i < hits.size(); ++i) {
        SCOPED_TRACE(i);
        if (i % 2 == 0) {
            EXPECT_TRUE(hits[i].is_hit());
            continue;
        }
        // A miss as docs/FORMAT.md describes it: no triangle, t = the ray's t_max bit for
        // bit (NaN included), u = v = 0.
        EXPECT_EQ(hits[i].triangle, invalid_triangle);
        EXPECT_EQ(std::bit_cast<std::uint32_t>(hits[i].t),
                  std::bit_cast<std::uint32_t>(rays_[i].t_max));
        EXPECT_EQ(hits[i].u, 0.0f);
        EXPECT_EQ(hits[i].v, 0.0f);
    }

    const ToolRun json_run = trace_mixed({"--json"});
    ASSERT_EQ(json_run.exit_code, 0) << describe(json_run);
    const json j = json::parse(json_run.out);
    EXPECT_EQ(j.at("invalid_rays"), 10);
    EXPECT_EQ(j.at("hit_count"), 10);
    EXPECT_EQ(j.at("ray_count"), 20);

    const ToolRun any = trace_mixed({"--any-hit"});
    ASSERT_EQ(any.exit_code, 0) << describe(any);
    const std::vector<Hit> occluded = read_hit_file(hits_);
    for (std::size_t i = 0; i < occluded.size(); ++i) {
        EXPECT_EQ(occluded[i].triangle, i % 2 == 0 ? 0u : invalid_triangle) << i;
        EXPECT_EQ(occluded[i].t, 0.0f) << i;
    }
}

TEST_F(SgTraceInvalidRays, StrictRefusesTheFileAndWritesNothing)
{
    const ToolRun run = trace_mixed({"--strict"});
    EXPECT_EQ(run.exit_code, 2) << describe(run);
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_EQ(run.err.rfind("error: " + mixed_.string() + ": 10 of 20 rays are invalid", 0), 0u)
        << run.err;
    EXPECT_NE(run.err.find("--strict"), std::string::npos) << run.err;
    EXPECT_EQ(run.out, "");
    EXPECT_FALSE(fs::exists(hits_));
    for (const auto& entry : fs::directory_iterator(scratch_.path()))
        EXPECT_NE(entry.path().extension(), ".tmp") << "temporary file left behind";
}

TEST_F(SgTraceInvalidRays, CleanFileGivesNoWarningEvenWithStrict)
{
    const ToolRun run = run_tool(SG_TRACE_EXE,
                                 {sg_file_.string(), "--rays", good_rays_.string(), "--out",
                                  hits_.string(), "--strict", "--json"},
                                 scratch_);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    EXPECT_EQ(run.err, "");
    EXPECT_EQ(json::parse(run.out).at("invalid_rays"), 0);
}

}  // namespace
}  // namespace sg::test
