// Points from text and CSV files (point_text.hpp), in the text form of ray text files.

#include "splitgrid/formats/point_text.hpp"

#include "number_lines.hpp"

namespace sg {
namespace {

constexpr detail::NumberLineShape point_line{3, 0, "expected 3 (x y z)", "points"};

}  // namespace

std::vector<Vec3f> parse_point_text(std::string_view text, std::string_view name)
{
    std::vector<Vec3f> points;
    detail::parse_number_lines(text, name, point_line, [&](std::span<const float> v) {
        points.push_back({v[0], v[1], v[2]});
    });
    return points;
}

std::vector<Vec3f> read_point_text(const std::filesystem::path& path)
{
    std::vector<Vec3f> points;
    detail::read_number_lines(path, point_line, [&](std::span<const float> v) {
        points.push_back({v[0], v[1], v[2]});
    });
    return points;
}

}  // namespace sg
