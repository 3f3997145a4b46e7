// write_image read back with VTK's reader for each format (independent of the writer's code
// path in the library), orientation, atomicity and refusals.

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "apps/app_test_support.hpp"
#include "render_test_support.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/viz/image.hpp"

#include <gtest/gtest.h>
#include <vtkBMPReader.h>
#include <vtkJPEGReader.h>
#include <vtkPNMReader.h>

namespace sg::test {
namespace {

namespace fs = std::filesystem;

/// A smooth gradient with a pure red top-left and a pure blue bottom-right pixel, so a
/// flipped or mirrored image is caught, and smooth enough for JPEG to keep it close.
RgbImage test_pattern(int width, int height)
{
    RgbImage image(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            image.set(x, y, {static_cast<std::uint8_t>(x * 255 / (width - 1)),
                             static_cast<std::uint8_t>(y * 255 / (height - 1)), 128});
    image.set(0, 0, {255, 0, 0});
    image.set(width - 1, height - 1, {0, 0, 255});
    return image;
}

std::vector<fs::path> files_in(const fs::path& folder)
{
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(folder)) files.push_back(entry.path());
    return files;
}

TEST(ImageIo, LosslessFormatsReadBackExactly)
{
    ScratchDir scratch;
    const RgbImage image = test_pattern(37, 21);  // odd sizes catch row padding mistakes
    struct Case {
        std::string name;
        vtkSmartPointer<vtkImageReader2> reader;
    };
    const std::vector<Case> cases = {
        {"a.png", vtkSmartPointer<vtkPNGReader>::New()},
        {"b.PNG", vtkSmartPointer<vtkPNGReader>::New()},
        {"e.ppm", vtkSmartPointer<vtkPNMReader>::New()},
        {"f.pnm", vtkSmartPointer<vtkPNMReader>::New()},
        {"g.bmp", vtkSmartPointer<vtkBMPReader>::New()},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        write_image(scratch / c.name, image);
        const RgbImage back = read_with(c.reader, scratch / c.name);
        EXPECT_EQ(back.width, 37);
        EXPECT_EQ(back.height, 21);
        EXPECT_EQ(back.at(0, 0), (Rgb8{255, 0, 0})) << "top-left pixel";
        EXPECT_TRUE(back == image);
    }
}

TEST(ImageIo, JpegReadsBackClose)
{
    ScratchDir scratch;
    const RgbImage image = test_pattern(64, 48);
    for (const char* name : {"a.jpg", "b.jpeg"}) {
        write_image(scratch / name, image);
        vtkNew<vtkJPEGReader> reader;
        const RgbImage back = read_with(reader, scratch / name);
        ASSERT_EQ(back.width, 64);
        ASSERT_EQ(back.height, 48);
        double error = 0.0;
        for (std::size_t i = 0; i < image.rgb.size(); ++i)
            error += std::abs(int(image.rgb[i]) - int(back.rgb[i]));
        EXPECT_LT(error / static_cast<double>(image.rgb.size()), 3.0) << name;
        // Orientation survives compression: the top rows are dark in green, the bottom light.
        EXPECT_LT(back.at(32, 2).g, 40);
        EXPECT_GT(back.at(32, 45).g, 215);
    }
}

TEST(ImageIo, ReplacesAnExistingFileAndLeavesNoTemporaryFile)
{
    ScratchDir scratch;
    write_text(scratch / "out.png", "old contents");
    write_image(scratch / "out.png", test_pattern(8, 8));
    EXPECT_TRUE(read_png(scratch / "out.png") == test_pattern(8, 8));
    EXPECT_EQ(files_in(scratch.path()).size(), 1u);
}

TEST(ImageIo, UnsupportedExtensionIsRefusedBeforeWriting)
{
    ScratchDir scratch;
    EXPECT_THROW(write_image(scratch / "image.gif", test_pattern(4, 4)), ConfigError);
    EXPECT_THROW(write_image(scratch / "image", test_pattern(4, 4)), ConfigError);
    EXPECT_FALSE(image_format_for("x.webp").has_value());
    EXPECT_FALSE(image_format_for("x.tif").has_value());
    EXPECT_EQ(image_format_for("x.JPG"), ImageFormat::jpeg);
    EXPECT_TRUE(files_in(scratch.path()).empty());
}

TEST(ImageIo, MissingFolderIsAnIoError)
{
    ScratchDir scratch;
    EXPECT_THROW(write_image(scratch / "no" / "such.png", test_pattern(4, 4)), IoError);
    EXPECT_TRUE(files_in(scratch.path()).empty());
}

TEST(ImageIo, FailedRenameKeepsWhatWasThereAndCleansUp)
{
    // A non-empty folder cannot be replaced by a file: the rename fails after the writer
    // has written the temporary file, which must then be removed.
    ScratchDir scratch;
    fs::create_directory(scratch / "taken.png");
    write_text(scratch / "taken.png" / "keep", "x");
    EXPECT_THROW(write_image(scratch / "taken.png", test_pattern(4, 4)), IoError);
    EXPECT_TRUE(fs::is_directory(scratch / "taken.png"));
    EXPECT_EQ(files_in(scratch.path()).size(), 1u);
}

TEST(ImageIo, EmptyImageIsRefused)
{
    ScratchDir scratch;
    EXPECT_THROW(write_image(scratch / "empty.png", RgbImage{}), ConfigError);
    RgbImage wrong(4, 4);
    wrong.rgb.pop_back();
    EXPECT_THROW(write_image(scratch / "wrong.png", wrong), ConfigError);
    EXPECT_TRUE(files_in(scratch.path()).empty());
}

}  // namespace
}  // namespace sg::test
