// End-to-end tests of vertex welding: a binary STL soup written here goes through sg-build;
// its summary, its JSON and sg-stats report the vertex counts the test computes from the
// soup itself, the .sg file read back holds every corner bit for bit, and sg-trace gives
// byte-identical hit files for the welded file and for an unwelded one the test writes.

#include <array>
#include <bit>
#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "splitgrid/formats/ray_file.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "support/random_scene.hpp"
#include "support/triangle_soup.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class SgBuildWelding : public ::testing::Test {
protected:
    void SetUp() override
    {
        // The duck's Collada file has normals and texture coordinates; its soup has three
        // corners per triangle, each STL face with its own normal.
        const fs::path model = assimp_model("Collada/duck.dae");
        ASSERT_TRUE(fs::exists(model)) << model << ": install assimp-testmodels";
        soup_ = soup_of(import_mesh(model).mesh);
        write_binary_stl(stl_, soup_);
    }

    ToolRun build(std::vector<std::string> extra)
    {
        std::vector<std::string> args = {stl_.string(), "-o", welded_.string()};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_tool(SG_BUILD_EXE, args, scratch_);
    }

    ScratchDir scratch_;
    Mesh soup_;
    fs::path stl_ = scratch_ / "duck_soup.stl";
    fs::path welded_ = scratch_ / "welded.sg";
};

TEST_F(SgBuildWelding, ReportsVerticesBeforeAndAfterWelding)
{
    const std::size_t distinct = distinct_corner_positions(soup_);
    ASSERT_LT(distinct, soup_.vertices.size() / 3) << "a closed surface shares its corners";

    const ToolRun text = build({});
    ASSERT_EQ(text.exit_code, 0) << describe(text);
    EXPECT_NE(text.out.find("vertices    " + std::to_string(soup_.vertices.size()) +
                            " before welding, " + std::to_string(distinct) + " after"),
              std::string::npos)
        << text.out;

    const ToolRun j = build({"--json"});
    ASSERT_EQ(j.exit_code, 0) << describe(j);
    const json imp = json::parse(j.out).at("import");
    EXPECT_EQ(imp.at("vertices_before_welding"), soup_.vertices.size());
    EXPECT_EQ(imp.at("vertices"), distinct);

    const ToolRun stats = run_tool(SG_STATS_EXE, {welded_.string()}, scratch_);
    ASSERT_EQ(stats.exit_code, 0) << describe(stats);
    EXPECT_NE(stats.out.find(std::to_string(distinct) + " vertices stored, " +
                             std::to_string(soup_.triangles.size()) + " triangles"),
              std::string::npos)
        << stats.out;
    const ToolRun stats_json = run_tool(SG_STATS_EXE, {welded_.string(), "--json"}, scratch_);
    ASSERT_EQ(stats_json.exit_code, 0) << describe(stats_json);
    EXPECT_EQ(json::parse(stats_json.out).at("mesh").at("vertex_count"), distinct);
}

TEST_F(SgBuildWelding, FileKeepsEveryCornerAndTracesLikeTheUnweldedSoup)
{
    const ToolRun run = build({"-q"});
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const SgContents welded = read_sg_file(welded_);
    ASSERT_EQ(welded.mesh.triangles.size(), soup_.triangles.size());
    for (std::uint32_t t = 0; t < soup_.triangles.size(); ++t)
        for (int c = 0; c < 3; ++c)
            ASSERT_EQ(position_bits(welded.mesh.view().vertex(t, c)),
                      position_bits(soup_.view().vertex(t, c)))
                << "triangle " << t << " corner " << c;

    // The soup as it was before welding, with its own grid, in a file of its own.
    const fs::path unwelded = scratch_ / "unwelded.sg";
    write_sg_file(unwelded, SgContents{soup_, build_split_grid(soup_.view(), BuildConfig{}),
                                       "duck_soup.stl"});

    // Rays aimed at the soup's triangles (mostly hits) and random ones, from a box larger
    // than the duck's.
    Aabb box = bounds(soup_.view());
    const Vec3f pad = (box.upper - box.lower) * 0.25f;
    box.lower = box.lower - pad;
    box.upper = box.upper + pad;
    const fs::path rays = scratch_ / "aimed.rays";
    write_ray_file(rays, rays_at_triangles(5, 20000, box, soup_.view()));
    const fs::path random = scratch_ / "random.rays";
    write_ray_file(random, random_rays(6, 20000, box));

    for (const fs::path& ray_file : {rays, random}) {
        SCOPED_TRACE(ray_file.filename().string());
        for (const fs::path& sg : {welded_, unwelded}) {
            const ToolRun traced =
                run_tool(SG_TRACE_EXE,
                         {sg.string(), "--rays", ray_file.string(), "--out",
                          (scratch_ / (sg.stem().string() + ".hits")).string()},
                         scratch_);
            ASSERT_EQ(traced.exit_code, 0) << describe(traced);
        }
        const std::vector<Hit> hits = read_hit_file(scratch_ / "welded.hits");
        std::size_t hit_count = 0;
        for (const Hit& h : hits) hit_count += h.is_hit() ? 1 : 0;
        EXPECT_GT(hit_count, hits.size() / 50) << "the rays must hit the duck";
        EXPECT_EQ(read_text(scratch_ / "welded.hits"), read_text(scratch_ / "unwelded.hits"))
            << "triangle ids, t, u and v must be bit-identical";
    }
}

// The same on a scanned mesh of ../shared/meshes: the Stanford bunny written as a binary STL
// soup (208,353 corners) welds to the positions the soup really has, and the file shrinks by
// the 12 bytes of each vertex saved against the same soup stored unwelded.
TEST(SgBuildWeldingShared, StanfordBunnySoupWeldsToItsDistinctPositions)
{
    const fs::path model = shared_mesh("scanned/stanford_bunny.obj");
    if (!fs::exists(model)) GTEST_SKIP() << model << " not found (../shared/meshes is absent)";
    ScratchDir scratch;
    const Mesh soup = soup_of(import_mesh(model).mesh);
    const fs::path stl = scratch / "bunny_soup.stl";
    write_binary_stl(stl, soup);
    const std::size_t distinct = distinct_corner_positions(soup);

    const fs::path welded = scratch / "bunny_soup.sg";
    const ToolRun run = run_tool(SG_BUILD_EXE, {stl.string(), "-o", welded.string(), "--json"},
                                 scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const json imp = json::parse(run.out).at("import");
    EXPECT_EQ(imp.at("triangles_kept"), soup.triangles.size());
    EXPECT_EQ(imp.at("vertices_before_welding"), 3 * soup.triangles.size());
    EXPECT_EQ(imp.at("vertices"), distinct);
    EXPECT_LT(distinct, soup.vertices.size() / 5) << "a scanned surface shares its corners";

    const fs::path unwelded = scratch / "unwelded.sg";
    write_sg_file(unwelded, SgContents{soup, build_split_grid(soup.view(), BuildConfig{}),
                                       "bunny_soup.stl"});
    const auto saved = static_cast<std::int64_t>(soup.vertices.size() - distinct);
    const auto shrink = static_cast<std::int64_t>(fs::file_size(unwelded)) -
                        static_cast<std::int64_t>(fs::file_size(welded));
    // 12 bytes per vertex, give or take the 8-byte alignment of the sections that follow.
    EXPECT_NEAR(static_cast<double>(shrink), 12.0 * static_cast<double>(saved), 8.0);
}

}  // namespace
}  // namespace sg::test
