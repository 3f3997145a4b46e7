#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace sg::detail {

/// The first bytes of a file and the size of the whole file.
struct FilePrefix {
    std::vector<std::uint8_t> bytes;  ///< at most the requested number of bytes
    std::uint64_t file_bytes = 0;     ///< size of the whole file
};

/// Reads a whole file. Throws IoError "<path>: cannot open: <reason>" or
/// "<path>: cannot read: <reason>". Memory: the file's size.
[[nodiscard]] std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& path);

/// Reads at most `max_bytes` from the start of a file, and its size. Same errors.
[[nodiscard]] FilePrefix read_file_prefix(const std::filesystem::path& path,
                                          std::uint64_t max_bytes);

}  // namespace sg::detail
