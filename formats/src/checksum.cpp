#include "checksum.hpp"

#include <array>
#include <cstring>

#include <zlib.h>

namespace sg::detail {

std::uint32_t crc32_of(std::span<const std::uint8_t> bytes, std::uint32_t crc) noexcept
{
    // crc32_z takes a z_size_t length, so sections above 4 GiB need no chunking.
    return static_cast<std::uint32_t>(
        ::crc32_z(static_cast<uLong>(crc), bytes.data(), static_cast<z_size_t>(bytes.size())));
}

std::uint32_t sg_header_crc32(const SgHeader& header,
                              std::span<const std::uint8_t> table_bytes) noexcept
{
    SgHeader copy = header;
    copy.header_crc32 = 0;
    std::array<std::uint8_t, sizeof(SgHeader)> raw{};
    std::memcpy(raw.data(), &copy, sizeof copy);
    return crc32_of(table_bytes, crc32_of(raw));
}

}  // namespace sg::detail
