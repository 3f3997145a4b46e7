#pragma once

// The text form shared by ray and point files written by hand or by a spreadsheet
// (ray_text.hpp, point_text.hpp): one record per line, numbers separated by commas and/or
// blanks, '#' comments, an optional header line, errors that name the line.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <span>
#include <string_view>

namespace sg::detail {

/// The most numbers a line may hold.
inline constexpr std::size_t max_line_numbers = 8;

/// What each line of a file must hold.
struct NumberLineShape {
    /// The number of fields a line has, at most max_line_numbers.
    std::size_t fields = 0;
    /// Another number of fields a line may have (rays: 6 or 8), 0 for none.
    std::size_t other_fields = 0;
    /// Completes "<n> fields, " in the message for a line with another count: "expected 3 (x y z)".
    std::string_view expected;
    /// What the lines are, for the message about a file without one: "rays", "points".
    std::string_view items;
};

/// Parses `text` line by line and calls `line(numbers)` for each line of numbers, in order.
/// Numbers are decimal or scientific notation rounded to the nearest float32
/// (std::from_chars; a leading '+' allowed), or "inf", "-inf", "nan". Blank lines and lines
/// whose first non-blank character is '#' are skipped; the first other line is skipped as a
/// header when its first field is not a number. LF or CRLF line endings. Throws FormatError
/// "<name>:<line>: <what>" for a field that is not a number ("field 2 'x' is not a number"), a
/// number outside the float32 range, an empty field between two commas ("field 4 is empty"),
/// or another count of fields than the shape's; FormatError "<name>: no <items> (every line
/// is blank, a comment or a header)" when no line holds numbers.
void parse_number_lines(std::string_view text, std::string_view name, const NumberLineShape& shape,
                        const std::function<void(std::span<const float>)>& line);

/// parse_number_lines on the whole file at `path` (named by its path in messages). Throws
/// IoError if it cannot be read.
void read_number_lines(const std::filesystem::path& path, const NumberLineShape& shape,
                       const std::function<void(std::span<const float>)>& line);

}  // namespace sg::detail
