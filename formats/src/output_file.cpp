#include "splitgrid/formats/output_file.hpp"

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "splitgrid/error.hpp"

namespace sg {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void throw_io(const fs::path& path, const std::string& reason)
{
    throw IoError(path.string() + ": " + reason);
}

std::string errno_text(int error) { return std::error_code(error, std::generic_category()).message(); }

fs::path folder_of(const fs::path& target)
{
    return target.has_parent_path() ? target.parent_path() : fs::path(".");
}

void write_all(int fd, const fs::path& temporary, const fs::path& target,
               std::span<const std::uint8_t> bytes)
{
    std::size_t done = 0;
    while (done < bytes.size()) {
        // Linux write() transfers at most ~2 GiB per call: loop on short writes.
        const ssize_t written = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (written < 0) {
            if (errno == EINTR) continue;
            throw_io(target, "cannot write " + temporary.string() + ": " + errno_text(errno));
        }
        done += static_cast<std::size_t>(written);
    }
}

/// Makes the rename durable. Best effort: some file systems refuse fsync on a folder, and by
/// now the data is complete under its final name either way.
void sync_folder(const fs::path& target) noexcept
{
    const int fd = ::open(folder_of(target).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    (void)::fsync(fd);
    ::close(fd);
}

}  // namespace

OutputFile::OutputFile(fs::path target) : target_(std::move(target))
{
    if (target_.empty() || !target_.has_filename()) throw_io(target_, "not a file name");
    std::error_code ec;
    if (fs::is_directory(target_, ec)) throw_io(target_, "is a folder, expected a file name");
    // A device, pipe or socket would be replaced by the rename, not written to: with the
    // rights to do so, `-o /dev/null` would swap the system's /dev/null for a regular file.
    const fs::file_status status = fs::symlink_status(target_, ec);
    if (fs::exists(status) && !fs::is_regular_file(status) && !fs::is_symlink(status))
        throw_io(target_, "is not a regular file (a device, pipe or socket): the file is "
                          "written by renaming a complete one into place, which would replace it");
    stale_removed_ = remove_stale_temporaries(target_, "tmp");

    // mkstemp would create the file with mode 0600 and ignore the umask; O_CREAT | O_EXCL
    // with 0666 gives the target the permissions any new file would get, and O_EXCL with a
    // random name is what mkstemp does internally.
    const std::string prefix = temporary_prefix(target_, "tmp");
    std::random_device seed_source;
    std::mt19937_64 random((static_cast<std::uint64_t>(seed_source()) << 32) ^ seed_source());
    int last_error = 0;
    for (int attempt = 0; attempt < 100; ++attempt) {
        char suffix[17];
        std::snprintf(suffix, sizeof suffix, "%016llx",
                      static_cast<unsigned long long>(random()));
        fs::path candidate = folder_of(target_) / (prefix + suffix);
        // Registered before it exists, so that an interrupt right after the open still
        // finds it; removing a name that was never created is harmless.
        CleanupEntry cleanup = CleanupEntry::file(candidate);
        fd_ = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd_ >= 0) {
            temporary_ = std::move(candidate);
            cleanup_ = std::move(cleanup);
            return;
        }
        last_error = errno;
        if (last_error != EEXIST) break;
    }
    throw_io(target_, "cannot create a temporary file in " + folder_of(target_).string() + ": " +
                          errno_text(last_error));
}

OutputFile::~OutputFile()
{
    if (fd_ >= 0) ::close(fd_);
    if (!committed_) ::unlink(temporary_.c_str());
}

void OutputFile::commit(std::span<const std::uint8_t> bytes)
{
    write_all(fd_, temporary_, target_, bytes);
    if (::fsync(fd_) != 0)
        throw_io(target_, "cannot flush " + temporary_.string() + ": " + errno_text(errno));
    const int result = ::close(fd_);
    fd_ = -1;
    if (result != 0)
        throw_io(target_, "cannot close " + temporary_.string() + ": " + errno_text(errno));
    rename_into_place();
}

void OutputFile::commit_written()
{
    if (fd_ >= 0) ::close(fd_);
    fd_ = ::open(temporary_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) throw_io(target_, "cannot open " + temporary_.string() + ": " + errno_text(errno));
    if (::fsync(fd_) != 0)
        throw_io(target_, "cannot flush " + temporary_.string() + ": " + errno_text(errno));
    ::close(fd_);
    fd_ = -1;
    rename_into_place();
}

void OutputFile::rename_into_place()
{
    {
        // The rename and forgetting the temporary are one step for the interrupt cleanup:
        // either the new file is in place, or the old one is untouched and the temporary
        // gone.
        const auto hold = hold_off_cleanup();
        std::error_code ec;
        fs::rename(temporary_, target_, ec);
        if (ec)
            throw_io(target_, "cannot rename " + temporary_.string() + " to it: " + ec.message());
        committed_ = true;
        cleanup_.release_locked();
    }
    sync_folder(target_);
}

}  // namespace sg
