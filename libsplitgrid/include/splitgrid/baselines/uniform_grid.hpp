#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/cell_math.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/structure_queries.hpp"

namespace sg {

/// Parameters of the uniform grid (a comparison structure for sg-bench; docs/BASELINES.md).
///
/// Resolution rule (the usual cube-root rule, Cleary and Wyvill 1988; Wald et al. 2006): the
/// cells are cubes of edge s chosen so that the grid has about density * N cells for N
/// triangles, s = cbrt(volume / (density * N)), and an axis of extent e gets round(e / s)
/// cells. An axis thinner than one cell (a flat or thin scene) gets one cell and s is
/// recomputed over the other axes (square root, or the extent itself), so flat scenes are
/// not cut into slivers. The product is then capped at max_cells.
struct UniformGridConfig {
    /// Cells per triangle (lambda). Range (0, 1e4]. 4, the usual choice: on scans a denser
    /// grid traces no faster and costs memory, on an architectural scene speed still rises
    /// with the density up to 8 (docs/BASELINES.md, "Uniform grid", has the measurements).
    double density = 4.0;
    /// Most cells in total (each costs a 4-byte offset). Range [1, 2^30]. 2^26 cells = 256 MiB
    /// of offsets; the rule reaches it at 16.7 million triangles with the default density.
    std::uint64_t max_cells = std::uint64_t{1} << 26;
    /// Cells per axis, overriding the rule when all three are non-zero (tests place geometry
    /// on known cell planes; sg-bench may sweep it). Each in [0, 2^20]; all zero or all set.
    std::array<std::uint32_t, 3> resolution{0, 0, 0};
    /// Worker threads for the build; 0 means all hardware threads. Range [0, 1024]. The grid
    /// is identical for every value.
    unsigned threads = 0;

    /// Throws ConfigError naming the first field out of range.
    void validate() const;
    friend bool operator==(const UniformGridConfig&, const UniformGridConfig&) = default;
};

/// Cells per axis that the resolution rule of UniformGridConfig gives for a scene whose
/// (unpadded) bounding box is `scene` and which has `triangles` triangles. {1, 1, 1} for an
/// empty scene. Each entry is in [1, 2^20] and their product is at most config.max_cells.
[[nodiscard]] std::array<std::uint32_t, 3> grid_resolution(const Aabb& scene,
                                                           std::size_t triangles,
                                                           const UniformGridConfig& config);

/// A uniform grid over the scene's bounding box (padded by boundary_pad), traversed with the
/// 3D-DDA of Amanatides and Woo ("A Fast Voxel Traversal Algorithm for Ray Tracing",
/// Eurographics 1987), stepped as nested per-axis walks so that it is conservative (see walk).
///
/// Storage (compact, 32-bit): `cell_offsets` has cell_count() + 1 entries; cell c (linear
/// index (z * ny + y) * nx + x) references triangles refs[cell_offsets[c] ..
/// cell_offsets[c + 1]), in increasing id order. A triangle is referenced by every cell whose
/// box, padded by boundary_pad, its polygon overlaps; overlap is decided exactly by clipping
/// the triangle in double precision (clip.hpp), first to the cell's x slab, then its y slab.
/// Cell planes on each axis come from CellMath, the same mapping at build and traversal.
class UniformGrid : public StructureQueries<UniformGrid> {
public:
    using Config = UniformGridConfig;

    /// Builds the grid. Throws ConfigError for a bad config, InputError for a bad mesh (see
    /// check_mesh) or one with 2^32 - 1 triangles or references or more. An empty mesh gives
    /// an empty grid on which every query misses. Cost: O(references) after a parallel
    /// per-triangle pass; the counting sort into cells is serial.
    [[nodiscard]] static UniformGrid build(const MeshView& mesh, const UniformGridConfig& config = {});

    // Queries (intersect, occluded): StructureQueries (structure_queries.hpp), traversed by
    // src/kernels/uniform_grid_walk.hpp. Counters: cells_visited = cells stepped through
    // (side cells included).

    /// Bytes of the grid itself: the box, resolution, offsets and references (not the mesh).
    [[nodiscard]] std::size_t memory_bytes() const noexcept
    {
        return sizeof(box_) + sizeof(resolution_) + sizeof(triangle_count_) +
               cell_offsets_.size() * sizeof(std::uint32_t) + refs_.size() * sizeof(std::uint32_t);
    }

    /// The grid's box: the scene's bounding box padded by boundary_pad (empty for no triangles).
    [[nodiscard]] const Aabb& box() const noexcept { return box_; }
    /// Cells per axis ({0, 0, 0} for an empty mesh).
    [[nodiscard]] const std::array<std::uint32_t, 3>& resolution() const noexcept
    {
        return resolution_;
    }
    /// The cell planes on `axis` (0, 1, 2). Precondition: the mesh was not empty.
    [[nodiscard]] CellMath axis_cells(int axis) const noexcept
    {
        return CellMath(box_.lower[axis], box_.upper[axis], resolution_[static_cast<std::size_t>(axis)]);
    }
    [[nodiscard]] std::size_t cell_count() const noexcept
    {
        return cell_offsets_.empty() ? 0 : cell_offsets_.size() - 1;
    }
    [[nodiscard]] std::size_t empty_cell_count() const noexcept;
    [[nodiscard]] std::size_t reference_count() const noexcept { return refs_.size(); }
    [[nodiscard]] std::uint32_t triangle_count() const noexcept { return triangle_count_; }
    /// Triangles referenced by the cell (x, y, z), in increasing id order.
    [[nodiscard]] std::span<const std::uint32_t> cell_triangles(std::uint32_t x, std::uint32_t y,
                                                                std::uint32_t z) const noexcept
    {
        const std::size_t c = cell_index(x, y, z);
        return {refs_.data() + cell_offsets_[c], refs_.data() + cell_offsets_[c + 1]};
    }

    friend bool operator==(const UniformGrid&, const UniformGrid&) = default;

    /// Linear index of the cell (x, y, z) into cell_offsets().
    [[nodiscard]] std::size_t cell_index(std::uint32_t x, std::uint32_t y, std::uint32_t z) const noexcept
    {
        return (std::size_t{z} * resolution_[1] + y) * resolution_[0] + x;
    }
    /// cell_count() + 1 offsets into refs(): cell c holds refs()[offsets[c], offsets[c + 1]).
    [[nodiscard]] std::span<const std::uint32_t> cell_offsets() const noexcept { return cell_offsets_; }
    [[nodiscard]] std::span<const std::uint32_t> refs() const noexcept { return refs_; }

private:
    Aabb box_;
    std::array<std::uint32_t, 3> resolution_{0, 0, 0};
    std::uint32_t triangle_count_ = 0;
    std::vector<std::uint32_t> cell_offsets_;
    std::vector<std::uint32_t> refs_;
};

}  // namespace sg
