// Lines of numbers from text and CSV files (number_lines.hpp): for users whose rays or points
// come from a script or a spreadsheet rather than from code that writes the binary files.

#include "number_lines.hpp"

#include <array>
#include <charconv>
#include <cstdint>
#include <string>
#include <system_error>
#include <vector>

#include "file_bytes.hpp"
#include "splitgrid/error.hpp"

namespace sg::detail {
namespace {

bool is_blank(char c) noexcept { return c == ' ' || c == '\t'; }

/// A line cut into its fields: at most max_line_numbers + 1 are kept, which is enough to tell
/// that there are too many.
struct Fields {
    std::array<std::string_view, max_line_numbers + 1> text{};
    std::size_t count = 0;
    bool has_empty = false;  ///< two commas with nothing but blanks between, or one at the end
    std::size_t empty_index = 0;
};

Fields split_fields(std::string_view line)
{
    Fields fields;
    std::size_t i = 0;
    const auto skip_blanks = [&] {
        while (i < line.size() && is_blank(line[i])) ++i;
    };
    skip_blanks();
    while (i < line.size()) {
        const std::size_t start = i;
        while (i < line.size() && line[i] != ',' && !is_blank(line[i])) ++i;
        if (i == start && !fields.has_empty) {  // a comma where a field should start
            fields.has_empty = true;
            fields.empty_index = fields.count + 1;
        }
        if (fields.count < fields.text.size())
            fields.text[fields.count] = line.substr(start, i - start);
        ++fields.count;
        skip_blanks();
        if (i < line.size() && line[i] == ',') {
            ++i;
            skip_blanks();
            if ((i == line.size() || line[i] == ',') && !fields.has_empty) {
                fields.has_empty = true;
                fields.empty_index = fields.count + 1;
            }
        }
    }
    return fields;
}

enum class NumberStatus { ok, not_a_number, out_of_range };

NumberStatus parse_number(std::string_view text, float& value)
{
    // std::from_chars takes no leading '+', which spreadsheets and printf("%+g") write.
    if (text.size() > 1 && text[0] == '+' && text[1] != '-') text.remove_prefix(1);
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    if (ec == std::errc::result_out_of_range) return NumberStatus::out_of_range;
    if (ec != std::errc{} || ptr != end) return NumberStatus::not_a_number;
    return NumberStatus::ok;
}

[[noreturn]] void fail(std::string_view name, std::size_t line, const std::string& what)
{
    throw FormatError(std::string(name) + ":" + std::to_string(line) + ": " + what);
}

}  // namespace

void parse_number_lines(std::string_view text, std::string_view name, const NumberLineShape& shape,
                        const std::function<void(std::span<const float>)>& line_numbers)
{
    bool header_allowed = true;
    bool any_line = false;
    std::size_t line_number = 0;
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string_view::npos) end = text.size();
        std::string_view line = text.substr(start, end - start);
        start = end + 1;
        ++line_number;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);

        const Fields fields = split_fields(line);
        const std::string_view first = fields.text[0];
        if (fields.count == 0 || (!first.empty() && first.front() == '#')) continue;
        std::array<float, max_line_numbers> values{};
        if (header_allowed) {
            header_allowed = false;
            if (!first.empty() &&
                parse_number(first, values[0]) == NumberStatus::not_a_number)
                continue;
        }
        if (fields.has_empty)
            fail(name, line_number, "field " + std::to_string(fields.empty_index) + " is empty");
        if (fields.count != shape.fields &&
            (shape.other_fields == 0 || fields.count != shape.other_fields))
            fail(name, line_number,
                 std::to_string(fields.count) + " fields, " + std::string(shape.expected));
        for (std::size_t f = 0; f < fields.count; ++f) {
            const std::string_view field = fields.text[f];
            switch (parse_number(field, values[f])) {
            case NumberStatus::ok: break;
            case NumberStatus::not_a_number:
                fail(name, line_number,
                     "field " + std::to_string(f + 1) + " '" + std::string(field) +
                         "' is not a number");
            case NumberStatus::out_of_range:
                fail(name, line_number,
                     "field " + std::to_string(f + 1) + " '" + std::string(field) +
                         "' is outside the float32 range");
            }
        }
        any_line = true;
        line_numbers(std::span<const float>(values.data(), fields.count));
    }
    if (!any_line)
        throw FormatError(std::string(name) + ": no " + std::string(shape.items) +
                          " (every line is blank, a comment or a header)");
}

void read_number_lines(const std::filesystem::path& path, const NumberLineShape& shape,
                       const std::function<void(std::span<const float>)>& line)
{
    const std::vector<std::uint8_t> bytes = read_file_bytes(path);
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    parse_number_lines(text, path.string(), shape, line);
}

}  // namespace sg::detail
