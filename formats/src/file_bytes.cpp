#include "file_bytes.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <limits>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "splitgrid/error.hpp"

namespace sg::detail {
namespace {

[[noreturn]] void throw_io(const std::filesystem::path& path, const char* step, int error)
{
    throw IoError(path.string() + ": " + step + ": " +
                  std::error_code(error, std::generic_category()).message());
}

/// Closes the descriptor on every exit.
class ReadOnlyFile {
public:
    explicit ReadOnlyFile(const std::filesystem::path& path)
        : fd_(::open(path.c_str(), O_RDONLY | O_CLOEXEC))
    {
        if (fd_ < 0) throw_io(path, "cannot open", errno);
        struct stat info {};
        if (::fstat(fd_, &info) != 0) {
            const int error = errno;
            ::close(fd_);
            throw_io(path, "cannot open", error);
        }
        // Checked here so that a folder gives "cannot open: Is a directory" rather than a
        // read error later.
        if (S_ISDIR(info.st_mode)) {
            ::close(fd_);
            throw_io(path, "cannot open", EISDIR);
        }
        size_ = S_ISREG(info.st_mode) ? static_cast<std::uint64_t>(info.st_size) : 0;
    }
    ReadOnlyFile(const ReadOnlyFile&) = delete;
    ReadOnlyFile& operator=(const ReadOnlyFile&) = delete;
    ~ReadOnlyFile() { ::close(fd_); }

    [[nodiscard]] int fd() const noexcept { return fd_; }
    /// Size reported by fstat (0 for pipes and other non-regular files).
    [[nodiscard]] std::uint64_t size() const noexcept { return size_; }

private:
    int fd_;
    std::uint64_t size_ = 0;
};

/// Appends up to `limit` bytes read from `file`; stops at end of file. Reads into the vector's
/// spare capacity first, so a vector reserved to the file's size is never reallocated unless
/// the file grew; the end-of-file probe uses a small buffer for the same reason.
void read_into(const ReadOnlyFile& file, const std::filesystem::path& path,
               std::vector<std::uint8_t>& out, std::uint64_t limit)
{
    constexpr std::size_t chunk = std::size_t{1} << 20;
    std::array<std::uint8_t, 4096> probe{};
    while (out.size() < limit) {
        const std::size_t old_size = out.size();
        const std::uint64_t room = out.capacity() - old_size;
        const auto want = static_cast<std::size_t>(
            std::min<std::uint64_t>({room > 0 ? room : probe.size(), chunk, limit - old_size}));
        std::uint8_t* target = probe.data();
        if (room > 0) {
            out.resize(old_size + want);
            target = out.data() + old_size;
        }
        const ssize_t got = ::read(file.fd(), target, want);
        const int error = errno;
        if (room > 0) out.resize(old_size + static_cast<std::size_t>(std::max<ssize_t>(got, 0)));
        if (got < 0) {
            if (error == EINTR) continue;
            throw_io(path, "cannot read", error);
        }
        if (got == 0) break;
        if (room == 0) out.insert(out.end(), probe.begin(), probe.begin() + got);
    }
}

}  // namespace

std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& path)
{
    const ReadOnlyFile file(path);
    std::vector<std::uint8_t> bytes;
    // fstat's size is a hint: the file may change while being read, so read to end of file.
    bytes.reserve(static_cast<std::size_t>(file.size()));
    read_into(file, path, bytes, std::numeric_limits<std::uint64_t>::max());
    return bytes;
}

FilePrefix read_file_prefix(const std::filesystem::path& path, std::uint64_t max_bytes)
{
    const ReadOnlyFile file(path);
    FilePrefix prefix;
    read_into(file, path, prefix.bytes, max_bytes);
    prefix.file_bytes = std::max<std::uint64_t>(file.size(), prefix.bytes.size());
    return prefix;
}

}  // namespace sg::detail
