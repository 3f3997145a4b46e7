#include "splitgrid/baselines/uniform_grid.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "../config_check.hpp"
#include "build_common.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/clip.hpp"
#include "splitgrid/error.hpp"

namespace sg {
namespace {

constexpr std::uint32_t max_axis_resolution = 1u << 20;

// Triangles per parallel task of the assignment pass; fixed, so that the per-chunk outputs
// (and so the reference order) do not depend on the thread count.
constexpr std::size_t chunk_size = 4096;

// Which cells each triangle overlaps (padded cell boxes, exact clipping in double).
class CellAssigner {
public:
    CellAssigner(const MeshView& mesh, const Aabb& box, const std::array<std::uint32_t, 3>& res,
                 float pad)
        : mesh_(mesh), pad_(pad), res_(res),
          cells_{CellMath(box.lower.x, box.upper.x, res[0]), CellMath(box.lower.y, box.upper.y, res[1]),
                 CellMath(box.lower.z, box.upper.z, res[2])},
          clip_box_(Aabbd::from(box).padded(pad))
    {
    }

    // Calls emit(linear cell index) for every cell triangle `tri` overlaps, in increasing
    // (x, then y, then z) order.
    template <class Emit>
    void for_each_cell(std::uint32_t tri, const Emit& emit) const
    {
        const Vec3d a(mesh_.vertex(tri, 0));
        const Vec3d b(mesh_.vertex(tri, 1));
        const Vec3d c(mesh_.vertex(tri, 2));
        const Aabbd whole = triangle_box(a, b, c);
        std::uint32_t x0, x1;
        cell_range(0, whole, x0, x1);
        for (std::uint32_t x = x0; x <= x1; ++x) {
            // The triangle cut to the x slab: its extent on y gives the y cells to look at.
            Aabbd slab_x = clip_box_;
            narrow(slab_x, 0, x);
            Aabbd part_x;
            if (!clip_triangle_bounds(a, b, c, slab_x, part_x)) continue;
            std::uint32_t y0, y1;
            cell_range(1, part_x, y0, y1);
            for (std::uint32_t y = y0; y <= y1; ++y) {
                // The triangle cut to the x-y column: its extent on z is exact, and every z
                // cell it touches overlaps the (convex) clipped polygon.
                Aabbd column = slab_x;
                narrow(column, 1, y);
                Aabbd part_xy;
                if (!clip_triangle_bounds(a, b, c, column, part_xy)) continue;
                std::uint32_t z0, z1;
                cell_range(2, part_xy, z0, z1);
                for (std::uint32_t z = z0; z <= z1; ++z)
                    emit((std::uint64_t{z} * res_[1] + y) * res_[0] + x);
            }
        }
    }

private:
    // Cells on `axis` whose padded slab the extent of `part` touches.
    void cell_range(int axis, const Aabbd& part, std::uint32_t& first, std::uint32_t& last) const
    {
        const CellMath& cm = cells_[static_cast<std::size_t>(axis)];
        first = cm.locate_lowest(detail::float_below(part.lower[axis]) - pad_);
        last = cm.locate_highest(detail::float_above(part.upper[axis]) + pad_);
    }
    // Narrows `box` on `axis` to cell i's slab, padded.
    void narrow(Aabbd& box, int axis, std::uint32_t i) const
    {
        const CellMath& cm = cells_[static_cast<std::size_t>(axis)];
        box.lower[axis] = double(cm.boundary(i)) - pad_;
        box.upper[axis] = double(cm.boundary(i + 1)) + pad_;
    }

    const MeshView& mesh_;
    float pad_;
    std::array<std::uint32_t, 3> res_;
    std::array<CellMath, 3> cells_;
    Aabbd clip_box_;
};

}  // namespace

void UniformGridConfig::validate() const
{
    using detail::check_config_range;
    check_config_range("UniformGridConfig", "density", density, 0.0, 1e4, true);
    check_config_range("UniformGridConfig", "max_cells", max_cells, 1, std::uint64_t{1} << 30);
    const char* names[3] = {"resolution[0]", "resolution[1]", "resolution[2]"};
    for (std::size_t k = 0; k < 3; ++k)
        check_config_range("UniformGridConfig", names[k], resolution[k], 0, max_axis_resolution);
    const bool all_set = resolution[0] > 0 && resolution[1] > 0 && resolution[2] > 0;
    const bool none_set = resolution[0] == 0 && resolution[1] == 0 && resolution[2] == 0;
    if (!all_set && !none_set)
        throw ConfigError("UniformGridConfig.resolution must be all zero (use the rule) or all "
                          "non-zero");
    if (all_set && std::uint64_t{resolution[0]} * resolution[1] * resolution[2] > max_cells)
        throw ConfigError("UniformGridConfig.resolution has more cells than max_cells = " +
                          std::to_string(max_cells));
    check_config_range("UniformGridConfig", "threads", threads, 0, 1024);
}

std::array<std::uint32_t, 3> grid_resolution(const Aabb& scene, std::size_t triangles,
                                             const UniformGridConfig& config)
{
    std::array<std::uint32_t, 3> res{1, 1, 1};
    if (scene.is_empty() || triangles == 0) return res;
    std::array<double, 3> extent{};
    std::array<bool, 3> active{};
    for (int k = 0; k < 3; ++k) {
        const auto uk = static_cast<std::size_t>(k);
        extent[uk] = double(scene.upper[k]) - scene.lower[k];
        active[uk] = extent[uk] > 0.0;
    }
    const double target = config.density * static_cast<double>(triangles);
    // Cube edge s with about `target` cells over the active axes; an axis thinner than s
    // gets one cell and leaves the product, and s is recomputed over the remaining ones.
    double s = 0.0;
    for (;;) {
        double volume = 1.0;
        int dims = 0;
        for (std::size_t k = 0; k < 3; ++k)
            if (active[k]) {
                volume *= extent[k];
                ++dims;
            }
        if (dims == 0) return res;
        s = std::pow(volume / target, 1.0 / dims);
        bool changed = false;
        for (std::size_t k = 0; k < 3; ++k)
            if (active[k] && extent[k] < s) {
                active[k] = false;
                changed = true;
            }
        if (!changed) break;
    }
    for (std::size_t k = 0; k < 3; ++k)
        if (active[k])
            res[k] = static_cast<std::uint32_t>(
                std::clamp(std::round(extent[k] / s), 1.0, double(max_axis_resolution)));
    // The cap: shrink every axis by the same factor until the product fits.
    for (;;) {
        const double cells = double(res[0]) * res[1] * res[2];
        if (cells <= double(config.max_cells)) break;
        const double shrink = std::cbrt(cells / double(config.max_cells)) * (1.0 + 1e-9);
        for (std::uint32_t& r : res)
            r = std::max(1u, static_cast<std::uint32_t>(std::floor(r / shrink)));
    }
    return res;
}

UniformGrid UniformGrid::build(const MeshView& mesh, const UniformGridConfig& config)
{
    config.validate();
    Aabb scene;
    detail::run_with_threads(config.threads,
                             [&] { scene = detail::checked_build_bounds(mesh, "uniform grid"); });
    UniformGrid grid;
    grid.triangle_count_ = static_cast<std::uint32_t>(mesh.triangle_count());
    if (mesh.triangle_count() == 0) return grid;

    const float pad = boundary_pad(scene);
    grid.box_ = padded_root_box(scene, pad);
    const bool fixed = config.resolution[0] > 0;
    grid.resolution_ = fixed ? config.resolution : grid_resolution(scene, mesh.triangle_count(), config);
    const std::size_t cells = std::size_t{grid.resolution_[0]} * grid.resolution_[1] * grid.resolution_[2];

    const CellAssigner assigner(mesh, grid.box_, grid.resolution_, pad);
    const std::size_t n = mesh.triangle_count();
    const std::size_t chunks = (n + chunk_size - 1) / chunk_size;
    // (cell << 32 | triangle) per reference, per chunk of triangles, in triangle order.
    std::vector<std::vector<std::uint64_t>> found(chunks);
    detail::run_with_threads(config.threads, [&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t ch = r.begin(); ch != r.end(); ++ch) {
                                  std::vector<std::uint64_t>& out = found[ch];
                                  out.reserve(2 * chunk_size);
                                  const std::size_t end = std::min(n, (ch + 1) * chunk_size);
                                  for (std::size_t t = ch * chunk_size; t < end; ++t) {
                                      const auto tri = static_cast<std::uint32_t>(t);
                                      assigner.for_each_cell(tri, [&](std::uint64_t cell) {
                                          out.push_back(cell << 32 | tri);
                                      });
                                  }
                              }
                          });
    });

    // Counting sort into cells; visiting chunks in order keeps each cell's ids increasing.
    std::vector<std::uint32_t> counts(cells, 0);
    std::uint64_t total = 0;
    for (const auto& chunk : found) {
        total += chunk.size();
        for (std::uint64_t key : chunk) ++counts[key >> 32];
    }
    if (total >= std::numeric_limits<std::uint32_t>::max())
        throw InputError("uniform grid: more than 2^32 - 2 triangle references; lower the density");
    grid.cell_offsets_.resize(cells + 1);
    std::uint32_t running = 0;
    for (std::size_t c = 0; c < cells; ++c) {
        grid.cell_offsets_[c] = running;
        running += counts[c];
    }
    grid.cell_offsets_[cells] = running;
    grid.refs_.resize(total);
    std::vector<std::uint32_t>& cursor = counts;
    std::copy(grid.cell_offsets_.begin(), grid.cell_offsets_.end() - 1, cursor.begin());
    for (auto& chunk : found) {
        for (std::uint64_t key : chunk)
            grid.refs_[cursor[key >> 32]++] = static_cast<std::uint32_t>(key & 0xFFFFFFFFu);
        chunk = {};
    }
    return grid;
}

std::size_t UniformGrid::empty_cell_count() const noexcept
{
    std::size_t empty = 0;
    for (std::size_t c = 0; c + 1 < cell_offsets_.size(); ++c)
        empty += cell_offsets_[c] == cell_offsets_[c + 1] ? 1 : 0;
    return empty;
}

}  // namespace sg
