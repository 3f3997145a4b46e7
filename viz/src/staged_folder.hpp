#pragma once

#include <filesystem>
#include <vector>

#include "splitgrid/formats/temporary_paths.hpp"

namespace sg::viz::detail {

/// A folder written in full before it appears under its final name, so that a reader never
/// sees half an export and a failure leaves nothing behind.
///
/// The constructor checks the target and creates an empty hidden folder beside it (same
/// parent, so the final rename stays on one file system), named
/// ".<target name>.sg-export-<pid>-<random>" (temporary_paths.hpp), after removing the
/// staging folders of the same target that killed runs left behind. The caller fills it,
/// then commit() flushes every file and folder to disk (fsync) and renames it to the target.
/// If commit() is never reached (an exception), the destructor removes the staging folder
/// with everything in it; on an interrupt the cleanup registry does (CleanupEntry).
///
/// The target may be absent or an empty folder. A non-empty folder is replaced only if
/// `replace_existing` is set and it holds an earlier export (a .vtm file at its top level):
/// the two folders are swapped with one atomic renameat2(RENAME_EXCHANGE) and the old one is
/// removed; on file systems without that call, the old folder is first moved aside.
/// Every refusal and failure throws IoError naming the path.
class StagedFolder {
public:
    StagedFolder(std::filesystem::path target, bool replace_existing);
    ~StagedFolder();
    StagedFolder(const StagedFolder&) = delete;
    StagedFolder& operator=(const StagedFolder&) = delete;

    /// The folder to write into.
    [[nodiscard]] const std::filesystem::path& path() const noexcept { return staging_; }
    /// Staging folders of killed runs that the constructor removed.
    [[nodiscard]] const std::vector<std::filesystem::path>& stale_removed() const noexcept
    {
        return stale_removed_;
    }

    /// Makes the staged contents the target (see the class comment). Call at most once.
    void commit();

private:
    /// Replaces the non-empty target folder by the staging folder.
    void swap_in();

    std::filesystem::path target_;
    std::filesystem::path staging_;
    CleanupEntry cleanup_;
    std::vector<std::filesystem::path> stale_removed_;
    bool replace_existing_;
    bool committed_ = false;
};

}  // namespace sg::viz::detail
