#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "splitgrid/formats/temporary_paths.hpp"

namespace sg {

/// An output file written atomically, reserved before the work that produces it: whatever
/// happens, the target names either the old file (or nothing) or the complete new one, never
/// a partial write.
///
/// The constructor creates the temporary file beside the target at once (same folder, so
/// the final rename is atomic), named ".<file name>.tmp-<pid>-<random>" with mode 0666 minus
/// the umask like any new file: a folder that is missing, read-only or full of other problems
/// is found before a long import, build or render rather than after it. It also removes the
/// temporaries of the same target that killed runs left behind (remove_stale_temporaries)
/// and registers its own for removal on an interrupt (CleanupEntry). commit() fills and
/// flushes the temporary (fsync) and renames it over the target, then flushes the folder so
/// the rename survives a power cut; if the target is a symbolic link, the link itself is
/// replaced. Without commit() the destructor removes the temporary. A target that exists and
/// is a folder, a device, a pipe or a socket is refused, since the rename would replace it.
///
/// Every failure throws IoError "<target>: <reason>".
class OutputFile {
public:
    explicit OutputFile(std::filesystem::path target);
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    [[nodiscard]] const std::filesystem::path& target() const noexcept { return target_; }
    /// The temporary file, for writers that open files by name (VTK's image writers).
    [[nodiscard]] const std::filesystem::path& temporary_path() const noexcept
    {
        return temporary_;
    }
    /// Temporaries of this target left by runs that were killed, removed by the constructor.
    [[nodiscard]] const std::vector<std::filesystem::path>& stale_removed() const noexcept
    {
        return stale_removed_;
    }

    /// Writes `bytes` as the whole file and renames it into place. Call at most once.
    void commit(std::span<const std::uint8_t> bytes);
    /// Renames into place what a writer wrote to temporary_path() by name, after flushing it.
    /// Call at most once, instead of commit(bytes).
    void commit_written();

private:
    void rename_into_place();

    std::filesystem::path target_;
    std::filesystem::path temporary_;
    std::vector<std::filesystem::path> stale_removed_;
    int fd_ = -1;
    CleanupEntry cleanup_;
    bool committed_ = false;
};

}  // namespace sg
