#pragma once

// The table of traversal kernels: every structure's closest-hit and any-hit batch queries,
// for each triangle test, padding and counting choice, as compiled for one instruction set
// (kernels_<isa>.cpp). dispatch.cpp picks the table of the active instruction set.

#include <cstdint>
#include <span>

#include "splitgrid/baselines/bvh.hpp"
#include "splitgrid/baselines/kd_tree.hpp"
#include "splitgrid/baselines/uniform_grid.hpp"
#include "splitgrid/closest_point.hpp"
#include "splitgrid/intersections.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/query.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/traversal_counters.hpp"

namespace sg::kernels {

/// Closest hits of `rays` into `hits` (same size); adds the work of every ray to `*total`
/// when the kernel counts (total is then not null).
template <class Structure>
using ClosestKernel = void (*)(const Structure&, const MeshView&, std::span<const Ray>,
                               std::span<Hit>, TraversalCounters* total);
/// Any-hit answers (1 = occluded) of `rays` into `occluded`.
template <class Structure>
using AnyKernel = void (*)(const Structure&, const MeshView&, std::span<const Ray>,
                           std::span<std::uint8_t>, TraversalCounters* total);

/// The number of distinct triangles each ray hits, into `counts` (same size).
template <class Structure>
using CountKernel = void (*)(const Structure&, const MeshView&, std::span<const Ray>,
                             std::span<std::int32_t> counts);
/// Every hit of each ray, appended to `out` (its rays numbered on from out.ray_count()).
template <class Structure>
using AllKernel = void (*)(const Structure&, const MeshView&, std::span<const Ray>,
                           IntersectionList& out);

/// The closest point of each of `points` (taken in `order`, a permutation of their
/// indices) into `out` (same size), within `max_distance`.
template <class Structure>
using PointKernel = void (*)(const Structure&, const MeshView&, std::span<const Vec3f> points,
                             std::span<const std::uint32_t> order, std::span<ClosestPoint> out,
                             float max_distance);

template <class Structure>
struct StructureKernels {
    /// [TriangleTest][Padding][counting]; TriangleTest::watertight_no_tie_break is not offered
    /// for closest hits (it changes nothing but which of two equal hits is kept)
    ClosestKernel<Structure> closest[2][2][2];
    /// [counting]; watertight test, conservative padding
    AnyKernel<Structure> any[2];
    /// [TriangleTest]; conservative padding
    CountKernel<Structure> count[3];
    /// watertight test, conservative padding
    AllKernel<Structure> all;
    PointKernel<Structure> closest_point;
};

// The tables are indexed by these enums' values.
static_assert(static_cast<int>(TriangleTest::watertight) == 0 &&
                  static_cast<int>(TriangleTest::moller_trumbore) == 1 &&
                  static_cast<int>(TriangleTest::watertight_no_tie_break) == 2,
              "StructureKernels::closest and ::count are indexed by TriangleTest");
static_assert(static_cast<int>(Padding::conservative) == 0 && static_cast<int>(Padding::none) == 1,
              "StructureKernels::closest is indexed by Padding");

struct KernelTable {
    StructureKernels<SplitGrid> split_grid;
    StructureKernels<Bvh> bvh;
    StructureKernels<KdTree> kd_tree;
    StructureKernels<UniformGrid> uniform_grid;

    template <class Structure>
    [[nodiscard]] const StructureKernels<Structure>& of() const noexcept
    {
        if constexpr (std::is_same_v<Structure, SplitGrid>) return split_grid;
        else if constexpr (std::is_same_v<Structure, Bvh>) return bvh;
        else if constexpr (std::is_same_v<Structure, KdTree>) return kd_tree;
        else return uniform_grid;
    }
};

/// The kernels compiled for each instruction set; avx2 and avx512 only where the compiler
/// targets x86-64 (SG_KERNEL_AVX2 / SG_KERNEL_AVX512 defined by CMake).
const KernelTable& sse2_kernels() noexcept;
#ifdef SG_KERNEL_AVX2
const KernelTable& avx2_kernels() noexcept;
#endif
#ifdef SG_KERNEL_AVX512
const KernelTable& avx512_kernels() noexcept;
#endif

}  // namespace sg::kernels
