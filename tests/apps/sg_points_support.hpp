#pragma once

// What the end-to-end tests of sg-points' distance queries and grids share
// (sg_points_distance_test.cpp, sg_points_grid_test.cpp): a closed mesh of two shapes; for
// each point the distance, the nearest triangles and the side by brute force in double over
// every triangle (tests/support/distance_oracle.hpp, the winding number of
// crossings_oracle.hpp), sharing no code with the library's search or its parity count; and
// the keys docs/STATS_JSON.md documents for sg-points --json.
// Header-only because tests/CMakeLists.txt compiles only tests/apps/*_test.cpp.

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "splitgrid/brute_force.hpp"
#include "splitgrid/closed_shapes.hpp"
#include "support/crossings_oracle.hpp"
#include "support/distance_oracle.hpp"

#include <nlohmann/json.hpp>

namespace sg::test {

/// An icosphere of radius 1 around the origin (320 triangles, curved: closest points on
/// faces, edges and vertices) and the cube [2, 4] x [-1, 1] x [-1, 1] cut into unit squares
/// (96 triangles, flat: many points equally near two triangles), one closed mesh.
inline Mesh sphere_and_cube()
{
    Mesh mesh = icosphere(2, 1.0f);
    const Mesh cube = tessellated_cube(2);
    const auto offset = static_cast<std::uint32_t>(mesh.vertices.size());
    for (const Vec3f v : cube.vertices)
        mesh.vertices.push_back({v.x + 2.0f, v.y - 1.0f, v.z - 1.0f});
    for (Triangle t : cube.triangles) {
        for (std::uint32_t& v : t.v) v += offset;
        mesh.triangles.push_back(t);
    }
    return mesh;
}

/// Builds `mesh` with sg-build (through an OBJ file beside `sg_file`).
inline void build_with_sg_build(const Mesh& mesh, const std::filesystem::path& sg_file,
                                const ScratchDir& scratch)
{
    const std::filesystem::path obj = std::filesystem::path(sg_file).replace_extension(".obj");
    write_text(obj, obj_of(mesh));
    const ToolRun run = run_tool(SG_BUILD_EXE, {obj.string(), "-o", sg_file.string()}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
}

/// Points of every kind around sphere_and_cube: uniform in a box around both shapes
/// (seeded), on and off the sphere's vertices, on the cube's lattice of unit points (vertices,
/// edge and face points, where several triangles tie), and far away.
inline std::vector<Vec3f> points_around_sphere_and_cube()
{
    std::vector<Vec3f> points;
    std::mt19937 random(45);
    std::uniform_real_distribution<float> x(-2.0f, 5.0f), yz(-2.0f, 2.0f);
    for (int i = 0; i < 1500; ++i) points.push_back({x(random), yz(random), yz(random)});
    for (const Vec3f v : icosphere(2, 1.0f).vertices)
        for (const float scale : {0.0f, 0.5f, 0.999f, 1.0f, 1.001f, 1.5f})
            points.push_back({v.x * scale, v.y * scale, v.z * scale});
    for (float px = 1.5f; px <= 4.5f; px += 0.5f)
        for (float py = -1.5f; py <= 1.5f; py += 0.5f)
            for (float pz = -1.5f; pz <= 1.5f; pz += 0.5f) points.push_back({px, py, pz});
    points.push_back({100.0f, -50.0f, 30.0f});
    points.push_back({-1e4f, 0.0f, 0.0f});
    return points;
}

/// The answers of the oracle for one point.
struct PointOracle {
    double distance = 0.0;
    std::vector<std::uint32_t> nearest;  ///< triangles within the tie tolerance
    bool inside = false;                 ///< by the winding number
};

/// Ties: the library counts two distances within 2^-40 (M + |p|) as equal; a wider margin
/// here accepts any triangle the library may pick, and no triangle that is really farther
/// (the meshes' distinct distances differ by far more).
inline constexpr double tie_tolerance = 1e-9;

inline PointOracle point_oracle(const MeshView& mesh, Vec3f p)
{
    const DistanceOracle d = distance_oracle(mesh, p, tie_tolerance);
    return {d.distance, d.nearest, sg::winding_number(mesh, sg::Vec3d(p)) > 0.5};
}

/// How far a float distance may lie from the oracle's double one: the library's search is
/// exact to within 2^-40 (M + |p|), then rounds to float (half an ulp, 2^-24 relative).
inline double distance_tolerance(double oracle, Vec3f p)
{
    const double magnitude =
        4.0 + std::sqrt(double{p.x} * p.x + double{p.y} * p.y + double{p.z} * p.z);
    return oracle * 0x1p-24 + magnitude * 0x1p-40;
}

/// Points nearer the surface than this may get either side (docs/SPLIT_GRID.md, "Inside or
/// outside": 2^-17 M); the sign is checked only farther away.
inline constexpr double side_band = 1e-4;

/// The keys of the sg-points table of docs/STATS_JSON.md ("grid.origin" for a nested key;
/// a row naming two keys gives both).
inline std::set<std::string> documented_points_keys()
{
    const std::string doc =
        read_text(std::filesystem::path(SG_SOURCE_DIR) / "docs" / "STATS_JSON.md");
    const std::size_t start = doc.find("## `sg-points");
    const std::size_t end = doc.find("\n## ", start + 1);
    std::set<std::string> keys;
    std::size_t line = doc.find("\n| `", start);
    while (line != std::string::npos && line < end) {
        const std::size_t cell_end = doc.find(" |", line + 3);
        const std::string cell = doc.substr(line + 3, cell_end - line - 3);
        for (std::size_t at = cell.find('`'); at != std::string::npos;
             at = cell.find('`', cell.find('`', at + 1) + 1))
            keys.insert(cell.substr(at + 1, cell.find('`', at + 1) - at - 1));
        line = doc.find("\n| `", line + 1);
    }
    return keys;
}

/// Fails for every key of `j` (and of its object `grid`) that docs/STATS_JSON.md does not list.
inline void expect_documented_points_json(const nlohmann::json& j)
{
    const std::set<std::string> documented = documented_points_keys();
    ASSERT_GT(documented.size(), 20u) << "the table of docs/STATS_JSON.md was not found";
    for (const auto& [key, value] : j.items()) {
        if (key == "grid") {
            for (const auto& item : value.items())
                EXPECT_TRUE(documented.count("grid." + item.key())) << "grid." << item.key();
        } else {
            EXPECT_TRUE(documented.count(key)) << key << " is not in docs/STATS_JSON.md";
        }
    }
}

}  // namespace sg::test
