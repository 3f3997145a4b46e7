#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace sg {

class OutputFile;

/// One 8-bit sRGB colour.
struct Rgb8 {
    std::uint8_t r = 0;
    std::uint8_t g = 0;
    std::uint8_t b = 0;
    friend constexpr bool operator==(const Rgb8&, const Rgb8&) = default;
};

/// An 8-bit RGB image in memory: rows from the top of the picture down, pixels from left to
/// right, three bytes (r, g, b) per pixel, no padding. Pixel (x, y) counts from the top-left
/// corner, as sg::PrimaryRays does; the image writers flip rows into the files' own order.
struct RgbImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;  ///< width * height * 3 bytes

    RgbImage() = default;
    /// A black image. Precondition: width, height >= 0.
    RgbImage(int width_, int height_)
        : width(width_), height(height_),
          rgb(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) * 3u, 0)
    {
    }

    [[nodiscard]] Rgb8 at(int x, int y) const noexcept
    {
        const std::size_t i = offset(x, y);
        return {rgb[i], rgb[i + 1], rgb[i + 2]};
    }
    void set(int x, int y, Rgb8 colour) noexcept
    {
        const std::size_t i = offset(x, y);
        rgb[i] = colour.r;
        rgb[i + 1] = colour.g;
        rgb[i + 2] = colour.b;
    }
    friend bool operator==(const RgbImage&, const RgbImage&) = default;

private:
    [[nodiscard]] std::size_t offset(int x, int y) const noexcept
    {
        return (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                static_cast<std::size_t>(x)) *
               3u;
    }
};

/// Image file formats written through VTK's image writers. TIFF is left out: VTK 9.1's TIFF
/// reader ignores the orientation tag its writer sets and reads those files upside down, so
/// they could not be checked by reading them back.
enum class ImageFormat {
    png,   ///< .png (vtkPNGWriter), lossless: the format for renders and heat maps
    jpeg,  ///< .jpg, .jpeg (vtkJPEGWriter, quality 95), lossy
    pnm,   ///< .ppm, .pnm (vtkPNMWriter, binary PPM)
    bmp,   ///< .bmp (vtkBMPWriter)
};

/// The format named by the extension of `path` (letter case ignored), or nothing for an
/// extension no writer handles.
[[nodiscard]] std::optional<ImageFormat> image_format_for(const std::filesystem::path& path);

/// "PNG", "JPEG", ... for messages.
[[nodiscard]] const char* format_name(ImageFormat format) noexcept;

/// The accepted extensions, for messages and --help: ".png, .jpg, .jpeg, ...".
[[nodiscard]] std::string supported_image_extensions();

/// Writes `image` to `path` with VTK's writer for the extension, atomically: the writer fills
/// a temporary file in the same folder (OutputFile: ".<name>.tmp-<pid>-<random>"), which is
/// renamed over `path` only when the writer reports success; on any failure the temporary
/// file is removed and an existing file at `path` is left as it was.
/// Throws ConfigError for an extension no writer handles or an empty image, IoError
/// "<path>: <reason>" when the folder is missing or the writer or the rename fails.
void write_image(const std::filesystem::path& path, const RgbImage& image);

/// The same into an output reserved before the render (so that an unwritable folder is found
/// first), which it commits. The format follows output.target()'s extension.
void write_image(OutputFile& output, const RgbImage& image);

}  // namespace sg
