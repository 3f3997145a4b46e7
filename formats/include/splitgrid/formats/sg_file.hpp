#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "splitgrid/mesh.hpp"
#include "splitgrid/split_grid.hpp"

namespace sg {

class OutputFile;

/// Current .sg format version (docs/FORMAT.md). Readers refuse newer versions.
inline constexpr std::uint32_t sg_format_version = 5;

/// Everything a .sg file holds: the mesh the grid was built for, the grid (with its
/// BuildConfig) and the name of the source mesh file.
struct SgContents {
    Mesh mesh;
    SplitGrid grid;
    std::string source_name;
    friend bool operator==(const SgContents&, const SgContents&) = default;
};

/// One entry of the section table, as read from a file.
struct SgSectionInfo {
    std::string name;          ///< four-character tag, e.g. "VERT"
    std::uint64_t offset = 0;  ///< from the start of the file
    std::uint64_t bytes = 0;
    std::uint64_t count = 0;   ///< records in the section
    std::uint32_t crc32 = 0;
};

/// Header-level facts about a file.
struct SgFileInfo {
    std::uint32_t format_version = 0;
    std::uint64_t file_bytes = 0;
    std::vector<SgSectionInfo> sections;
};

struct SgReadOptions {
    /// Check each section's CRC-32. Turn off only to fuzz the checks behind the checksums.
    bool verify_checksums = true;
    /// Also run check_coverage (slow on large meshes: one descent per triangle).
    bool check_coverage = false;
};

/// Writes `contents` to `path` atomically: the bytes go to a temporary file in the same
/// folder, which is renamed over `path` only when complete. Throws IoError on failure
/// (the temporary file is removed). Precondition: check_invariants(contents.grid) passes;
/// it is not re-checked here (the reader checks everything). Memory: one copy of the file.
void write_sg_file(const std::filesystem::path& path, const SgContents& contents);

/// The same into an output reserved before the work that made `contents` (OutputFile, so
/// that an unwritable folder is found first), which it commits.
void write_sg_file(OutputFile& output, const SgContents& contents);

/// Reads and fully checks a .sg file: magic, version, endianness, record sizes, section
/// table, every count against the file size before allocating, checksums, every index
/// (check_mesh, check_invariants). Throws FormatError "<path>: <what is wrong>" (with the
/// byte offset where it applies) or IoError. Memory: the file plus its decoded contents;
/// a forged count is refused before anything is allocated from it.
[[nodiscard]] SgContents read_sg_file(const std::filesystem::path& path,
                                      const SgReadOptions& options = {});

/// Same checks on bytes already in memory; `name` is used in messages.
[[nodiscard]] SgContents read_sg_bytes(const std::vector<std::uint8_t>& bytes,
                                       const std::string& name,
                                       const SgReadOptions& options = {});

/// The same encoding write_sg_file() writes, in memory (tests, fuzzing). A pure function of
/// `contents`: padding and reserved bytes are zero. Does not validate `contents`, so tests
/// can encode deliberately broken grids.
[[nodiscard]] std::vector<std::uint8_t> encode_sg(const SgContents& contents);

/// Reads only the header and section table (no checksums beyond the header's own).
[[nodiscard]] SgFileInfo read_sg_info(const std::filesystem::path& path);

}  // namespace sg
