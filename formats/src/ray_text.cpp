// Rays from text and CSV files (ray_text.hpp): for users whose rays come from a script or a
// spreadsheet rather than from code that writes the binary ray file.

#include "splitgrid/formats/ray_text.hpp"

#include "number_lines.hpp"

namespace sg {
namespace {

constexpr detail::NumberLineShape ray_line{
    6, 8, "expected 6 (origin x y z, direction x y z) or 8 (and t_min t_max)", "rays"};

/// The ray of a line of 6 or 8 numbers.
Ray ray_of(std::span<const float> v)
{
    Ray ray{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
    if (v.size() == 8) {
        ray.t_min = v[6];
        ray.t_max = v[7];
    }
    return ray;
}

}  // namespace

std::vector<Ray> parse_ray_text(std::string_view text, std::string_view name)
{
    std::vector<Ray> rays;
    detail::parse_number_lines(text, name, ray_line,
                               [&](std::span<const float> v) { rays.push_back(ray_of(v)); });
    return rays;
}

std::vector<Ray> read_ray_text(const std::filesystem::path& path)
{
    std::vector<Ray> rays;
    detail::read_number_lines(path, ray_line,
                              [&](std::span<const float> v) { rays.push_back(ray_of(v)); });
    return rays;
}

}  // namespace sg
