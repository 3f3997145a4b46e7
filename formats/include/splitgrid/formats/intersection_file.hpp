#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "splitgrid/intersections.hpp"

namespace sg {

class OutputFile;

/// Hit count files and hit list files: the answers of `sg-trace --query count` and
/// `--query all` (count_intersections, list_intersections), in the layout of the ray and hit
/// files (docs/FORMAT.md): ASCII magic, little-endian uint64 counts, then fixed-size records,
/// one numpy.fromfile away.

/// Writes a hit count file: magic "SGCNT001", a uint64 ray count, then one int32 per ray (the
/// distinct triangles the ray hits in [t_min, t_max]), atomically into an output reserved
/// earlier (OutputFile), which it commits.
void write_hit_count_file(OutputFile& output, std::span<const std::int32_t> counts);
/// The same to `path` (temporary file, then rename).
void write_hit_count_file(const std::filesystem::path& path, std::span<const std::int32_t> counts);

/// Reads a hit count file. Throws FormatError "<path>: <what is wrong>" on a bad magic, a
/// count that does not match the file size (a truncated file), or a negative count (naming
/// the ray and its byte offset); IoError if it cannot be read.
[[nodiscard]] std::vector<std::int32_t> read_hit_count_file(const std::filesystem::path& path);

/// Writes a hit list file: magic "SGALL001", uint64 ray count R, uint64 hit count H, the R + 1
/// uint64 `ray_splits`, then per hit a uint32 ray id, uint32 triangle id and float32 t, u, v
/// (Open3D's list_intersections layout, hits of a ray sorted by t then triangle id).
/// Atomically into an output reserved earlier, which it commits.
void write_hit_list_file(OutputFile& output, const IntersectionList& list);
/// The same to `path`.
void write_hit_list_file(const std::filesystem::path& path, const IntersectionList& list);

/// Reads a hit list file. Besides magic and sizes (R and H against the file size, by division,
/// so a forged count neither overflows nor allocates) it checks what the layout promises:
/// ray_splits start at 0, never decrease and end at H; every hit's ray id is the ray whose
/// range holds it; each ray's hits are strictly ascending by t, then triangle id. Throws
/// FormatError "<path>: <what> (at byte offset N ...)" or IoError.
[[nodiscard]] IntersectionList read_hit_list_file(const std::filesystem::path& path);

}  // namespace sg
