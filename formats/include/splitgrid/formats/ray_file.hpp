#pragma once

#include <filesystem>
#include <vector>

#include "splitgrid/ray.hpp"

namespace sg {

class OutputFile;

/// Reads a ray file (docs/FORMAT.md): 8 magic bytes "SGRAY001", a little-endian uint64
/// count, then per ray 8 float32: origin xyz, direction xyz, t_min, t_max. Throws
/// FormatError "<path>: <what is wrong>" on a bad magic, a count that does not match the
/// file size, or a truncated file; IoError if it cannot be read.
[[nodiscard]] std::vector<Ray> read_ray_file(const std::filesystem::path& path);

/// Writes a ray file atomically (temporary file, then rename).
void write_ray_file(const std::filesystem::path& path, const std::vector<Ray>& rays);
/// The same into an output reserved earlier (OutputFile), which it commits.
void write_ray_file(OutputFile& output, const std::vector<Ray>& rays);

/// Writes a hit file atomically: magic "SGHIT001", a uint64 count, then per ray a uint32
/// triangle id (0xFFFFFFFF on a miss), float32 t, u, v.
void write_hit_file(const std::filesystem::path& path, const std::vector<Hit>& hits);
/// The same into an output reserved earlier (OutputFile), which it commits.
void write_hit_file(OutputFile& output, const std::vector<Hit>& hits);

/// Reads a hit file with the same checks as read_ray_file.
[[nodiscard]] std::vector<Hit> read_hit_file(const std::filesystem::path& path);

}  // namespace sg
