// End-to-end tests of sg-points --query occupancy: two tessellated cubes made here, built by
// sg-build from an OBJ file, and points on their grid lines and planes (where rays from the
// points run through the surface's edges and vertices) answered against the analytic inside;
// point files and text points; the warning of an open mesh against edges counted here; the
// refusals (exit codes, messages, nothing written); the JSON; the numpy lines of
// docs/FORMAT.md.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "splitgrid/closed_shapes.hpp"
#include "splitgrid/formats/point_file.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/occupancy.hpp"
#include "splitgrid/ray_triangle.hpp"
#include "support/edge_oracle.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr float nan = std::numeric_limits<float>::quiet_NaN();
constexpr float inf = std::numeric_limits<float>::infinity();
constexpr float side = 4.0f;  ///< the cubes' edge length, in unit squares
constexpr float gap = 2.0f;   ///< between the cubes along x

/// The cube [0, 4]^3 and its copy moved to [6, 10] x [0, 4]^2: a closed mesh whose root box
/// also holds points outside it (the gap between the cubes).
Mesh two_cubes()
{
    Mesh mesh = tessellated_cube(static_cast<std::uint32_t>(side));
    Mesh other = mesh;
    for (Vec3f& v : other.vertices) v.x += side + gap;
    const auto offset = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), other.vertices.begin(), other.vertices.end());
    for (Triangle t : other.triangles) {
        for (std::uint32_t& v : t.v) v += offset;
        mesh.triangles.push_back(t);
    }
    return mesh;
}

/// Where p lies against the box [lo, hi] on every axis: strictly inside (1), on its boundary
/// (0) or outside (-1).
int side_of_box(Vec3f p, Vec3f lo, Vec3f hi)
{
    bool on_boundary = false;
    for (int a = 0; a < 3; ++a) {
        if (p[a] < lo[a] || p[a] > hi[a]) return -1;
        on_boundary = on_boundary || p[a] == lo[a] || p[a] == hi[a];
    }
    return on_boundary ? 0 : 1;
}

/// The analytic answer: 1 strictly inside a cube, 0 outside both; -1 on a surface.
int inside_two_cubes(Vec3f p)
{
    const int a = side_of_box(p, {0, 0, 0}, {side, side, side});
    const int b = side_of_box(p, {side + gap, 0, 0}, {2 * side + gap, side, side});
    if (a == 0 || b == 0) return -1;
    return a == 1 || b == 1 ? 1 : 0;
}

/// Points every half unit from 1 below to 1 above the cubes, none on a surface: on the cubes'
/// grid lines and planes (integers) and between them, inside, in the gap and around.
std::vector<Vec3f> lattice_points()
{
    std::vector<Vec3f> points;
    for (float x = -1.0f; x <= 2 * side + gap + 1.0f; x += 0.5f)
        for (float y = -1.0f; y <= side + 1.0f; y += 0.5f)
            for (float z = -1.0f; z <= side + 1.0f; z += 0.5f)
                if (inside_two_cubes({x, y, z}) >= 0) points.push_back({x, y, z});
    return points;
}

std::size_t line_count(const std::string& text)
{
    return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

class SgPoints : public ::testing::Test {
protected:
    void SetUp() override { build(two_cubes(), sg_file_); }

    void build(const Mesh& mesh, const fs::path& sg_file)
    {
        const fs::path obj = fs::path(sg_file).replace_extension(".obj");
        write_text(obj, obj_of(mesh));
        const ToolRun run =
            run_tool(SG_BUILD_EXE, {obj.string(), "-o", sg_file.string()}, scratch_);
        ASSERT_EQ(run.exit_code, 0) << describe(run);
    }

    ToolRun points(const fs::path& points_file, std::vector<std::string> extra,
                   const fs::path& sg_file = {})
    {
        std::vector<std::string> args = {sg_file.empty() ? sg_file_.string() : sg_file.string(),
                                         "--points", points_file.string(), "-o", out_.string(),
                                         "--query", "occupancy"};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_tool(SG_POINTS_EXE, args, scratch_);
    }

    /// Expects the documented refusal: `code`, one line "error: ..." naming `named`, nothing on
    /// stdout, no output and no temporary file.
    void expect_refused(const ToolRun& run, int code, const std::string& named)
    {
        expect_refused_leaving_nothing(run, code, named, out_, scratch_.path());
    }

    ScratchDir scratch_;
    fs::path sg_file_ = scratch_ / "cubes.sg";
    fs::path out_ = scratch_ / "occupancy.bin";
};

TEST_F(SgPoints, OccupancyOnGridLinesAndPlanesIsTheAnalyticInside)
{
    std::vector<Vec3f> pts = lattice_points();
    pts.insert(pts.begin() + 7, Vec3f{nan, 1.0f, 1.0f});
    pts.push_back({1.0f, inf, 1.0f});
    const fs::path file = scratch_ / "points.bin";
    write_point_file(file, pts);

    std::size_t inside = 0, outside = 0;
    for (const Vec3f p : pts)
        if (is_finite(p)) (inside_two_cubes(p) == 1 ? inside : outside) += 1;
    // Premise: both answers, many points inside the root box but outside the mesh.
    ASSERT_GT(inside, 500u);
    ASSERT_GT(outside, 1000u);

    std::string first_bytes;
    for (const auto& [nsamples, threads] : {std::pair{"1", "1"}, std::pair{"1", "2"},
                                            std::pair{"5", "2"}, std::pair{"7", "1"}}) {
        SCOPED_TRACE(std::string("--nsamples ") + nsamples + " --threads " + threads);
        const ToolRun run = points(file, {"--nsamples", nsamples, "--threads", threads, "--json"});
        ASSERT_EQ(run.exit_code, 0) << describe(run);
        const std::vector<float> got = read_occupancy_file(out_);
        ASSERT_EQ(got.size(), pts.size());
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const bool ok = is_finite(pts[i])
                                ? got[i] == static_cast<float>(inside_two_cubes(pts[i]))
                                : std::isnan(got[i]);
            if (!ok && ++wrong <= 5)
                ADD_FAILURE() << "point (" << pts[i].x << ", " << pts[i].y << ", " << pts[i].z
                              << "): " << got[i];
        }
        EXPECT_EQ(wrong, 0u);
        if (std::string(nsamples) == "1") {
            if (first_bytes.empty())
                first_bytes = read_text(out_);
            else
                EXPECT_EQ(read_text(out_), first_bytes) << "the file depends on --threads";
        }

        const json j = json::parse(run.out);
        EXPECT_EQ(j.at("query"), "occupancy");
        EXPECT_EQ(j.at("nsamples"), std::stoi(nsamples));
        EXPECT_EQ(j.at("threads"), std::stoi(threads));
        EXPECT_EQ(j.at("point_count"), pts.size());
        EXPECT_EQ(j.at("inside"), inside);
        EXPECT_EQ(j.at("outside"), outside);
        EXPECT_EQ(j.at("nonfinite_points"), 2);
        EXPECT_EQ(j.at("points_format"), "binary");
        EXPECT_EQ(j.at("points_file"), file.string());
        EXPECT_EQ(j.at("output"), out_.string());
        EXPECT_EQ(j.at("edges").at("closed"), true);
        EXPECT_EQ(j.at("edges").at("open_edges"), 0);
        EXPECT_EQ(j.at("edges").at("edges"), count_edges(two_cubes()).edges);
        EXPECT_GT(j.at("points_per_second").get<double>(), 0.0);
        // The non-finite points: one warning naming the count and the first; nothing else.
        EXPECT_EQ(line_count(run.err), 1u) << run.err;
        EXPECT_EQ(run.err.rfind("warning: " + file.string() + ": 2 of " +
                                    std::to_string(pts.size()) +
                                    " points are invalid (a NaN or infinite coordinate; the "
                                    "first is point 7): the file is well formed, the points are "
                                    "not; they are written as NaN",
                                0),
                  0u)
            << run.err;
    }

    const ToolRun summary = points(file, {});
    ASSERT_EQ(summary.exit_code, 0) << describe(summary);
    EXPECT_NE(summary.out.find(std::to_string(inside) + " inside, " + std::to_string(outside) +
                               " outside, 2 non-finite, written to " + out_.string()),
              std::string::npos)
        << summary.out;
    const ToolRun quiet = points(file, {"-q"});
    ASSERT_EQ(quiet.exit_code, 0) << describe(quiet);
    EXPECT_EQ(quiet.out, "");

    fs::remove(out_);
    const ToolRun strict = points(file, {"--strict"});
    expect_refused(strict, 2, "refused by --strict");
}

TEST_F(SgPoints, TextPointsAreReadLineByLine)
{
    // Every 13th lattice point, as a CSV with a header, a comment, blanks and commas.
    const std::vector<Vec3f> all = lattice_points();
    std::vector<Vec3f> pts;
    std::ostringstream csv;
    csv << "x,y,z\n# points of the test\n";
    for (std::size_t i = 0; i < all.size(); i += 13) {
        pts.push_back(all[i]);
        csv << all[i].x << (i % 2 == 0 ? ", " : " ") << all[i].y << "," << all[i].z << "\n";
    }
    const fs::path file = scratch_ / "pts.csv";
    write_text(file, csv.str());
    const ToolRun run = points(file, {"--json"});
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    EXPECT_EQ(json::parse(run.out).at("points_format"), "text");
    EXPECT_EQ(run.err, "");
    const std::vector<float> got = read_occupancy_file(out_);
    ASSERT_EQ(got.size(), pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i)
        EXPECT_EQ(got[i], static_cast<float>(inside_two_cubes(pts[i]))) << i;
}

TEST_F(SgPoints, TextWithABadFieldIsRefusedNamingTheLine)
{
    write_text(out_, "an earlier result");
    const fs::path file = scratch_ / "pts.csv";
    write_text(file, "x,y,z\n1,2,3\n4,x,6\n");
    const ToolRun run = points(file, {});
    EXPECT_EQ(run.exit_code, 2) << describe(run);
    EXPECT_EQ(run.err, "error: " + file.string() + ":3: field 2 'x' is not a number\n");
    EXPECT_EQ(read_text(out_), "an earlier result") << "an existing output is left untouched";
}

TEST_F(SgPoints, MissingTruncatedOrForeignPointFilesAreRefused)
{
    expect_refused(points(scratch_ / "none.bin", {}), 2, (scratch_ / "none.bin").string());

    const fs::path file = scratch_ / "points.bin";
    write_point_file(file, lattice_points());
    const std::string bytes = read_text(file);
    write_text(scratch_ / "cut.bin", bytes.substr(0, bytes.size() - 5));
    const ToolRun cut = points(scratch_ / "cut.bin", {});
    expect_refused(cut, 2, (scratch_ / "cut.bin").string());
    EXPECT_NE(cut.err.find("truncated"), std::string::npos) << cut.err;

    expect_refused(points(sg_file_, {}), 2, "neither a point file");
    write_text(scratch_ / "binary.bin", std::string("\x89PNG\r\n\x1a\n", 8));
    expect_refused(points(scratch_ / "binary.bin", {}), 2, "neither a point file");
    const ToolRun over = run_tool(SG_POINTS_EXE,
                                  {sg_file_.string(), "--points", file.string(), "-o",
                                   file.string(), "--query", "occupancy"},
                                  scratch_);
    EXPECT_EQ(over.exit_code, 2) << describe(over);
    EXPECT_NE(over.err.find("refusing to write the output over the input"), std::string::npos)
        << over.err;
    EXPECT_EQ(read_text(file), bytes) << "the input is left untouched";
    expect_refused(points(file, {}, scratch_ / "missing.sg"), 2, "missing.sg");
}

TEST_F(SgPoints, UsageErrorsExitWithOne)
{
    const fs::path file = scratch_ / "points.bin";
    write_point_file(file, lattice_points());
    const ToolRun even = points(file, {"--nsamples", "4"});
    expect_refused(even, 1, "--nsamples 4 is even");
    expect_refused(points(file, {"--nsamples", "0"}), 1, "--nsamples");
    expect_refused(points(file, {"--nsamples", "1001"}), 1, "--nsamples");
    const ToolRun unknown = run_tool(SG_POINTS_EXE,
                                     {sg_file_.string(), "--points", file.string(), "-o",
                                      out_.string(), "--query", "volume"},
                                     scratch_);
    expect_refused(unknown, 1, "volume");
    const ToolRun no_query = run_tool(
        SG_POINTS_EXE, {sg_file_.string(), "--points", file.string(), "-o", out_.string()},
        scratch_);
    expect_refused(no_query, 1, "--query");
}

TEST_F(SgPoints, OpenMeshGetsOneWarningNamingItsEdges)
{
    // One cube without its first triangle (3 open edges), and with a face's triangle twice
    // (3 edges shared by three triangles: open and non-manifold).
    Mesh open = tessellated_cube(static_cast<std::uint32_t>(side));
    open.triangles.push_back(open.triangles[5]);
    open.triangles.erase(open.triangles.begin());
    const EdgeCounts expected = count_edges(open);
    ASSERT_EQ(expected.open_edges, 6u);
    ASSERT_EQ(expected.nonmanifold_edges, 3u);
    const fs::path sg_file = scratch_ / "open.sg";
    build(open, sg_file);

    const fs::path file = scratch_ / "points.bin";
    write_point_file(file, std::vector<Vec3f>{{1, 1, 1}, {2, 2, 2}, {3.5f, 0.5f, 2}});
    const ToolRun run = points(file, {"--nsamples", "3", "--json"}, sg_file);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    EXPECT_EQ(line_count(run.err), 1u) << run.err;
    const std::string warning = "warning: " + sg_file.string() +
                                ": the mesh is not closed: 6 open edges (shared by an odd number "
                                "of triangles) and 3 non-manifold edges (shared by more than "
                                "two) of " +
                                std::to_string(expected.edges);
    EXPECT_EQ(run.err.rfind(warning, 0), 0u) << run.err;
    const json j = json::parse(run.out);
    EXPECT_EQ(j.at("edges").at("closed"), false);
    EXPECT_EQ(j.at("edges").at("open_edges"), expected.open_edges);
    EXPECT_EQ(j.at("edges").at("nonmanifold_edges"), expected.nonmanifold_edges);
    EXPECT_EQ(j.at("edges").at("edges"), expected.edges);
    EXPECT_EQ(read_occupancy_file(out_).size(), 3u);

    // The closed cubes give no warning.
    const ToolRun closed = points(file, {});
    ASSERT_EQ(closed.exit_code, 0) << describe(closed);
    EXPECT_EQ(closed.err, "");
}

/// Occupancy by brute force: for each of the nsamples rays of occupancy_ray, the parity of the
/// triangles it crosses, each tested with intersect_triangle; the majority decides. A point
/// outside the root box is outside without a ray, as compute_occupancy documents.
float occupancy_by_every_triangle(const SgContents& contents, Vec3f p, std::uint32_t nsamples)
{
    const Aabb& box = contents.grid.root_box;
    for (int a = 0; a < 3; ++a)
        if (!(p[a] >= box.lower[a] && p[a] <= box.upper[a])) return 0.0f;
    const MeshView mesh = contents.mesh.view();
    std::uint32_t odd = 0;
    for (std::uint32_t s = 0; s < nsamples; ++s) {
        const Ray ray = occupancy_ray(p, box, s, nsamples);
        const WatertightRay watertight(ray);
        std::uint32_t crossings = 0;
        for (std::uint32_t i = 0; i < mesh.triangle_count(); ++i) {
            float t = 0, u = 0, v = 0;
            crossings += intersect_triangle(watertight, mesh.vertex(i, 0), mesh.vertex(i, 1),
                                            mesh.vertex(i, 2), ray.t_min, ray.t_max, t, u, v)
                             ? 1
                             : 0;
        }
        odd += crossings % 2;
    }
    return 2 * odd > nsamples ? 1.0f : 0.0f;
}

TEST_F(SgPoints, NsamplesVoteOnAMeshWithoutItsTopFace)
{
    // Rays from points near the missing top leave through the hole and cross nothing: one
    // ray says outside; more rays, most of which meet the walls, say inside.
    Mesh open = tessellated_cube(static_cast<std::uint32_t>(side));
    std::erase_if(open.triangles, [&](const Triangle& t) {
        return std::all_of(t.v.begin(), t.v.end(),
                           [&](std::uint32_t v) { return open.vertices[v].z == side; });
    });
    const fs::path sg_file = scratch_ / "open_top.sg";
    build(open, sg_file);
    const SgContents contents = read_sg_file(sg_file);
    std::vector<Vec3f> pts;
    for (float x = 0.5f; x < side; x += 0.5f)
        for (float y = 0.5f; y < side; y += 0.5f)
            for (float z = 0.5f; z < side; z += 0.5f) pts.push_back({x, y, z});
    const fs::path file = scratch_ / "points.bin";
    write_point_file(file, pts);

    std::vector<std::vector<float>> answers;
    for (const std::uint32_t nsamples : {1u, 3u, 9u}) {
        SCOPED_TRACE(nsamples);
        const ToolRun run = points(file, {"--nsamples", std::to_string(nsamples)}, sg_file);
        ASSERT_EQ(run.exit_code, 0) << describe(run);
        EXPECT_NE(run.err.find("the mesh is not closed"), std::string::npos) << run.err;
        answers.push_back(read_occupancy_file(out_));
        ASSERT_EQ(answers.back().size(), pts.size());
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < pts.size(); ++i)
            wrong += answers.back()[i] == occupancy_by_every_triangle(contents, pts[i], nsamples)
                         ? 0
                         : 1;
        EXPECT_EQ(wrong, 0u) << "of " << pts.size();
    }
    // Premise: the vote changes answers.
    EXPECT_NE(answers[0], answers[2]);
}

TEST_F(SgPoints, NumpyLinesOfFormatMdReadAndWritePointFiles)
{
    const std::string doc = read_text(fs::path(SG_SOURCE_DIR) / "docs" / "FORMAT.md");
    const std::size_t heading = doc.find("Reading and writing point files with numpy");
    ASSERT_NE(heading, std::string::npos) << "docs/FORMAT.md lost its numpy block";
    const std::size_t start = doc.find("```python\n", heading) + 10;
    const std::string code = doc.substr(start, doc.find("```\n", start) - start);
    const fs::path script = scratch_ / "points.py";
    write_text(script, code);

    std::vector<Vec3f> pts = lattice_points();
    pts.push_back({nan, 0, 0});
    const fs::path file = scratch_ / "points.bin";
    write_point_file(file, pts);
    ASSERT_EQ(points(file, {}).exit_code, 0);
    const fs::path mine = scratch_ / "my_points.bin";
    const ToolRun python = run_tool("/usr/bin/python3",
                                    {script.string(), file.string(), out_.string(), mine.string()},
                                    scratch_);
    ASSERT_EQ(python.exit_code, 0) << describe(python);
    std::size_t inside = 0;
    for (const Vec3f p : pts) inside += is_finite(p) && inside_two_cubes(p) == 1 ? 1 : 0;
    EXPECT_EQ(python.out, std::to_string(pts.size()) + " points, " + std::to_string(inside) +
                              " inside, 1 non-finite\n");

    // The point file numpy wrote is one sg-points reads, with the points numpy meant.
    const std::vector<Vec3f> written = read_point_file(mine);
    ASSERT_EQ(written.size(), 2u);
    EXPECT_EQ(written[0], (Vec3f{0.5f, 0.5f, 0.5f}));
    EXPECT_EQ(written[1], (Vec3f{2, 2, 2}));
    const ToolRun traced = points(mine, {"--strict"});
    ASSERT_EQ(traced.exit_code, 0) << describe(traced);
    EXPECT_EQ(read_occupancy_file(out_), (std::vector<float>{1.0f, 1.0f}));
}

TEST(SgPointsHelp, ExplainsEveryOptionWithRangeAndDefault)
{
    ScratchDir scratch;
    const ToolRun run = run_tool(SG_POINTS_EXE, {"--help"}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    for (const char* text :
         {"--points", "-o,--output", "--query", "occupancy", "distance", "signed-distance",
          "closest", "--nsamples", "Range [1, 999]. Default 1.", "--max-distance",
          "Default none.", "--grid NX,NY,NZ", "At most 67108864 points", "--padding",
          "Range [0, 10]. Default 0.05.", "--threads", "Range [0, 1024]", "--strict", "--json",
          "-q,--quiet", "-v,--verbose", "--version", "SGPTS001", "SGOCC001", "SGDST001",
          "SGSDF001", "SGCLP001", ".vti", "text", "no converter", "Exit codes:"})
        EXPECT_NE(run.out.find(text), std::string::npos) << text;
    const ToolRun version = run_tool(SG_POINTS_EXE, {"--version"}, scratch);
    ASSERT_EQ(version.exit_code, 0) << describe(version);
    EXPECT_EQ(version.out.rfind("sg-points ", 0), 0u) << version.out;
}

}  // namespace
}  // namespace sg::test
