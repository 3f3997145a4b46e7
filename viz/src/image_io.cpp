#include "splitgrid/viz/image.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <string_view>
#include <system_error>
#include <utility>

#include <fcntl.h>
#include <unistd.h>

#include "splitgrid/error.hpp"

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

/// Reserves a fresh name beside `target` by creating the file (O_EXCL, mode 0666 less the
/// umask, so the final file gets the permissions of any new file); the writer then fills it.
fs::path reserve_temporary(const fs::path& target)
{
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    std::random_device random;
    int error = 0;
    for (int attempt = 0; attempt < 32; ++attempt) {
        char suffix[20];
        std::snprintf(suffix, sizeof suffix, "%08x%08x", random(), random());
        // Built by appending: GCC 12 warns falsely (-Wrestrict) on chained string '+'.
        std::string leaf(".");
        leaf.append(target.filename().string()).append(".").append(suffix).append(".tmp");
        fs::path candidate = folder / leaf;
        const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) {
            ::close(fd);
            return candidate;
        }
        error = errno;
        if (error != EEXIST) break;
    }
    throw IoError(target.string() + ": cannot create a temporary file in " + folder.string() +
                  ": " + std::error_code(error, std::generic_category()).message());
}

/// Removes the temporary file unless it was renamed into place.
class TemporaryName {
public:
    explicit TemporaryName(fs::path path) : path_(std::move(path)) {}
    TemporaryName(const TemporaryName&) = delete;
    TemporaryName& operator=(const TemporaryName&) = delete;
    ~TemporaryName()
    {
        if (path_.empty()) return;
        std::error_code ignored;
        fs::remove(path_, ignored);
    }
    [[nodiscard]] const fs::path& path() const noexcept { return path_; }
    void release() noexcept { path_.clear(); }

private:
    fs::path path_;
};

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

void write_image(const fs::path& path, const RgbImage& image)
{
    const std::optional<ImageFormat> format = image_format_for(path);
    if (!format)
        throw ConfigError(path.string() + ": unsupported image extension (use one of " +
                          supported_image_extensions() + ")");
    if (image.width <= 0 || image.height <= 0 ||
        image.rgb.size() != static_cast<std::size_t>(image.width) *
                                static_cast<std::size_t>(image.height) * 3u)
        throw ConfigError(path.string() + ": the image is empty or its pixel buffer has the "
                                          "wrong size");
    const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(folder, ec))
        throw IoError(path.string() + ": folder " + folder.string() + " does not exist");

    TemporaryName temporary(reserve_temporary(path));
    vtkNew<vtkImageData> data = to_vtk(image);
    vtkSmartPointer<vtkImageWriter> writer = make_writer(*format);
    writer->SetFileName(temporary.path().c_str());
    writer->SetInputData(data);
    unsigned long error_code = vtkErrorCode::NoError;
    {
        const MuteVtkWarnings mute;
        writer->Write();
        error_code = writer->GetErrorCode();
    }
    if (error_code != vtkErrorCode::NoError)
        throw IoError(path.string() + ": the " + format_name(*format) +
                      " writer failed: " + vtkErrorCode::GetStringFromErrorCode(error_code));
    fs::rename(temporary.path(), path, ec);
    if (ec) throw IoError(path.string() + ": cannot rename the temporary file: " + ec.message());
    temporary.release();
}

}  // namespace sg
