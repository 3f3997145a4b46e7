#pragma once

#include <cstdint>
#include <span>

#include "sg_file_layout.hpp"

namespace sg::detail {

/// CRC-32 (ISO-HDLC polynomial, as in zlib, PNG and gzip) of `bytes`, continuing from `crc`
/// (0 starts a new checksum). Computed by zlib.
[[nodiscard]] std::uint32_t crc32_of(std::span<const std::uint8_t> bytes,
                                     std::uint32_t crc = 0) noexcept;

/// The header checksum of a .sg file: CRC-32 of the 80 header bytes with header_crc32 read as
/// zero, continued over the section table bytes.
[[nodiscard]] std::uint32_t sg_header_crc32(const SgHeader& header,
                                            std::span<const std::uint8_t> table_bytes) noexcept;

}  // namespace sg::detail
