#include "splitgrid/viz/image.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <string_view>

#include "splitgrid/error.hpp"
#include "splitgrid/formats/output_file.hpp"

#include <vtkBMPWriter.h>
#include <vtkErrorCode.h>
#include <vtkImageData.h>
#include <vtkJPEGWriter.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPNMWriter.h>
#include <vtkSmartPointer.h>

namespace sg {
namespace {

namespace fs = std::filesystem;

struct Extension {
    std::string_view text;
    ImageFormat format;
};
constexpr std::array<Extension, 6> extensions{{
    {".png", ImageFormat::png},
    {".jpg", ImageFormat::jpeg},
    {".jpeg", ImageFormat::jpeg},
    {".ppm", ImageFormat::pnm},
    {".pnm", ImageFormat::pnm},
    {".bmp", ImageFormat::bmp},
}};

vtkSmartPointer<vtkImageWriter> make_writer(ImageFormat format)
{
    switch (format) {
    case ImageFormat::png: return vtkSmartPointer<vtkPNGWriter>::New();
    case ImageFormat::jpeg: {
        auto writer = vtkSmartPointer<vtkJPEGWriter>::New();
        writer->SetQuality(95);
        return writer;
    }
    case ImageFormat::pnm: return vtkSmartPointer<vtkPNMWriter>::New();
    case ImageFormat::bmp: return vtkSmartPointer<vtkBMPWriter>::New();
    }
    return nullptr;
}

/// VTK images start at the bottom-left corner, RgbImage at the top-left: rows are flipped.
vtkNew<vtkImageData> to_vtk(const RgbImage& image)
{
    vtkNew<vtkImageData> data;
    data->SetDimensions(image.width, image.height, 1);
    data->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
    auto* pixels = static_cast<unsigned char*>(data->GetScalarPointer());
    const auto row_bytes = static_cast<std::size_t>(image.width) * 3u;
    for (int y = 0; y < image.height; ++y) {
        const std::size_t vtk_row = static_cast<std::size_t>(image.height - 1 - y);
        std::memcpy(pixels + vtk_row * row_bytes,
                    image.rgb.data() + static_cast<std::size_t>(y) * row_bytes, row_bytes);
    }
    return data;
}

/// VTK reports writer failures on its own output window (several lines on stderr) as well as
/// in the error code; the caller turns the code into one exception, so the window is muted
/// while the writer runs.
class MuteVtkWarnings {
public:
    MuteVtkWarnings() : previous_(vtkObject::GetGlobalWarningDisplay())
    {
        vtkObject::GlobalWarningDisplayOff();
    }
    MuteVtkWarnings(const MuteVtkWarnings&) = delete;
    MuteVtkWarnings& operator=(const MuteVtkWarnings&) = delete;
    ~MuteVtkWarnings() { vtkObject::SetGlobalWarningDisplay(previous_); }

private:
    int previous_;
};

}  // namespace

std::optional<ImageFormat> image_format_for(const fs::path& path)
{
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    for (const Extension& e : extensions)
        if (e.text == extension) return e.format;
    return std::nullopt;
}

const char* format_name(ImageFormat format) noexcept
{
    switch (format) {
    case ImageFormat::png: return "PNG";
    case ImageFormat::jpeg: return "JPEG";
    case ImageFormat::pnm: return "PPM";
    case ImageFormat::bmp: return "BMP";
    }
    return "?";
}

std::string supported_image_extensions()
{
    std::string list;
    for (const Extension& e : extensions) {
        if (!list.empty()) list += ", ";
        list += e.text;
    }
    return list;
}

namespace {

/// Refuses what no writer can write, before any file is touched.
void check_writable(const fs::path& path, const RgbImage& image)
{
    if (!image_format_for(path))
        throw ConfigError(path.string() + ": unsupported image extension (use one of " +
                          supported_image_extensions() + ")");
    if (image.width <= 0 || image.height <= 0 ||
        image.rgb.size() != static_cast<std::size_t>(image.width) *
                                static_cast<std::size_t>(image.height) * 3u)
        throw ConfigError(path.string() + ": the image is empty or its pixel buffer has the "
                                          "wrong size");
}

}  // namespace

void write_image(const fs::path& path, const RgbImage& image)
{
    check_writable(path, image);
    OutputFile output(path);
    write_image(output, image);
}

void write_image(OutputFile& output, const RgbImage& image)
{
    const fs::path& path = output.target();
    check_writable(path, image);
    const ImageFormat format = *image_format_for(path);
    vtkNew<vtkImageData> data = to_vtk(image);
    vtkSmartPointer<vtkImageWriter> writer = make_writer(format);
    writer->SetFileName(output.temporary_path().c_str());
    writer->SetInputData(data);
    unsigned long error_code = vtkErrorCode::NoError;
    {
        const MuteVtkWarnings mute;
        writer->Write();
        error_code = writer->GetErrorCode();
    }
    if (error_code != vtkErrorCode::NoError)
        throw IoError(path.string() + ": the " + format_name(format) +
                      " writer failed: " + vtkErrorCode::GetStringFromErrorCode(error_code));
    output.commit_written();
}

}  // namespace sg
