#include "atomic_file.hpp"

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

namespace sg::detail {
namespace {

[[noreturn]] void throw_io(const std::filesystem::path& path, const std::string& reason)
{
    throw IoError(path.string() + ": " + reason);
}

std::string errno_text(int error) { return std::error_code(error, std::generic_category()).message(); }

/// Owns the temporary file until it has been renamed: closes and unlinks it on every early
/// exit, including exceptions.
class TemporaryFile {
public:
    TemporaryFile(int fd, std::filesystem::path path) : fd_(fd), path_(std::move(path)) {}
    TemporaryFile(const TemporaryFile&) = delete;
    TemporaryFile& operator=(const TemporaryFile&) = delete;
    ~TemporaryFile()
    {
        if (fd_ >= 0) ::close(fd_);
        if (!path_.empty()) ::unlink(path_.c_str());
    }

    [[nodiscard]] int fd() const noexcept { return fd_; }
    [[nodiscard]] const std::filesystem::path& path() const noexcept { return path_; }

    /// Closes the descriptor; returns 0 or the errno of close().
    int close() noexcept
    {
        const int result = ::close(fd_);
        fd_ = -1;
        return result == 0 ? 0 : errno;
    }
    /// The file now lives under another name: do not unlink it.
    void release() noexcept { path_.clear(); }

private:
    int fd_;
    std::filesystem::path path_;
};

/// Creates the temporary file. mkstemp would create it with mode 0600 and ignore the umask;
/// opening with O_CREAT | O_EXCL and 0666 gives the target the permissions any new file
/// would get, and O_EXCL with a random name is what mkstemp does internally.
TemporaryFile create_temporary(const std::filesystem::path& target)
{
    const std::filesystem::path folder =
        target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
    std::random_device seed_source;
    std::mt19937_64 random(
        (static_cast<std::uint64_t>(seed_source()) << 32) ^ seed_source() ^
        static_cast<std::uint64_t>(::getpid()));
    int last_error = 0;
    for (int attempt = 0; attempt < 100; ++attempt) {
        char suffix[17];
        std::snprintf(suffix, sizeof suffix, "%016llx",
                      static_cast<unsigned long long>(random()));
        std::string leaf = ".";
        leaf += target.filename().string();
        leaf += '.';
        leaf += suffix;
        leaf += ".tmp";
        std::filesystem::path candidate = folder / leaf;
        const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) return TemporaryFile(fd, std::move(candidate));
        last_error = errno;
        if (last_error != EEXIST) break;
    }
    throw_io(target, "cannot create a temporary file in " + folder.string() + ": " +
                         errno_text(last_error));
}

void write_all(const TemporaryFile& file, const std::filesystem::path& target,
               std::span<const std::uint8_t> bytes)
{
    std::size_t done = 0;
    while (done < bytes.size()) {
        // Linux write() transfers at most ~2 GiB per call: loop on short writes.
        const ssize_t written = ::write(file.fd(), bytes.data() + done, bytes.size() - done);
        if (written < 0) {
            if (errno == EINTR) continue;
            throw_io(target, "cannot write " + file.path().string() + ": " + errno_text(errno));
        }
        done += static_cast<std::size_t>(written);
    }
}

/// Makes the rename durable. Best effort: some file systems refuse fsync on a folder, and by
/// now the data is complete under its final name either way.
void sync_folder(const std::filesystem::path& target) noexcept
{
    const std::filesystem::path folder =
        target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    (void)::fsync(fd);
    ::close(fd);
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, std::span<const std::uint8_t> bytes)
{
    if (path.empty() || !path.has_filename()) throw_io(path, "not a file name");
    TemporaryFile file = create_temporary(path);
    write_all(file, path, bytes);
    if (::fsync(file.fd()) != 0)
        throw_io(path, "cannot flush " + file.path().string() + ": " + errno_text(errno));
    if (const int error = file.close(); error != 0)
        throw_io(path, "cannot close " + file.path().string() + ": " + errno_text(error));

    std::error_code ec;
    std::filesystem::rename(file.path(), path, ec);
    if (ec) throw_io(path, "cannot rename " + file.path().string() + " to it: " + ec.message());
    file.release();
    sync_folder(path);
}

}  // namespace sg::detail
