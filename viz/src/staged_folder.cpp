#include "staged_folder.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "splitgrid/error.hpp"

namespace sg::viz::detail {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const fs::path& path, const std::string& what)
{
    throw IoError(path.string() + ": " + what);
}

std::string errno_text(int error) { return std::strerror(error); }

/// The target with any trailing separator dropped ("out/" -> "out"), so that it has a file
/// name to derive the staging name from.
fs::path without_trailing_separator(fs::path path)
{
    if (!path.has_filename() && path.has_parent_path()) path = path.parent_path();
    return path;
}

bool holds_export(const fs::path& folder)
{
    std::error_code ec;
    for (const fs::directory_entry& entry : fs::directory_iterator(folder, ec))
        if (entry.is_regular_file(ec) && entry.path().extension() == ".vtm") return true;
    return false;
}

/// Refuses a target that must not be written (see StagedFolder). Returns whether it exists
/// as a non-empty folder (then commit swaps instead of renaming).
bool check_target(const fs::path& target, bool replace_existing)
{
    std::error_code ec;
    const fs::path parent = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    if (!fs::is_directory(parent, ec)) fail(target, "folder " + parent.string() + " does not exist");
    const fs::file_status status = fs::status(target, ec);
    if (!fs::exists(status)) return false;
    if (!fs::is_directory(status)) fail(target, "exists and is not a folder");
    if (fs::is_empty(target, ec)) return false;
    if (!replace_existing)
        fail(target, "folder exists and is not empty; it is replaced only on request "
                     "(sg-export --force)");
    if (!holds_export(target))
        fail(target, "folder is not empty and holds no .vtm file, so it is not an earlier "
                     "export; it is never replaced");
    return true;
}

void fsync_path(const fs::path& path, bool is_folder)
{
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | (is_folder ? O_DIRECTORY : 0));
    if (fd < 0) fail(path, "cannot open to flush: " + errno_text(errno));
    const int result = ::fsync(fd);
    const int error = errno;
    ::close(fd);
    if (result != 0) fail(path, "cannot flush to disk: " + errno_text(error));
}

/// Flushes every file, then every folder (deepest first), so that after the rename the
/// export survives a power cut.
void fsync_tree(const fs::path& root)
{
    std::vector<fs::path> folders{root};
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(root)) {
        if (entry.is_directory())
            folders.push_back(entry.path());
        else
            fsync_path(entry.path(), false);
    }
    for (auto it = folders.rbegin(); it != folders.rend(); ++it) fsync_path(*it, true);
}

/// The name of staging folders: "sg-export", as in ".<target name>.sg-export-<pid>-<random>".
constexpr const char* staging_kind = "sg-export";

/// Creates a new hidden folder beside `target` and registers it for removal on an interrupt
/// before it exists, so that no interrupt finds it unregistered. mkdir's mode 0777 gives it
/// the permissions of any new folder (mkdtemp would make it private).
fs::path make_staging_folder(const fs::path& target, CleanupEntry& cleanup)
{
    const fs::path parent = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    const std::string prefix = temporary_prefix(target, staging_kind);
    std::random_device seed_source;
    std::mt19937 random(seed_source());
    int error = 0;
    for (int attempt = 0; attempt < 100; ++attempt) {
        char suffix[9];
        std::snprintf(suffix, sizeof suffix, "%08x", static_cast<unsigned>(random()));
        fs::path candidate = parent / (prefix + suffix);
        CleanupEntry entry = CleanupEntry::folder(candidate);
        if (::mkdir(candidate.c_str(), 0777) == 0) {
            cleanup = std::move(entry);
            return candidate;
        }
        error = errno;
        if (error != EEXIST) break;
    }
    fail(target, "cannot create a folder beside it: " + errno_text(error));
}

}  // namespace

StagedFolder::StagedFolder(fs::path target, bool replace_existing)
    : target_(without_trailing_separator(std::move(target))), replace_existing_(replace_existing)
{
    check_target(target_, replace_existing_);
    stale_removed_ = remove_stale_temporaries(target_, staging_kind);
    staging_ = make_staging_folder(target_, cleanup_);
}

StagedFolder::~StagedFolder()
{
    if (committed_) return;
    std::error_code ec;
    fs::remove_all(staging_, ec);
}

void StagedFolder::commit()
{
    fsync_tree(staging_);
    // Checked again: the target may have changed while the export was being written.
    if (!check_target(target_, replace_existing_)) {
        // The rename and forgetting the staging folder are one step for the interrupt
        // cleanup: either the export is in place, or the staging folder is removed.
        const auto hold = hold_off_cleanup();
        // rename(2) replaces an empty folder atomically and refuses a non-empty one.
        if (::rename(staging_.c_str(), target_.c_str()) != 0)
            fail(target_, "cannot rename " + staging_.string() + " to it: " + errno_text(errno));
        committed_ = true;
        cleanup_.release_locked();
    } else {
        swap_in();
    }
    fsync_path(target_.parent_path().empty() ? fs::path(".") : target_.parent_path(), true);
}

void StagedFolder::swap_in()
{
    std::error_code ec;
    {
        const auto hold = hold_off_cleanup();
        if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(),
                        RENAME_EXCHANGE) == 0) {
            // The staging path now holds the earlier export: it stays registered until it
            // is removed, so an interrupt removes it too.
            committed_ = true;
        } else if (errno != EINVAL && errno != ENOSYS) {
            fail(target_, "cannot swap in " + staging_.string() + ": " + errno_text(errno));
        }
    }
    if (committed_) {
        fs::remove_all(staging_, ec);
        cleanup_.release();
        return;
    }
    // No atomic exchange on this file system: move the earlier export aside first. In the
    // short gap between the two renames the target does not exist; no interrupt cleanup
    // runs in it, so the earlier export is never lost.
    CleanupEntry old_cleanup;
    const fs::path old = make_staging_folder(target_, old_cleanup);
    {
        const auto hold = hold_off_cleanup();
        // rename(2) replaces the empty folder just made.
        if (::rename(target_.c_str(), old.c_str()) != 0) {
            const int error = errno;
            fs::remove_all(old, ec);
            fail(target_, "cannot move the earlier export aside: " + errno_text(error));
        }
        if (::rename(staging_.c_str(), target_.c_str()) != 0) {
            const int error = errno;
            ::rename(old.c_str(), target_.c_str());
            fail(target_, "cannot rename " + staging_.string() + " to it: " + errno_text(error));
        }
        committed_ = true;
        cleanup_.release_locked();
    }
    fs::remove_all(old, ec);
}

}  // namespace sg::viz::detail
