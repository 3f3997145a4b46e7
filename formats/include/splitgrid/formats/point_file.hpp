#pragma once

#include <filesystem>
#include <span>
#include <vector>

#include "splitgrid/closest_point.hpp"
#include "splitgrid/vec3.hpp"

namespace sg {

class OutputFile;

/// Point files and point result files (docs/FORMAT.md, section 6): the input and the answers
/// of sg-points, in the layout of the ray and hit files: 8 ASCII magic bytes, a little-endian
/// uint64 count, then one fixed-size record per point, one numpy.fromfile away.
///
/// Each kind of point query answer has a magic of its own, so a reader never takes one kind
/// for another and every file keeps the 16-byte header (docs/FORMAT.md, 6.6): "SGOCC001"
/// (occupancy), "SGDST001" (distance) and "SGSDF001" (signed distance), one float32 per point
/// each; "SGCLP001" (closest point), one 28-byte record per point.

/// Writes a point file: magic "SGPTS001", a uint64 count, then per point float32 x, y, z,
/// stored as given (NaN and infinities too), atomically into an output reserved earlier
/// (OutputFile), which it commits.
void write_point_file(OutputFile& output, std::span<const Vec3f> points);
/// The same to `path` (temporary file, then rename).
void write_point_file(const std::filesystem::path& path, std::span<const Vec3f> points);

/// Reads a point file. Throws FormatError "<path>: <what is wrong>" on a bad magic, a count
/// that does not match the file size (a truncated file); IoError if it cannot be read.
[[nodiscard]] std::vector<Vec3f> read_point_file(const std::filesystem::path& path);

/// How read_points found the points.
enum class PointSource {
    binary,  ///< a point file (SGPTS001)
    text,    ///< a text or CSV file (point_text.hpp)
};

/// Points with where they came from.
struct LoadedPoints {
    std::vector<Vec3f> points;
    PointSource source = PointSource::binary;
};

/// Reads a point file or a text file of points, told apart by the content: a file whose first
/// bytes are those of the magic "SGPTS001" (as many as it has, up to five: "SGPTS") is a point
/// file and read with read_point_file's checks, so a truncated one is refused as truncated;
/// any other file is text (read_point_text) if it holds no control byte but tab, CR and LF,
/// else refused with FormatError "<path>: neither a point file (SGPTS001) nor text ...".
[[nodiscard]] LoadedPoints read_points(const std::filesystem::path& path);

/// Writes an occupancy file: magic "SGOCC001", a uint64 count, then one float32 per point:
/// 1 inside, 0 outside, NaN for a point with a non-finite coordinate (compute_occupancy).
void write_occupancy_file(OutputFile& output, std::span<const float> occupancy);
/// The same to `path`.
void write_occupancy_file(const std::filesystem::path& path, std::span<const float> occupancy);

/// Reads an occupancy file with the checks of read_point_file, and refuses a value other than
/// 0, 1 or NaN (naming the point and its byte offset).
[[nodiscard]] std::vector<float> read_occupancy_file(const std::filesystem::path& path);

/// Writes a distance file: magic "SGDST001", a uint64 count, then one float32 per point: the
/// distance to the mesh (ClosestPoint::distance), +infinity beyond the query's max_distance,
/// NaN for a point with a non-finite coordinate.
void write_distance_file(OutputFile& output, std::span<const float> distances);
/// The same to `path`.
void write_distance_file(const std::filesystem::path& path, std::span<const float> distances);

/// Reads a distance file with the checks of read_point_file, and refuses a negative value
/// (naming the point and its byte offset): a distance file holds no sign.
[[nodiscard]] std::vector<float> read_distance_file(const std::filesystem::path& path);

/// Writes a signed distance file: magic "SGSDF001", a uint64 count, then one float32 per
/// point: the distance, negative inside the closed mesh (signed_distances), +infinity beyond
/// the query's max_distance, NaN for a point with a non-finite coordinate.
void write_signed_distance_file(OutputFile& output, std::span<const float> signed_distances);
/// The same to `path`.
void write_signed_distance_file(const std::filesystem::path& path,
                                std::span<const float> signed_distances);

/// Reads a signed distance file with the checks of read_point_file, and refuses -infinity,
/// which no query gives (beyond max_distance the answer is +infinity, whatever the side).
[[nodiscard]] std::vector<float> read_signed_distance_file(const std::filesystem::path& path);

/// Writes a closest point file: magic "SGCLP001", a uint64 count, then per point 28 bytes:
/// uint32 triangle id, float32 distance, u, v (barycentrics on the triangle), x, y, z (the
/// closest point): the first 16 bytes in the places of a hit file's triangle, t, u, v. A point
/// without an answer (beyond max_distance: distance +infinity; a non-finite point: NaN) has
/// triangle id 0xFFFFFFFF, u = v = 0 and x, y, z NaN, so that no script takes the origin for
/// a closest point.
void write_closest_point_file(OutputFile& output, std::span<const ClosestPoint> closest);
/// The same to `path`.
void write_closest_point_file(const std::filesystem::path& path,
                              std::span<const ClosestPoint> closest);

/// Reads a closest point file with the checks of read_point_file, and refuses a record whose
/// triangle id and distance disagree (a triangle with a distance that is not finite and
/// non-negative, or no triangle with a finite distance), naming the point and its byte
/// offset. Records are returned as stored: a point without an answer has x, y, z NaN.
[[nodiscard]] std::vector<ClosestPoint> read_closest_point_file(
    const std::filesystem::path& path);

}  // namespace sg
