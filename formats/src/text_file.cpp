#include "splitgrid/formats/text_file.hpp"

#include <cstdint>
#include <span>

#include "splitgrid/formats/output_file.hpp"

namespace sg {

void write_text_file(const std::filesystem::path& path, std::string_view text)
{
    OutputFile output(path);
    write_text_file(output, text);
}

void write_text_file(OutputFile& output, std::string_view text)
{
    output.commit(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

}  // namespace sg
