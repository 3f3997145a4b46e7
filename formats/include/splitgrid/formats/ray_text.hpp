#pragma once

#include <filesystem>
#include <string_view>
#include <vector>

#include "splitgrid/ray.hpp"

namespace sg {

/// Reads rays from a text or CSV file (sg-rays text), one ray per line:
///   ox oy oz dx dy dz [t_min t_max]
/// six numbers (origin and direction; t_min = 0, t_max = infinity) or eight, separated by
/// commas, spaces or tabs (any mix; "1, 2, 3" and "1 2 3" both work). Numbers are decimal or
/// scientific notation, rounded to the nearest float32 (std::from_chars), and "inf", "-inf" and
/// "nan" are read as such, so a file can hold any ray a ray file can (sg-trace counts the
/// invalid ones). Blank lines and lines whose first non-blank character is '#' are skipped;
/// the first other line is skipped as a header when its first field is not a number (as the
/// "ox,oy,oz,dx,dy,dz,t_min,t_max" of a spreadsheet export). Line endings LF or CRLF.
/// Throws FormatError "<path>:<line>: <what>" for a field that is not a number ("field 4 'x1'
/// is not a number"), a number outside the float32 range, an empty field between two commas,
/// or a count of fields other than 6 or 8; FormatError "<path>: no rays ..." for a file
/// without a ray line; IoError if it cannot be read.
[[nodiscard]] std::vector<Ray> read_ray_text(const std::filesystem::path& path);

/// The same parser on text in memory; `name` stands for the path in messages.
[[nodiscard]] std::vector<Ray> parse_ray_text(std::string_view text, std::string_view name);

}  // namespace sg
