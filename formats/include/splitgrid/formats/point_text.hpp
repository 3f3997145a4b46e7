#pragma once

#include <filesystem>
#include <string_view>
#include <vector>

#include "splitgrid/vec3.hpp"

namespace sg {

/// Reads points from a text or CSV file (sg-points), one point per line: `x y z`, separated
/// by commas, spaces or tabs, in the number syntax of ray text files (read_ray_text: decimal
/// or scientific notation rounded to float32, "inf", "-inf", "nan"; '#' comments, blank
/// lines, an optional header line, LF or CRLF). Throws FormatError "<path>:<line>: <what>"
/// ("field 2 'x' is not a number", "4 fields, expected 3 (x y z)", "field 3 is empty", a
/// number outside the float32 range); FormatError "<path>: no points ..." for a file without
/// a point line; IoError if it cannot be read.
[[nodiscard]] std::vector<Vec3f> read_point_text(const std::filesystem::path& path);

/// The same parser on text in memory; `name` stands for the path in messages.
[[nodiscard]] std::vector<Vec3f> parse_point_text(std::string_view text, std::string_view name);

}  // namespace sg
