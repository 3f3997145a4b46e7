#include "point_files.hpp"

#include <limits>
#include <vector>

#include "splitgrid/builder.hpp"
#include "splitgrid/formats/point_file.hpp"
#include "splitgrid/formats/sg_file.hpp"

namespace sg::bench {

void save_scene(const std::filesystem::path& dir, const std::string& scene, const MeshView& mesh,
                const BuildConfig& config)
{
    SgContents contents;
    contents.mesh.vertices.assign(mesh.vertices.begin(), mesh.vertices.end());
    contents.mesh.triangles.assign(mesh.triangles.begin(), mesh.triangles.end());
    contents.grid = build_split_grid(contents.mesh.view(), config);
    contents.source_name = scene;
    write_sg_file(dir / (scene + ".sg"), contents);
}

void save_point_sets(const std::filesystem::path& dir, const std::string& scene,
                     const PointBench& points)
{
    for (const char* set : {"random", "near"}) {
        const std::vector<Vec3f>& occupancy = points.occupancy_points(set);
        const std::vector<Vec3f>& closest = points.closest_points(set);
        const std::vector<Vec3f>& longer = occupancy.size() >= closest.size() ? occupancy : closest;
        if (!longer.empty()) write_point_file(dir / (scene + "." + set + ".points"), longer);
    }
}

void save_inside_set(const std::filesystem::path& dir, const InsideSet& set)
{
    write_point_file(dir / (set.name + ".points"), set.points);
    std::vector<float> expected;
    for (const Side side : set.expected)
        expected.push_back(side == Side::inside    ? 1.0f
                           : side == Side::outside ? 0.0f
                                                   : std::numeric_limits<float>::quiet_NaN());
    write_occupancy_file(dir / (set.name + ".expected"), expected);
}

}  // namespace sg::bench
