#include "splitgrid/formats/text_file.hpp"

#include <cstdint>
#include <span>

#include "atomic_file.hpp"

namespace sg {

void write_text_file(const std::filesystem::path& path, std::string_view text)
{
    detail::write_file_atomically(
        path, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

}  // namespace sg
