// Point files and point result files (docs/FORMAT.md, section 6).

#include "splitgrid/formats/point_file.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
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

/// One closest point on disk (28 bytes): the triangle id (0xFFFFFFFF: none), then float32
/// distance, u, v and the point's x, y, z. Every field is 4 bytes, so every record (at 16 + 28 i)
/// is 4-byte aligned and numpy's structured dtype needs no padding.
struct ClosestPointRecord {
    std::uint32_t triangle;
    float distance;
    float u;
    float v;
    std::array<float, 3> xyz;
};
static_assert(sizeof(ClosestPointRecord) == 7 * 4 &&
                  std::is_trivially_copyable_v<ClosestPointRecord>,
              "ClosestPointRecord must be a uint32 and 6 packed float32 (docs/FORMAT.md)");

constexpr std::string_view point_magic = "SGPTS001";
constexpr std::string_view occupancy_magic = "SGOCC001";
constexpr std::string_view distance_magic = "SGDST001";
constexpr std::string_view signed_distance_magic = "SGSDF001";
constexpr std::string_view closest_point_magic = "SGCLP001";
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

void write_floats(OutputFile& output, std::string_view magic, std::span<const float> values)
{
    output.commit(detail::encode_records<float>(magic, values.size(),
                                                [&](std::size_t i) { return values[i]; }));
}

/// The values of a file of one float32 per point; a value for which `why_bad` returns a
/// reason is refused: "<path>: point 1 has <kind> -0.500000, <reason> (at byte offset 20)".
template <class WhyBad>
std::vector<float> read_floats(const std::filesystem::path& path, std::string_view magic,
                               std::string_view kind, WhyBad why_bad)
{
    const detail::RecordFile file = detail::read_record_file(path, magic, kind, sizeof(float));
    std::vector<float> values(file.count);
    for (std::size_t i = 0; i < file.count; ++i) {
        values[i] = file.record<float>(i);
        if (const char* reason = why_bad(values[i]))
            throw FormatError(path.string() + ": point " + std::to_string(i) + " has " +
                              std::string(kind) + " " + std::to_string(values[i]) + ", " +
                              reason + " (at byte offset " +
                              std::to_string(detail::RecordFile::offset_of(i, sizeof(float))) +
                              ")");
    }
    return values;
}

/// Why a closest point record is inconsistent, or null.
const char* why_bad_closest(const ClosestPointRecord& r) noexcept
{
    if (r.triangle != invalid_triangle)
        return std::isfinite(r.distance) && r.distance >= 0.0f
                   ? nullptr
                   : "expected a finite, non-negative distance for a triangle";
    return std::isnan(r.distance) || r.distance == std::numeric_limits<float>::infinity()
               ? nullptr
               : "expected +infinity or NaN without a triangle (id 0xFFFFFFFF)";
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
    write_floats(output, occupancy_magic, occupancy);
}

void write_occupancy_file(const std::filesystem::path& path, std::span<const float> occupancy)
{
    OutputFile output(path);
    write_occupancy_file(output, occupancy);
}

std::vector<float> read_occupancy_file(const std::filesystem::path& path)
{
    return read_floats(path, occupancy_magic, "occupancy", [](float value) -> const char* {
        return value == 0.0f || value == 1.0f || std::isnan(value) ? nullptr
                                                                   : "expected 0, 1 or NaN";
    });
}

void write_distance_file(OutputFile& output, std::span<const float> distances)
{
    write_floats(output, distance_magic, distances);
}

void write_distance_file(const std::filesystem::path& path, std::span<const float> distances)
{
    OutputFile output(path);
    write_distance_file(output, distances);
}

std::vector<float> read_distance_file(const std::filesystem::path& path)
{
    return read_floats(path, distance_magic, "distance", [](float value) -> const char* {
        return value < 0.0f ? "expected a distance >= 0, +infinity or NaN" : nullptr;
    });
}

void write_signed_distance_file(OutputFile& output, std::span<const float> signed_distances)
{
    write_floats(output, signed_distance_magic, signed_distances);
}

void write_signed_distance_file(const std::filesystem::path& path,
                                std::span<const float> signed_distances)
{
    OutputFile output(path);
    write_signed_distance_file(output, signed_distances);
}

std::vector<float> read_signed_distance_file(const std::filesystem::path& path)
{
    return read_floats(path, signed_distance_magic, "signed distance",
                       [](float value) -> const char* {
                           return value == -std::numeric_limits<float>::infinity()
                                      ? "expected a finite value, +infinity or NaN"
                                      : nullptr;
                       });
}

void write_closest_point_file(OutputFile& output, std::span<const ClosestPoint> closest)
{
    constexpr float nan = std::numeric_limits<float>::quiet_NaN();
    output.commit(detail::encode_records<ClosestPointRecord>(
        closest_point_magic, closest.size(), [&](std::size_t i) {
            const ClosestPoint& c = closest[i];
            if (!c.is_hit()) return ClosestPointRecord{invalid_triangle, c.distance, 0.0f, 0.0f,
                                                       {nan, nan, nan}};
            return ClosestPointRecord{c.triangle, c.distance, c.u, c.v,
                                      {c.point.x, c.point.y, c.point.z}};
        }));
}

void write_closest_point_file(const std::filesystem::path& path,
                              std::span<const ClosestPoint> closest)
{
    OutputFile output(path);
    write_closest_point_file(output, closest);
}

std::vector<ClosestPoint> read_closest_point_file(const std::filesystem::path& path)
{
    const detail::RecordFile file = detail::read_record_file(
        path, closest_point_magic, "closest point", sizeof(ClosestPointRecord));
    std::vector<ClosestPoint> closest(file.count);
    for (std::size_t i = 0; i < file.count; ++i) {
        const auto r = file.record<ClosestPointRecord>(i);
        if (const char* reason = why_bad_closest(r))
            throw FormatError(path.string() + ": point " + std::to_string(i) + " has triangle " +
                              std::to_string(r.triangle) + " and distance " +
                              std::to_string(r.distance) + ", " + reason + " (at byte offset " +
                              std::to_string(detail::RecordFile::offset_of(
                                  i, sizeof(ClosestPointRecord))) +
                              ")");
        closest[i] = {r.distance, r.triangle, r.u, r.v, {r.xyz[0], r.xyz[1], r.xyz[2]}};
    }
    return closest;
}

}  // namespace sg
