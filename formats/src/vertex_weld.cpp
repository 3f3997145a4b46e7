// Welding of bit-identical vertex positions (vertex_weld.hpp), with a small open-addressing
// hash table of our own. Assimp's aiProcess_JoinIdenticalVertices is not used for this: it
// compares positions with a tolerance of four float units in the last place (SpatialSort.h,
// FindIdenticalPositions), so it would move vertices, and it also keeps vertices apart whose
// normals or texture coordinates differ.

#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "splitgrid/error.hpp"
#include "splitgrid/formats/vertex_weld.hpp"

namespace sg {
namespace {

constexpr std::uint32_t unused = std::numeric_limits<std::uint32_t>::max();

using PositionBits = std::array<std::uint32_t, 3>;

PositionBits bits_of(Vec3f p) noexcept
{
    return {std::bit_cast<std::uint32_t>(p.x), std::bit_cast<std::uint32_t>(p.y),
            std::bit_cast<std::uint32_t>(p.z)};
}

/// Mixes the 96 bits of a position into 64 (the multipliers and the final avalanche are
/// those of splitmix64), so that neighbouring grid points spread over the whole table.
std::uint64_t hash_of(const PositionBits& b) noexcept
{
    std::uint64_t h = (std::uint64_t{b[0]} << 32) | b[1];
    h ^= std::uint64_t{b[2]} * 0x9E3779B97F4A7C15ull;
    h ^= h >> 30;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 27;
    h *= 0x94D049BB133111EBull;
    h ^= h >> 31;
    return h;
}

/// Slots for `count` keys: a power of two at least twice as large, so linear probing stays
/// short (about 1.5 probes per lookup at half load).
std::size_t table_size_for(std::size_t count)
{
    std::size_t size = 16;
    while (size < 2 * count) size *= 2;
    return size;
}

}  // namespace

WeldReport weld_identical_vertices(Mesh& mesh)
{
    const std::size_t vertex_count = mesh.vertices.size();
    if (vertex_count >= unused)
        throw InputError("more than 2^32 - 2 vertices, the limit of 32-bit indices");

    // new_index[v]: 0 marks "referenced" in the first pass, the welded index after the second.
    std::vector<std::uint32_t> new_index(vertex_count, unused);
    std::size_t referenced = 0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (const std::uint32_t v : mesh.triangles[t].v) {
            if (v >= vertex_count)
                throw InputError("triangle " + std::to_string(t) + " has vertex index " +
                                 std::to_string(v) + " but the mesh has " +
                                 std::to_string(vertex_count) + " vertices");
            if (new_index[v] == unused) ++referenced;
            new_index[v] = 0;
        }
    }

    // In vertex order, so the first occurrence of each position keeps its place. The welded
    // vertices are compacted in place: output index <= input index, and the table refers to
    // the already written prefix mesh.vertices[0, kept).
    std::vector<std::uint32_t> table(table_size_for(referenced), unused);
    const std::size_t mask = table.size() - 1;
    std::uint32_t kept = 0;
    for (std::size_t v = 0; v < vertex_count; ++v) {
        if (new_index[v] == unused) continue;
        const Vec3f position = mesh.vertices[v];
        const PositionBits key = bits_of(position);
        std::size_t slot = static_cast<std::size_t>(hash_of(key)) & mask;
        while (table[slot] != unused && bits_of(mesh.vertices[table[slot]]) != key)
            slot = (slot + 1) & mask;
        if (table[slot] == unused) {
            table[slot] = kept;
            mesh.vertices[kept++] = position;
        }
        new_index[v] = table[slot];
    }
    mesh.vertices.resize(kept);
    mesh.vertices.shrink_to_fit();
    for (Triangle& t : mesh.triangles)
        for (std::uint32_t& v : t.v) v = new_index[v];
    return {referenced, kept};
}

}  // namespace sg
