#pragma once

// Edge counts of a mesh by a plain ordered map, independent of sg::edge_report's sort and
// hash: vertices at the same position are one (-0 and +0 alike), an edge is the sorted pair of
// its ends' positions, and every triangle adds each of its three edges once.

#include <array>
#include <cstdint>
#include <map>
#include <utility>

#include "splitgrid/mesh.hpp"

namespace sg::test {

struct EdgeCounts {
    std::uint64_t edges = 0;
    std::uint64_t open_edges = 0;         ///< shared by an odd number of triangles
    std::uint64_t nonmanifold_edges = 0;  ///< shared by more than two
};

inline EdgeCounts count_edges(const Mesh& mesh)
{
    using Key = std::array<float, 3>;
    const auto key = [&](std::uint32_t v) {
        const Vec3f p = mesh.vertices[v];
        return Key{p.x + 0.0f, p.y + 0.0f, p.z + 0.0f};  // -0 + 0 is +0
    };
    std::map<std::pair<Key, Key>, std::uint64_t> uses;
    for (const Triangle& t : mesh.triangles) {
        const std::array<std::uint32_t, 3>& v = t.v;
        for (std::size_t e = 0; e < 3; ++e) {
            Key a = key(v[e]), b = key(v[(e + 1) % 3]);
            if (b < a) std::swap(a, b);
            ++uses[{a, b}];
        }
    }
    EdgeCounts counts;
    for (const auto& [edge, n] : uses) {
        ++counts.edges;
        counts.open_edges += n % 2;
        counts.nonmanifold_edges += n > 2 ? 1 : 0;
    }
    return counts;
}

}  // namespace sg::test
