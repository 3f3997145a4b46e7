#pragma once

// The layout every small binary file of splitgrid shares (ray, hit, count, hit list, point and
// point result files; docs/FORMAT.md): 8 ASCII magic bytes naming the kind, little-endian
// uint64 counts, then fixed-size little-endian records, so that numpy reads each in a line.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace sg::detail {

static_assert(std::endian::native == std::endian::little,
              "the record files are little-endian records copied as bytes: add byte swapping "
              "to port to a big-endian host");

inline constexpr std::size_t magic_bytes = 8;
/// Magic and one uint64 count: the header of every record file but the hit list file.
inline constexpr std::size_t record_prefix_bytes = magic_bytes + sizeof(std::uint64_t);

/// A record file's bytes: magic, count, then make_record(i) for each i.
template <class Record, class MakeRecord>
[[nodiscard]] std::vector<std::uint8_t> encode_records(std::string_view magic, std::size_t count,
                                                       MakeRecord make_record)
{
    std::vector<std::uint8_t> out(record_prefix_bytes + count * sizeof(Record));
    std::memcpy(out.data(), magic.data(), magic_bytes);
    const std::uint64_t count64 = count;
    std::memcpy(out.data() + magic_bytes, &count64, sizeof count64);
    for (std::size_t i = 0; i < count; ++i) {
        const Record r = make_record(i);
        std::memcpy(out.data() + record_prefix_bytes + i * sizeof(Record), &r, sizeof r);
    }
    return out;
}

/// A value of type T at `offset` of `bytes` (which must hold it), copied out: records are not
/// aligned for direct access.
template <class T>
[[nodiscard]] T load(const std::vector<std::uint8_t>& bytes, std::size_t offset) noexcept
{
    T value{};
    std::memcpy(&value, bytes.data() + offset, sizeof value);
    return value;
}

/// Refuses `bytes` (the file `path`) unless it starts with `magic`, compared on the bytes
/// there are, and holds at least `header_bytes`: FormatError "<path>: not a(n) <kind> file: bad
/// magic ..." or "<path>: truncated: the file is shorter than its header ...".
void check_magic_and_header(const std::vector<std::uint8_t>& bytes,
                            const std::filesystem::path& path, std::string_view magic,
                            std::string_view kind, std::size_t header_bytes);

/// The checked bytes of a record file.
struct RecordFile {
    std::vector<std::uint8_t> bytes;
    std::size_t count = 0;

    /// Record i, copied out of the byte buffer.
    template <class Record>
    [[nodiscard]] Record record(std::size_t i) const noexcept
    {
        return load<Record>(bytes, record_prefix_bytes + i * sizeof(Record));
    }
    /// Byte offset of record i, for messages.
    [[nodiscard]] static std::size_t offset_of(std::size_t i, std::size_t record_bytes) noexcept
    {
        return record_prefix_bytes + i * record_bytes;
    }
};

/// Reads a record file of `record_bytes` records and checks magic, count and size (`kind`
/// names one record in messages: "ray", "hit"). The count is checked against the file size by
/// division, so a forged count can neither overflow nor cause a huge allocation. Throws
/// FormatError "<path>: ..." or IoError.
[[nodiscard]] RecordFile read_record_file(const std::filesystem::path& path,
                                          std::string_view magic, std::string_view kind,
                                          std::size_t record_bytes);

}  // namespace sg::detail
