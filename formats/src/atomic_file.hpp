#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

namespace sg::detail {

/// Replaces the file at `path` with `bytes` so that, whatever happens, `path` names either
/// the old file (or nothing) or the complete new one, never a partial write.
///
/// The bytes go to a new temporary file in the same folder (same file system, so the final
/// rename is atomic), named ".<file name>.<random>.tmp" and created with mode 0666 minus the
/// umask, like an ordinary new file. It is flushed to disk with fsync, then renamed over
/// `path`; the folder is fsynced too so the rename survives a power cut. If `path` is a
/// symbolic link, the link itself is replaced.
///
/// Throws IoError "<path>: <reason>" if any step fails; the temporary file is removed first.
void write_file_atomically(const std::filesystem::path& path, std::span<const std::uint8_t> bytes);

}  // namespace sg::detail
