#include "record_file.hpp"

#include <algorithm>

#include "file_bytes.hpp"
#include "splitgrid/error.hpp"

namespace sg::detail {
namespace {

bool is_vowel(char c) noexcept
{
    return std::string_view("aeiou").find(c) != std::string_view::npos;
}

}  // namespace

void check_magic_and_header(const std::vector<std::uint8_t>& bytes,
                            const std::filesystem::path& path, std::string_view magic,
                            std::string_view kind, std::size_t header_bytes)
{
    const std::string name = path.string();
    const std::size_t checked = std::min(bytes.size(), magic_bytes);
    // An empty vector may have a null data(), which memcmp must not see even for 0 bytes.
    if (checked > 0 && std::memcmp(bytes.data(), magic.data(), checked) != 0)
        throw FormatError(name + ": not " + (is_vowel(kind.front()) ? "an " : "a ") +
                          std::string(kind) +
                          " file: bad magic (at byte offset 0, expected \"" + std::string(magic) +
                          "\")");
    if (bytes.size() < header_bytes)
        throw FormatError(name + ": truncated: the file is shorter than its header (at byte "
                                 "offset " +
                          std::to_string(bytes.size()) + ", expected at least " +
                          std::to_string(header_bytes) + " bytes, found " +
                          std::to_string(bytes.size()) + ")");
}

RecordFile read_record_file(const std::filesystem::path& path, std::string_view magic,
                            std::string_view kind, std::size_t record_bytes)
{
    RecordFile file{read_file_bytes(path), 0};
    const std::vector<std::uint8_t>& bytes = file.bytes;
    check_magic_and_header(bytes, path, magic, kind, record_prefix_bytes);
    const auto count = load<std::uint64_t>(bytes, magic_bytes);
    const std::uint64_t payload = bytes.size() - record_prefix_bytes;
    const std::uint64_t room = payload / record_bytes;
    if (count != room || payload % record_bytes != 0) {
        // "16 + N x 32" rather than the product, which overflows for a forged count.
        throw FormatError(path.string() + ": " + (count > room ? "truncated: " : "") +
                          "the header counts " + std::to_string(count) + " " + std::string(kind) +
                          "s, the file size fits " + std::to_string(room) + " (at byte offset " +
                          std::to_string(magic_bytes) + ", expected " +
                          std::to_string(record_prefix_bytes) + " + " + std::to_string(count) +
                          " x " + std::to_string(record_bytes) + " bytes, found " +
                          std::to_string(bytes.size()) + " bytes)");
    }
    file.count = static_cast<std::size_t>(count);
    return file;
}

}  // namespace sg::detail
