#include "splitgrid/mesh_order.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>

#include "splitgrid/aabb.hpp"
#include "splitgrid/error.hpp"

namespace sg {
namespace {

constexpr int bits_per_axis = 21;
constexpr double steps_per_axis = double{1u << bits_per_axis};
constexpr std::uint64_t largest_step = (std::uint64_t{1} << bits_per_axis) - 1;

/// The 21 bits of `q` spread to every third bit of a 64-bit word (bit k to bit 3k).
std::uint64_t spread_bits(std::uint64_t q) noexcept
{
    q &= largest_step;
    q = (q | (q << 32)) & 0x001F00000000FFFFull;
    q = (q | (q << 16)) & 0x001F0000FF0000FFull;
    q = (q | (q << 8)) & 0x100F00F00F00F00Full;
    q = (q | (q << 4)) & 0x10C30C30C30C30C3ull;
    q = (q | (q << 2)) & 0x1249249249249249ull;
    return q;
}

/// The step of `c` on an axis starting at `lo` with `steps_per_unit` steps per unit length.
std::uint64_t step_of(double c, double lo, double steps_per_unit) noexcept
{
    const double s = (c - lo) * steps_per_unit;
    if (!(s > 0.0)) return 0;  // below the box, or NaN
    return s >= double{largest_step} ? largest_step : static_cast<std::uint64_t>(s);
}

/// Morton codes over a box: 2^21 steps per axis of it (an axis of zero extent: one step).
class MortonGrid {
public:
    explicit MortonGrid(const Aabb& box) noexcept
    {
        for (int a = 0; a < 3; ++a) {
            lo_[a] = box.lower[a];
            const double extent = double{box.upper[a]} - double{box.lower[a]};
            scale_[a] = extent > 0.0 ? steps_per_axis / extent : 0.0;
        }
    }
    [[nodiscard]] std::uint64_t code(const double (&c)[3]) const noexcept
    {
        std::uint64_t code = 0;
        for (int a = 0; a < 3; ++a) code |= spread_bits(step_of(c[a], lo_[a], scale_[a])) << a;
        return code;
    }

private:
    double lo_[3];
    double scale_[3];
};

/// The ids sorted by their codes; equal codes keep their order.
std::vector<std::uint32_t> sorted_by_code(std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed)
{
    std::sort(keyed.begin(), keyed.end());
    std::vector<std::uint32_t> order(keyed.size());
    for (std::size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
    return order;
}

}  // namespace

std::vector<std::uint32_t> morton_order(const MeshView& mesh)
{
    const std::size_t count = mesh.triangles.size();
    if (count > std::numeric_limits<std::uint32_t>::max())
        throw InputError("more than 2^32 - 1 triangles, the limit of 32-bit triangle ids");
    const MortonGrid grid(checked_bounds(mesh));
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(count);
    for (std::size_t t = 0; t < count; ++t) {
        double centroid[3] = {0.0, 0.0, 0.0};
        for (int a = 0; a < 3; ++a) {
            for (const std::uint32_t v : mesh.triangles[t].v) centroid[a] += mesh.vertices[v][a];
            centroid[a] /= 3.0;
        }
        keyed[t] = {grid.code(centroid), static_cast<std::uint32_t>(t)};
    }
    return sorted_by_code(std::move(keyed));
}

std::vector<std::uint32_t> morton_order(std::span<const Vec3f> points, const Aabb& box)
{
    const MortonGrid grid(box);
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double c[3] = {points[i].x, points[i].y, points[i].z};
        keyed[i] = {grid.code(c), static_cast<std::uint32_t>(i)};
    }
    return sorted_by_code(std::move(keyed));
}

Mesh extract_triangles(const MeshView& mesh, std::span<const std::uint32_t> ids)
{
    constexpr std::uint32_t unused = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> new_index(mesh.vertices.size(), unused);
    Mesh out;
    out.triangles.reserve(ids.size());
    for (const std::uint32_t id : ids) {
        if (id >= mesh.triangles.size())
            throw ConfigError("extract_triangles: triangle " + std::to_string(id) +
                              " is past the mesh's " + std::to_string(mesh.triangles.size()));
        Triangle triangle = mesh.triangles[id];
        for (std::uint32_t& v : triangle.v) {
            if (v >= new_index.size())
                throw InputError("triangle " + std::to_string(id) + ": vertex index " +
                                 std::to_string(v) + " is past the vertex array");
            if (new_index[v] == unused) {
                new_index[v] = static_cast<std::uint32_t>(out.vertices.size());
                out.vertices.push_back(mesh.vertices[v]);
            }
            v = new_index[v];
        }
        out.triangles.push_back(triangle);
    }
    return out;
}

void reorder_triangles(Mesh& mesh, std::span<const std::uint32_t> order)
{
    check_mesh(mesh.view());
    const std::size_t count = mesh.triangles.size();
    std::vector<bool> seen(count, false);
    if (order.size() != count)
        throw ConfigError("reorder_triangles: the order must name every triangle once");
    for (const std::uint32_t id : order) {
        if (id >= count || seen[id])
            throw ConfigError("reorder_triangles: the order must name every triangle once");
        seen[id] = true;
    }
    mesh = extract_triangles(mesh.view(), order);
}

}  // namespace sg
