#include "splitgrid/mesh_edges.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <bit>
#include <unordered_map>
#include <vector>

namespace sg {
namespace {

/// A position's bits, with -0 as +0 (equal coordinates, one key).
std::uint64_t position_hash(Vec3f p) noexcept
{
    auto bits = [](float x) { return std::bit_cast<std::uint32_t>(x == 0.0f ? 0.0f : x); };
    std::uint64_t h = bits(p.x);
    h = h * 0x9E3779B97F4A7C15ull ^ bits(p.y);
    h = h * 0x9E3779B97F4A7C15ull ^ bits(p.z);
    return h;
}

struct PositionKey {
    Vec3f p;
    bool operator==(const PositionKey& o) const noexcept
    {
        return p.x == o.p.x && p.y == o.p.y && p.z == o.p.z;
    }
};
struct PositionKeyHash {
    std::size_t operator()(const PositionKey& k) const noexcept
    {
        return static_cast<std::size_t>(position_hash(k.p));
    }
};

/// For each vertex the first vertex at its position (positions compared as numbers).
std::vector<std::uint32_t> first_at_same_position(std::span<const Vec3f> vertices)
{
    std::vector<std::uint32_t> canonical(vertices.size());
    std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> seen;
    seen.reserve(vertices.size());
    for (std::size_t v = 0; v < vertices.size(); ++v)
        canonical[v] = seen.try_emplace(PositionKey{vertices[v]}, static_cast<std::uint32_t>(v))
                           .first->second;
    return canonical;
}

}  // namespace

EdgeReport edge_report(const MeshView& mesh)
{
    const std::vector<std::uint32_t> canonical = first_at_same_position(mesh.vertices);
    std::vector<std::uint64_t> keys;
    keys.reserve(3 * mesh.triangle_count());
    for (const Triangle& tri : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = canonical[tri.v[static_cast<std::size_t>(k)]];
            std::uint32_t b = canonical[tri.v[static_cast<std::size_t>((k + 1) % 3)]];
            if (a == b) continue;  // a zero-length edge bounds nothing
            if (a > b) std::swap(a, b);
            keys.push_back((std::uint64_t{a} << 32) | b);
        }
    }
    tbb::parallel_sort(keys.begin(), keys.end());
    EdgeReport report;
    for (std::size_t i = 0; i < keys.size();) {
        std::size_t j = i + 1;
        while (j < keys.size() && keys[j] == keys[i]) ++j;
        const std::size_t shared = j - i;
        ++report.edges;
        if (shared % 2 != 0) ++report.open_edges;
        if (shared > 2) ++report.nonmanifold_edges;
        i = j;
    }
    return report;
}

}  // namespace sg
