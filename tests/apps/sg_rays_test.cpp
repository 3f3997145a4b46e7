// End-to-end tests of sg-rays: each mode run as a process and its ray file read back (with
// the library's reader and byte by byte), against independent expectations: sg-render's
// camera for the same flags, rays computed here from the documented generator, the numbers
// of a text file written here; bad input gives one line "error: <file>:<line>: ..." and no
// ray file. Also the numpy lines of docs/FORMAT.md, run with /usr/bin/python3 on files the
// tools wrote.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "splitgrid/camera.hpp"
#include "splitgrid/formats/ray_file.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/sampling.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }

void expect_same_ray(const Ray& expected, const Ray& actual)
{
    for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(bits(actual.origin[a]), bits(expected.origin[a])) << "origin " << a;
        EXPECT_EQ(bits(actual.direction[a]), bits(expected.direction[a])) << "direction " << a;
    }
    EXPECT_EQ(bits(actual.t_min), bits(expected.t_min));
    EXPECT_EQ(bits(actual.t_max), bits(expected.t_max));
}

Vec3f vec_of(const json& v) { return {v[0].get<float>(), v[1].get<float>(), v[2].get<float>()}; }

class SgRays : public ::testing::Test {
protected:
    void SetUp() override
    {
        const fs::path model = assimp_model("Collada/duck.dae");
        ASSERT_TRUE(fs::exists(model)) << model << ": install assimp-testmodels";
        const ToolRun build =
            run_tool(SG_BUILD_EXE, {model.string(), "-o", sg_file_.string()}, scratch_);
        ASSERT_EQ(build.exit_code, 0) << describe(build);
    }

    ToolRun rays(std::vector<std::string> args)
    {
        return run_tool(SG_RAYS_EXE, args, scratch_);
    }

    /// Expects the documented refusal: `code`, one line "error: ..." naming `named`, nothing
    /// on stdout, no ray file and no temporary file.
    void expect_refused(const ToolRun& run, int code, const std::string& named)
    {
        expect_refused_leaving_nothing(run, code, named, out_, scratch_.path());
    }

    ScratchDir scratch_;
    fs::path sg_file_ = scratch_ / "duck.sg";
    fs::path out_ = scratch_ / "rays.bin";
};

TEST_F(SgRays, CameraModeWritesTheRaysOfSgRendersCamera)
{
    // sg-render prints the camera it frames; sg-rays must frame the same one for the same
    // flags and write its pixel-centre rays, row by row, in the documented layout.
    const std::vector<std::string> view = {"--width", "64", "--height", "48", "--up", "0,0,1",
                                           "--fov", "50"};
    std::vector<std::string> render_args = {sg_file_.string(), "-o",
                                            (scratch_ / "duck.png").string(), "--json"};
    render_args.insert(render_args.end(), view.begin(), view.end());
#ifdef SG_RENDER_EXE
    const ToolRun render = run_tool(SG_RENDER_EXE, render_args, scratch_);
    ASSERT_EQ(render.exit_code, 0) << describe(render);
    const json render_camera = json::parse(render.out).at("camera");
#endif
    std::vector<std::string> args = {"camera", sg_file_.string(), "-o", out_.string(), "--json"};
    args.insert(args.end(), view.begin(), view.end());
    const ToolRun run = rays(args);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const json j = json::parse(run.out);
    EXPECT_EQ(j.at("mode"), "camera");
    EXPECT_EQ(j.at("ray_count"), 64 * 48);
    EXPECT_EQ(j.at("invalid_rays"), 0);
    const json camera_json = j.at("camera");
#ifdef SG_RENDER_EXE
    EXPECT_EQ(camera_json, render_camera) << "the same framing as sg-render";
#endif
    EXPECT_EQ(camera_json.at("up"), json::parse("[0.0, 0.0, 1.0]"));

    // The file: 16 + 32 bytes per ray; each ray from the eye through its pixel's centre.
    EXPECT_EQ(fs::file_size(out_), 16u + 32u * 64u * 48u);
    const std::vector<Ray> got = read_ray_file(out_);
    ASSERT_EQ(got.size(), 64u * 48u);
    const Camera camera{vec_of(camera_json.at("eye")), vec_of(camera_json.at("look_at")),
                        vec_of(camera_json.at("up")), camera_json.at("fov_y_degrees").get<float>()};
    const PrimaryRays primary(camera, 64, 48);
    for (int y = 0; y < 48; y += 7)
        for (int x = 0; x < 64; x += 5) {
            SCOPED_TRACE(testing::Message() << "pixel " << x << "," << y);
            expect_same_ray(primary.ray(float(x) + 0.5f, float(y) + 0.5f),
                            got[static_cast<std::size_t>(y * 64 + x)]);
        }
    // The text summary names the camera as flags, to adjust from.
    std::vector<std::string> text_args = {"camera", sg_file_.string(), "--out", out_.string()};
    text_args.insert(text_args.end(), view.begin(), view.end());
    const ToolRun text = rays(text_args);
    ASSERT_EQ(text.exit_code, 0) << describe(text);
    EXPECT_NE(text.out.find("wrote 3072 rays (camera"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("--eye "), std::string::npos) << text.out;
}

TEST_F(SgRays, RandomModeFollowsTheDocumentedGenerator)
{
    const ToolRun run = rays({"random", sg_file_.string(), "-o", out_.string(), "--count",
                              "500", "--seed", "42", "--json"});
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const json j = json::parse(run.out);
    EXPECT_EQ(j.at("ray_count"), 500);
    EXPECT_EQ(j.at("seed"), 42);
    const std::vector<Ray> got = read_ray_file(out_);
    ASSERT_EQ(got.size(), 500u);

    // --help's recipe, written out here: ray k uses Rng(seed, k), three numbers for the
    // origin in the box of the triangles, two for the direction.
    const SgContents contents = read_sg_file(sg_file_);
    const Aabb box = bounds(contents.mesh.view());
    EXPECT_EQ(vec_of(j.at("box").at("lower")), box.lower);
    EXPECT_EQ(vec_of(j.at("box").at("upper")), box.upper);
    for (std::size_t k = 0; k < got.size(); ++k) {
        SCOPED_TRACE(k);
        Rng rng(42, k);
        Ray expected;
        for (int a = 0; a < 3; ++a)
            expected.origin[a] = box.lower[a] + rng.next_float() * box.extent(a);
        const float u1 = rng.next_float();
        const float u2 = rng.next_float();
        expected.direction = uniform_sphere(u1, u2);
        expect_same_ray(expected, got[k]);
    }

    // Same seed, same file; another seed, other rays.
    const fs::path again = scratch_ / "again.bin";
    ASSERT_EQ(rays({"random", sg_file_.string(), "-o", again.string(), "--count", "500",
                    "--seed", "42"})
                  .exit_code,
              0);
    EXPECT_EQ(read_text(again), read_text(out_));
    ASSERT_EQ(rays({"random", sg_file_.string(), "-o", again.string(), "--count", "500",
                    "--seed", "43"})
                  .exit_code,
              0);
    EXPECT_NE(read_text(again), read_text(out_));
}

TEST_F(SgRays, TextModeReadsCsvAndBlankSeparatedLines)
{
    const fs::path csv = scratch_ / "rays.csv";
    write_text(csv,
               "ox,oy,oz,dx,dy,dz,t_min,t_max\r\n"
               "# a comment, then a blank line\r\n"
               "\r\n"
               "0.5, -1, 2e1, 0, 0, -1\r\n"
               "1 2 3\t4 5 6 0.25 +7.5\n"
               "  -0.0,1e-3,3.25,1,0,0,1,inf\n"
               "0,0,0,0,0,0,0,nan\n");
    const ToolRun run = rays({"text", csv.string(), "-o", out_.string(), "--json"});
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    EXPECT_EQ(json::parse(run.out).at("ray_count"), 4);
    EXPECT_EQ(json::parse(run.out).at("invalid_rays"), 1) << "the zero direction";
    EXPECT_NE(run.err.find("1 of 4 rays are invalid"), std::string::npos) << run.err;
    const float inf = std::numeric_limits<float>::infinity();
    const std::vector<Ray> got = read_ray_file(out_);
    ASSERT_EQ(got.size(), 4u);
    expect_same_ray(Ray{{0.5f, -1.0f, 20.0f}, {0, 0, -1}, 0.0f, inf}, got[0]);
    expect_same_ray(Ray{{1, 2, 3}, {4, 5, 6}, 0.25f, 7.5f}, got[1]);
    expect_same_ray(Ray{{-0.0f, 1e-3f, 3.25f}, {1, 0, 0}, 1.0f, inf}, got[2]);
    EXPECT_TRUE(std::isnan(got[3].t_max));
}

TEST_F(SgRays, TextErrorsNameTheLine)
{
    struct Case {
        std::string text;
        std::string message;
    };
    const std::vector<Case> cases = {
        {"0,0,0,1,0,0\n0,0,x,1,0,0\n", "rays.csv:2: field 3 'x' is not a number"},
        {"# c\n0 0 0 1 0\n", "rays.csv:2: 5 fields, expected 6"},
        {"0,0,0,1,0,0,0\n", "rays.csv:1: 7 fields"},
        {"0,0,0,,1,0\n", "rays.csv:1: field 4 is empty"},
        {"0,0,0,1,0,0\n0,0,0,1,0,1e39\n", "rays.csv:2: field 6 '1e39' is outside the float32"},
        {"0,0,0,1.2.3,0,0\n", "rays.csv:1: field 4 '1.2.3' is not a number"},
        {"# only a comment\n\n", "rays.csv: no rays"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.text);
        write_text(scratch_ / "rays.csv", c.text);
        expect_refused(rays({"text", (scratch_ / "rays.csv").string(), "-o", out_.string()}), 2,
                       c.message);
    }
    expect_refused(rays({"text", (scratch_ / "missing.csv").string(), "-o", out_.string()}), 2,
                   "missing.csv");
}

TEST_F(SgRays, BadCommandLinesAndFilesAreRefused)
{
    expect_refused(rays({"camera", sg_file_.string()}), 1, "--output");
    expect_refused(rays({"sphere", sg_file_.string(), "-o", out_.string()}), 1, "sphere");
    expect_refused(rays({"random", sg_file_.string(), "-o", out_.string(), "--count", "0"}), 1,
                   "0");
    expect_refused(rays({"camera", sg_file_.string(), "-o", out_.string(), "--up", "0,0,0"}), 1,
                   "up");
    expect_refused(rays({"camera", (scratch_ / "missing.sg").string(), "-o", out_.string()}), 2,
                   "missing.sg");
    expect_refused(rays({"camera", sg_file_.string(), "-o",
                         (scratch_ / "no_such_folder" / "rays.bin").string()}),
                   2, "no_such_folder");
}

TEST_F(SgRays, HelpExplainsEveryMode)
{
    const ToolRun run = rays({"--help"});
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    for (const char* text : {"camera", "random", "text", "pixel", "PCG32", "--seed", "header",
                             "Exit codes:", "-o,--output"})
        EXPECT_NE(run.out.find(text), std::string::npos) << text;
    const ToolRun camera = rays({"camera", "--help"});
    ASSERT_EQ(camera.exit_code, 0) << describe(camera);
    for (const char* text : {"--width", "--eye", "--look-at", "--up", "--fov"})
        EXPECT_NE(camera.out.find(text), std::string::npos) << text;
}

/// The ```python block that follows the heading "Reading and writing ray and hit files with
/// numpy" in docs/FORMAT.md.
std::string numpy_lines_of_format_md()
{
    const std::string doc = read_text(fs::path(SG_SOURCE_DIR) / "docs" / "FORMAT.md");
    const std::size_t heading = doc.find("Reading and writing ray and hit files with numpy");
    if (heading == std::string::npos) return {};
    const std::size_t start = doc.find("```python\n", heading);
    if (start == std::string::npos) return {};
    const std::size_t end = doc.find("```\n", start + 10);
    return doc.substr(start + 10, end - start - 10);
}

TEST_F(SgRays, NumpyLinesOfFormatMdRunOnFilesTheToolsWrote)
{
    // python3-numpy comes with python3-matplotlib, which scripts/setup.sh installs.
    const std::string code = numpy_lines_of_format_md();
    ASSERT_FALSE(code.empty()) << "docs/FORMAT.md lost its numpy block";
    const fs::path script = scratch_ / "format_numpy.py";
    write_text(script, code);

    const fs::path hits = scratch_ / "hits.bin";
    ASSERT_EQ(rays({"camera", sg_file_.string(), "-o", out_.string(), "--width", "40",
                    "--height", "30"})
                  .exit_code,
              0);
    ASSERT_EQ(run_tool(SG_TRACE_EXE,
                       {sg_file_.string(), "--rays", out_.string(), "--out", hits.string()},
                       scratch_)
                  .exit_code,
              0);
    // The block reads rays.bin and hits.bin, prints what it read and writes my_rays.bin.
    const fs::path mine = scratch_ / "my_rays.bin";
    const ToolRun python = run_tool("/usr/bin/python3",
                                    {script.string(), out_.string(), hits.string(), mine.string()},
                                    scratch_);
    ASSERT_EQ(python.exit_code, 0) << describe(python);
    const std::vector<Hit> expected = read_hit_file(hits);
    std::size_t hit_count = 0;
    for (const Hit& h : expected) hit_count += h.is_hit() ? 1 : 0;
    EXPECT_NE(python.out.find("1200 rays, " + std::to_string(hit_count) + " hits"),
              std::string::npos)
        << python.out;

    // The ray file numpy wrote is one sg-trace reads, with the rays numpy meant.
    const std::vector<Ray> written = read_ray_file(mine);
    ASSERT_EQ(written.size(), 2u);
    expect_same_ray(Ray{{0, 0, 5}, {0, 0, -1}, 0.0f, std::numeric_limits<float>::infinity()},
                    written[0]);
    expect_same_ray(Ray{{1, 2, 3}, {0, 1, 0}, 0.5f, 100.0f}, written[1]);
    const ToolRun traced =
        run_tool(SG_TRACE_EXE,
                 {sg_file_.string(), "--rays", mine.string(), "--out",
                  (scratch_ / "my_hits.bin").string(), "--strict"},
                 scratch_);
    EXPECT_EQ(traced.exit_code, 0) << describe(traced);
}

}  // namespace
}  // namespace sg::test
