#pragma once

// Triangle soups for the welding tests: a mesh with three vertices of its own per triangle,
// the distinct corner positions of a mesh, and a binary STL file written byte by byte (so the
// import is tested on bytes the code under test did not write). Header-only so that every
// suite can use it.

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <vector>

#include "splitgrid/mesh.hpp"

namespace sg::test {

/// The three float32 bit patterns of a position: the identity welding goes by.
using PositionBits = std::array<std::uint32_t, 3>;
inline PositionBits position_bits(Vec3f p)
{
    return {std::bit_cast<std::uint32_t>(p.x), std::bit_cast<std::uint32_t>(p.y),
            std::bit_cast<std::uint32_t>(p.z)};
}

/// Distinct bit patterns among the triangles' corners: what welding must leave.
inline std::size_t distinct_corner_positions(const Mesh& mesh)
{
    std::set<PositionBits> seen;
    for (const Triangle& t : mesh.triangles)
        for (const std::uint32_t v : t.v) seen.insert(position_bits(mesh.vertices[v]));
    return seen.size();
}

/// Every triangle of `mesh` with three vertices of its own, in triangle order, as STL files
/// and OBJ files read by Assimp store them.
inline Mesh soup_of(const Mesh& mesh)
{
    Mesh soup;
    for (const Triangle& t : mesh.triangles) {
        const auto base = static_cast<std::uint32_t>(soup.vertices.size());
        for (const std::uint32_t v : t.v) soup.vertices.push_back(mesh.vertices[v]);
        soup.triangles.push_back(Triangle{{base, base + 1, base + 2}});
    }
    return soup;
}

/// A binary STL file of `mesh`: 80 header bytes (not starting with "solid", which would mean
/// ASCII), a little-endian uint32 triangle count, then per triangle the unit face normal (as
/// exporters write it, so corners that share a position have different normals), the three
/// corners as float32 and a zero uint16. Little-endian host assumed (the formats' own tests
/// check it).
inline void write_binary_stl(const std::filesystem::path& path, const Mesh& mesh)
{
    std::vector<char> bytes(84 + 50 * mesh.triangles.size(), 0);
    std::memcpy(bytes.data(), "binary STL soup", 15);
    const auto count = static_cast<std::uint32_t>(mesh.triangles.size());
    std::memcpy(bytes.data() + 80, &count, 4);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const MeshView view = mesh.view();
        const auto id = static_cast<std::uint32_t>(t);
        const Vec3f n = normalize(cross(view.vertex(id, 1) - view.vertex(id, 0),
                                        view.vertex(id, 2) - view.vertex(id, 0)));
        const Vec3f record[4] = {n, view.vertex(id, 0), view.vertex(id, 1), view.vertex(id, 2)};
        std::memcpy(bytes.data() + 84 + 50 * t, record, sizeof record);
    }
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace sg::test
