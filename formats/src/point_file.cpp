// Point files and point result files (docs/FORMAT.md, section 6).

#include "splitgrid/formats/point_file.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "file_bytes.hpp"
#include "record_file.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/output_file.hpp"
#include "splitgrid/formats/point_text.hpp"

namespace sg {
namespace {

/// One point on disk (12 bytes): float32 x, y, z.
struct PointRecord {
    std::array<float, 3> xyz;
};
static_assert(sizeof(PointRecord) == 3 * 4 && std::is_trivially_copyable_v<PointRecord>,
              "PointRecord must be 3 packed float32 (docs/FORMAT.md)");

constexpr std::string_view point_magic = "SGPTS001";
constexpr std::string_view occupancy_magic = "SGOCC001";
/// The bytes of the point magic that tell a point file from text: "SGPTS".
constexpr std::size_t point_kind_bytes = 5;

std::vector<Vec3f> decode_points(const detail::RecordFile& file)
{
    std::vector<Vec3f> points(file.count);
    for (std::size_t i = 0; i < file.count; ++i) {
        const auto r = file.record<PointRecord>(i);
        points[i] = {r.xyz[0], r.xyz[1], r.xyz[2]};
    }
    return points;
}

/// Whether `bytes` start like a point file, on as many bytes as they have.
bool looks_like_point_file(const std::vector<std::uint8_t>& bytes)
{
    const std::size_t n = std::min(bytes.size(), point_kind_bytes);
    return n > 0 && std::equal(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n),
                               point_magic.begin());
}

}  // namespace

void write_point_file(OutputFile& output, std::span<const Vec3f> points)
{
    output.commit(detail::encode_records<PointRecord>(point_magic, points.size(),
                                                      [&](std::size_t i) {
                                                          const Vec3f p = points[i];
                                                          return PointRecord{{p.x, p.y, p.z}};
                                                      }));
}

void write_point_file(const std::filesystem::path& path, std::span<const Vec3f> points)
{
    OutputFile output(path);
    write_point_file(output, points);
}

std::vector<Vec3f> read_point_file(const std::filesystem::path& path)
{
    return decode_points(detail::read_record_file(path, point_magic, "point", sizeof(PointRecord)));
}

LoadedPoints read_points(const std::filesystem::path& path)
{
    // The file is read once here; a point file is read again by read_point_file, whose checks
    // and messages stay the one version of them.
    const std::vector<std::uint8_t> bytes = detail::read_file_bytes(path);
    if (looks_like_point_file(bytes)) return {read_point_file(path), PointSource::binary};
    const auto control = std::find_if(bytes.begin(), bytes.end(), [](std::uint8_t c) {
        return (c < 0x20 && c != '\t' && c != '\n' && c != '\r') || c == 0x7F;
    });
    if (control != bytes.end()) {
        char byte[8];
        std::snprintf(byte, sizeof byte, "0x%02X", *control);
        throw FormatError(path.string() + ": neither a point file (magic \"SGPTS001\") nor text: "
                                          "byte " + byte + " at byte offset " +
                          std::to_string(control - bytes.begin()));
    }
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    return {parse_point_text(text, path.string()), PointSource::text};
}

void write_occupancy_file(OutputFile& output, std::span<const float> occupancy)
{
    output.commit(detail::encode_records<float>(occupancy_magic, occupancy.size(),
                                                [&](std::size_t i) { return occupancy[i]; }));
}

void write_occupancy_file(const std::filesystem::path& path, std::span<const float> occupancy)
{
    OutputFile output(path);
    write_occupancy_file(output, occupancy);
}

std::vector<float> read_occupancy_file(const std::filesystem::path& path)
{
    const detail::RecordFile file =
        detail::read_record_file(path, occupancy_magic, "occupancy", sizeof(float));
    std::vector<float> values(file.count);
    for (std::size_t i = 0; i < file.count; ++i) {
        values[i] = file.record<float>(i);
        if (values[i] != 0.0f && values[i] != 1.0f && !std::isnan(values[i]))
            throw FormatError(
                path.string() + ": point " + std::to_string(i) + " has occupancy " +
                std::to_string(values[i]) + ", expected 0, 1 or NaN (at byte offset " +
                std::to_string(detail::RecordFile::offset_of(i, sizeof(float))) + ")");
    }
    return values;
}

}  // namespace sg
