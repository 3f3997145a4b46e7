#include "assimp_guards.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <string>
#include <string_view>

#include "file_bytes.hpp"
#include "splitgrid/error.hpp"

namespace sg::detail {
namespace {

/// A PLY header is a few hundred bytes of text; real files with comments stay far below this.
constexpr std::uint64_t ply_header_limit = std::uint64_t{1} << 20;

bool equals_ignoring_case(std::string_view a, std::string_view b)
{
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) ==
                      std::tolower(static_cast<unsigned char>(y));
           });
}

/// True if some line of `text` is exactly "end_header" (LF or CRLF line ends, or the end of
/// the text), which is what Assimp's PLY parser needs to stop.
bool has_end_header_line(std::string_view text)
{
    constexpr std::string_view keyword = "end_header";
    for (std::size_t at = text.find(keyword); at != std::string_view::npos;
         at = text.find(keyword, at + 1)) {
        const bool starts_line = at == 0 || text[at - 1] == '\n';
        const std::size_t end = at + keyword.size();
        const bool ends_line = end == text.size() || text[end] == '\n' || text[end] == '\r';
        if (starts_line && ends_line) return true;
    }
    return false;
}

}  // namespace

void refuse_known_assimp_hangs(const std::filesystem::path& path)
{
    const FilePrefix prefix = read_file_prefix(path, ply_header_limit);
    const std::string_view text(reinterpret_cast<const char*>(prefix.bytes.data()),
                                prefix.bytes.size());
    const bool ply_extension = equals_ignoring_case(path.extension().string(), ".ply");
    const bool ply_content = equals_ignoring_case(text.substr(0, 3), "ply");
    if ((ply_extension || ply_content) && !text.empty() && !has_end_header_line(text))
        throw InputError(path.string() +
                         ": PLY header without an end_header line (within the first " +
                         std::to_string(ply_header_limit) +
                         " bytes): the file is cut off or not a PLY file");
}

}  // namespace sg::detail
