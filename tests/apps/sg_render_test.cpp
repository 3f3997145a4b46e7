// End-to-end tests of sg-render: images read back with VTK's readers at the requested size,
// camera flags that change what is seen, thread-count independence, JSON, and bad inputs
// (documented exit code, one line on stderr, no image left behind).
// Built only with VTK (SG_WITH_VTK), which defines SG_RENDER_EXE.

#ifdef SG_RENDER_EXE

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/formats/sg_file.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <vtkImageData.h>
#include <vtkImageReader2.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPNMReader.h>

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// Pixels of an image file as VTK's reader sees them: size and the 8-bit RGB bytes.
struct ReadBack {
    int width = 0;
    int height = 0;
    int components = 0;
    std::vector<unsigned char> bytes;
};

ReadBack read_back(vtkImageReader2* reader, const fs::path& path)
{
    ReadBack image;
    if (!reader->CanReadFile(path.c_str())) return image;
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkImageData* data = reader->GetOutput();
    int dims[3];
    data->GetDimensions(dims);
    image.width = dims[0];
    image.height = dims[1];
    image.components = data->GetNumberOfScalarComponents();
    const auto* p = static_cast<const unsigned char*>(data->GetScalarPointer());
    const std::size_t count = static_cast<std::size_t>(dims[0]) *
                              static_cast<std::size_t>(dims[1]) *
                              static_cast<std::size_t>(image.components);
    image.bytes.assign(p, p + count);
    return image;
}

ReadBack read_png(const fs::path& path)
{
    vtkNew<vtkPNGReader> reader;
    return read_back(reader, path);
}

/// Pixels that differ from the first pixel (the top-left one is background in these views).
std::size_t pixels_unlike_corner(const ReadBack& image)
{
    std::size_t count = 0;
    const auto n = static_cast<std::size_t>(image.components);
    for (std::size_t i = 0; i < image.bytes.size(); i += n)
        if (!std::equal(image.bytes.begin(), image.bytes.begin() + static_cast<std::ptrdiff_t>(n),
                        image.bytes.begin() + static_cast<std::ptrdiff_t>(i)))
            ++count;
    return count;
}

std::size_t line_count(const std::string& text)
{
    return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

class SgRender : public ::testing::Test {
protected:
    void SetUp() override
    {
        const fs::path model = assimp_model("Collada/duck.dae");
        ASSERT_TRUE(fs::exists(model)) << model << ": install assimp-testmodels";
        const ToolRun build =
            run_tool(SG_BUILD_EXE, {model.string(), "-o", sg_file_.string(), "-q"}, scratch_);
        ASSERT_EQ(build.exit_code, 0) << describe(build);
    }

    ToolRun render(const fs::path& out, std::vector<std::string> extra)
    {
        std::vector<std::string> args = {sg_file_.string(), "-o", out.string()};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_tool(SG_RENDER_EXE, args, scratch_);
    }

    ScratchDir scratch_;
    fs::path sg_file_ = scratch_ / "duck.sg";
};

TEST_F(SgRender, EveryModeWritesAnImageOfTheRequestedSize)
{
    for (const std::string mode : {"shaded", "ao", "path", "heat-cells", "heat-triangles"}) {
        SCOPED_TRACE(mode);
        const fs::path out = scratch_ / (mode + ".png");
        const ToolRun run = render(out, {"--mode", mode, "--width", "72", "--height", "40",
                                         "--spp", "2", "--ao-samples", "4"});
        ASSERT_EQ(run.exit_code, 0) << describe(run);
        const ReadBack image = read_png(out);
        EXPECT_EQ(image.width, 72);
        EXPECT_EQ(image.height, 40);
        EXPECT_EQ(image.components, 3);
        EXPECT_GT(pixels_unlike_corner(image), 50u) << "the duck is in the automatic view";
        EXPECT_NE(run.out.find("Mrays/s"), std::string::npos) << run.out;
        EXPECT_NE(run.out.find("cells visited mean"), std::string::npos) << run.out;
        // 72x40 cannot hold a heat legend: the tool says so, and says nothing else.
        const bool heat = mode.rfind("heat", 0) == 0;
        EXPECT_EQ(run.err.find("error"), std::string::npos) << run.err;
        EXPECT_EQ(run.err.find("too small for the heat legend") != std::string::npos, heat)
            << run.err;
    }
}

TEST_F(SgRender, JsonDescribesTheRender)
{
    const fs::path out = scratch_ / "heat.png";
    const ToolRun run = render(out, {"--mode", "heat-triangles", "--width", "320", "--height",
                                     "240", "--spp", "3", "--heat-max", "20", "--json"});
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const json j = json::parse(run.out);
    EXPECT_EQ(j.at("mode"), "heat-triangles");
    EXPECT_EQ(j.at("image").at("width"), 320);
    EXPECT_EQ(j.at("image").at("height"), 240);
    EXPECT_EQ(j.at("image").at("format"), "PNG");
    EXPECT_EQ(j.at("image").at("bytes"), fs::file_size(out));
    EXPECT_EQ(j.at("rays").at("primary"), 320 * 240 * 3);
    EXPECT_EQ(j.at("rays").at("secondary"), 0);
    EXPECT_EQ(j.at("heat").at("scale_max"), 20.0);
    EXPECT_EQ(j.at("heat").at("automatic"), false);
    EXPECT_EQ(j.at("heat").at("drawn"), true);
    EXPECT_EQ(j.at("camera").at("automatic"), true);
    EXPECT_GE(j.at("primary").at("triangles_tested_max").get<double>(),
              j.at("primary").at("triangles_tested_mean").get<double>());
    EXPECT_GT(j.at("mrays_per_second").get<double>(), 0.0);
    const ReadBack image = read_png(out);
    EXPECT_EQ(image.width, 320);
}

TEST_F(SgRender, CameraFlagsDecideWhatIsSeen)
{
    // The automatic camera's flags, printed in the JSON, aim at the duck; turned around, the
    // same eye sees nothing but background.
    const ToolRun automatic = render(scratch_ / "auto.png", {"--width", "48", "--height", "36",
                                                             "--json"});
    ASSERT_EQ(automatic.exit_code, 0) << describe(automatic);
    const json camera = json::parse(automatic.out).at("camera");
    const auto text = [](const json& v) {
        return std::to_string(v[0].get<float>()) + "," + std::to_string(v[1].get<float>()) +
               "," + std::to_string(v[2].get<float>());
    };
    const json eye = camera.at("eye");
    const json look_at = camera.at("look_at");
    json away = json::array();
    for (int k = 0; k < 3; ++k)
        away.push_back(2.0f * eye[k].get<float>() - look_at[k].get<float>());

    const ToolRun towards = render(scratch_ / "towards.png",
                                   {"--width", "48", "--height", "36", "--eye", text(eye),
                                    "--look-at", text(look_at)});
    ASSERT_EQ(towards.exit_code, 0) << describe(towards);
    EXPECT_GT(pixels_unlike_corner(read_png(scratch_ / "towards.png")), 50u);

    const ToolRun turned = render(scratch_ / "away.png", {"--width", "48", "--height", "36",
                                                          "--eye", text(eye), "--look-at",
                                                          text(away)});
    ASSERT_EQ(turned.exit_code, 0) << describe(turned);
    EXPECT_EQ(pixels_unlike_corner(read_png(scratch_ / "away.png")), 0u);
}

TEST_F(SgRender, ThreadCountDoesNotChangeTheFile)
{
    for (const std::string threads : {"1", "2"}) {
        const ToolRun run = render(scratch_ / ("path" + threads + ".png"),
                                   {"--mode", "path", "--width", "40", "--height", "30", "--spp",
                                    "2", "--threads", threads, "--seed", "7"});
        ASSERT_EQ(run.exit_code, 0) << describe(run);
    }
    EXPECT_EQ(read_text(scratch_ / "path1.png"), read_text(scratch_ / "path2.png"));
}

TEST_F(SgRender, ExtensionChoosesTheWriter)
{
    const fs::path out = scratch_ / "duck.ppm";
    const ToolRun run = render(out, {"--width", "30", "--height", "20"});
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    vtkNew<vtkPNMReader> reader;
    const ReadBack image = read_back(reader, out);
    EXPECT_EQ(image.width, 30);
    EXPECT_EQ(image.height, 20);
    EXPECT_EQ(read_text(out).substr(0, 2), "P6") << "binary PPM";
}

TEST_F(SgRender, HelpListsModesAndExitCodes)
{
    const ToolRun run = run_tool(SG_RENDER_EXE, {"--help"}, scratch_);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    for (const char* text : {"shaded", "ao", "path", "heat-cells", "heat-triangles", "--eye",
                             "--look-at", "--spp", "--heat-max", "Exit codes:", "2  bad input"})
        EXPECT_NE(run.out.find(text), std::string::npos) << text;
}

/// Rows and columns of the pixels unlike the top-left one: the scene's outline in the image.
struct Outline {
    int width = 0;
    int height = 0;
};
Outline outline_of(const ReadBack& image)
{
    const auto n = static_cast<std::size_t>(image.components);
    int x_lo = image.width, x_hi = -1, y_lo = image.height, y_hi = -1;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const std::size_t i =
                (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                 static_cast<std::size_t>(x)) *
                n;
            const auto first = image.bytes.begin();
            if (std::equal(first, first + static_cast<std::ptrdiff_t>(n),
                           first + static_cast<std::ptrdiff_t>(i)))
                continue;
            x_lo = std::min(x_lo, x);
            x_hi = std::max(x_hi, x);
            y_lo = std::min(y_lo, y);
            y_hi = std::max(y_hi, y);
        }
    return x_hi < 0 ? Outline{} : Outline{x_hi - x_lo + 1, y_hi - y_lo + 1};
}

TEST(SgRenderFraming, AutomaticFramingHonoursUpAndFillsTheImage)
{
    // A pillar standing on the z = 0 plane of a z-up scene: 1 x 1 wide, 6 tall along z.
    ScratchDir scratch;
    Mesh pillar;
    for (int corner = 0; corner < 8; ++corner)
        pillar.vertices.push_back({float(corner & 1), float((corner >> 1) & 1),
                                   6.0f * float((corner >> 2) & 1)});
    pillar.triangles = {{{0, 2, 1}}, {{1, 2, 3}}, {{4, 5, 6}}, {{5, 7, 6}}, {{0, 1, 4}},
                        {{1, 5, 4}}, {{2, 6, 3}}, {{3, 6, 7}}, {{0, 4, 2}}, {{2, 4, 6}},
                        {{1, 3, 5}}, {{3, 7, 5}}};
    const fs::path sg_file = scratch / "pillar.sg";
    write_sg_file(sg_file, SgContents{pillar, build_split_grid(pillar.view(), BuildConfig{}),
                                      "pillar"});

    const auto render = [&](const std::string& name, std::vector<std::string> extra) {
        std::vector<std::string> args = {sg_file.string(), "-o", (scratch / name).string(),
                                         "--width", "160", "--height", "120", "--json"};
        args.insert(args.end(), extra.begin(), extra.end());
        const ToolRun run = run_tool(SG_RENDER_EXE, args, scratch);
        EXPECT_EQ(run.exit_code, 0) << describe(run);
        return run;
    };
    const ToolRun z_up = render("z_up.png", {"--up", "0,0,1"});
    const json camera = json::parse(z_up.out).at("camera");
    EXPECT_EQ(camera.at("up"), json::parse("[0.0, 0.0, 1.0]"));
    EXPECT_EQ(camera.at("automatic"), true);
    EXPECT_GT(camera.at("eye")[2].get<double>(), camera.at("look_at")[2].get<double>())
        << "seen from above the ground plane";

    const Outline upright = outline_of(read_png(scratch / "z_up.png"));
    EXPECT_GE(upright.height, 108) << "the pillar fills the image's height (95% of 120)";
    EXPECT_LE(upright.height, 118) << "with a margin";
    EXPECT_GT(upright.height, 2 * upright.width) << "and stands upright";

    // The same scene with the default +y up is not upright: the pillar lies across the image.
    const ToolRun y_up = render("y_up.png", {});
    const Outline lying = outline_of(read_png(scratch / "y_up.png"));
    EXPECT_LT(lying.height, 2 * lying.width);
}

// --- bad input: the documented exit code, one line on stderr, and no image ---

class SgRenderRefuses : public SgRender {
protected:
    void expect_refused(const std::vector<std::string>& args, int exit_code,
                        const std::string& named, const fs::path& out)
    {
        const ToolRun run = run_tool(SG_RENDER_EXE, args, scratch_);
        EXPECT_EQ(run.exit_code, exit_code) << describe(run);
        EXPECT_EQ(line_count(run.err), 1u) << run.err;
        EXPECT_EQ(run.err.rfind("error: ", 0), 0u) << run.err;
        EXPECT_NE(run.err.find(named), std::string::npos) << "stderr must name " << named
                                                          << ":\n" << run.err;
        EXPECT_EQ(run.out, "");
        EXPECT_FALSE(fs::exists(out));
        // Temporary files are named ".<output>.tmp-<pid>-<random>" (sg::OutputFile).
        for (const auto& entry : fs::directory_iterator(scratch_.path()))
            EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos)
                << entry.path() << ": temporary file left behind";
    }
    void expect_usage_error(std::vector<std::string> extra, const std::string& named)
    {
        std::vector<std::string> args = {sg_file_.string(), "-o", out_.string()};
        args.insert(args.end(), extra.begin(), extra.end());
        expect_refused(args, 1, named, out_);
    }
    fs::path out_ = scratch_ / "out.png";
};

TEST_F(SgRenderRefuses, BadFlagValuesAreUsageErrors)
{
    expect_usage_error({"--mode", "wireframe"}, "wireframe");
    expect_usage_error({"--width", "0"}, "0");
    expect_usage_error({"--height", "20000"}, "20000");
    expect_usage_error({"--spp", "-1"}, "--spp");
    expect_usage_error({"--fov", "180"}, "--fov");
    expect_usage_error({"--ao-distance", "nan"}, "nan");
    expect_usage_error({"--bounces", "65"}, "65");
    expect_usage_error({"--eye", "1,2"}, "1,2");
    expect_usage_error({"--look-at", "1,2,x"}, "1,2,x");
    expect_usage_error({"--eye", "1,1,1", "--look-at", "1,1,1"}, "eye and look-at must differ");
    expect_usage_error({"--eye", "0,5,0", "--look-at", "0,0,0"}, "parallel");
    expect_usage_error({"--no-such-flag"}, "no-such-flag");
}

TEST_F(SgRenderRefuses, CameraCompletedFromTheSceneIsCheckedToo)
{
    // The eye comes from automatic framing, which always looks from 19 degrees above the
    // plane perpendicular to --up; a --look-at straight above any eye the scene gives makes
    // the view parallel to up, which is only found after the scene is read and is still a
    // usage error.
    expect_usage_error({"--look-at", "0,1e30,0"}, "parallel");
    expect_usage_error({"--look-at", "0,-1e30,0"}, "parallel");
}

TEST_F(SgRenderRefuses, UnsupportedExtensionIsAUsageError)
{
    expect_refused({sg_file_.string(), "-o", (scratch_ / "out.gif").string()}, 1, "out.gif",
                   scratch_ / "out.gif");
}

TEST_F(SgRenderRefuses, MissingSgFile)
{
    expect_refused({(scratch_ / "missing.sg").string(), "-o", out_.string()}, 2, "missing.sg",
                   out_);
}

TEST_F(SgRenderRefuses, TruncatedSgFile)
{
    const std::string bytes = read_text(sg_file_);
    write_text(scratch_ / "half.sg", bytes.substr(0, bytes.size() / 2));
    expect_refused({(scratch_ / "half.sg").string(), "-o", out_.string()}, 2, "half.sg", out_);
}

TEST_F(SgRenderRefuses, MeshInsteadOfSgFile)
{
    const fs::path mesh = assimp_model("OFF/Cube.off");
    expect_refused({mesh.string(), "-o", out_.string()}, 2, "Cube.off", out_);
}

TEST_F(SgRenderRefuses, MissingOutputFolder)
{
    const fs::path out = scratch_ / "no" / "such" / "out.png";
    expect_refused({sg_file_.string(), "-o", out.string()}, 2, "does not exist", out);
}

TEST_F(SgRenderRefuses, FailureLeavesAnExistingImageUntouched)
{
    write_text(out_, "previous image");
    const ToolRun run = run_tool(SG_RENDER_EXE,
                                 {(scratch_ / "missing.sg").string(), "-o", out_.string()},
                                 scratch_);
    EXPECT_EQ(run.exit_code, 2);
    EXPECT_EQ(read_text(out_), "previous image");
}

}  // namespace
}  // namespace sg::test

#endif  // SG_RENDER_EXE
