#pragma once

// Small file helpers shared by the formats tests: raw byte access, so the tests can look at
// files without going through the code under test (the scratch folder and text files come
// from support/scratch_dir.hpp).

#include <bit>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "support/scratch_dir.hpp"

#include <gtest/gtest.h>

namespace sg::test {

static_assert(std::endian::native == std::endian::little,
              "the formats are little-endian and these helpers read them natively");

[[nodiscard]] inline std::vector<std::uint8_t> read_bytes(const std::filesystem::path& path)
{
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write_bytes(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes)
{
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
}

/// A little-endian value at `offset` (the test host is little-endian, as the formats require).
template <class T>
[[nodiscard]] T load_le(const std::vector<std::uint8_t>& bytes, std::size_t offset)
{
    T value{};
    std::memcpy(&value, bytes.data() + offset, sizeof value);
    return value;
}

template <class T>
void store_le(std::vector<std::uint8_t>& bytes, std::size_t offset, T value)
{
    std::memcpy(bytes.data() + offset, &value, sizeof value);
}

/// The first `size` bytes of `bytes` (a truncated copy of a file).
[[nodiscard]] inline std::vector<std::uint8_t> prefix_of(const std::vector<std::uint8_t>& bytes,
                                                         std::size_t size)
{
    return {bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(size)};
}

/// The message of the exception of type E that `read` throws; a test failure (and "") when it
/// throws another type or nothing.
template <class E, class F>
[[nodiscard]] std::string error_of(F read)
{
    try {
        read();
    } catch (const E& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "wrong exception type: " << e.what();
        return {};
    }
    ADD_FAILURE() << "accepted";
    return {};
}

}  // namespace sg::test
