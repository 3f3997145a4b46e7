#pragma once

// The table of traversal kernels: every structure's closest-hit and any-hit batch queries,
// for each triangle test, padding and counting choice, as compiled for one instruction set
// (kernels_<isa>.cpp). dispatch.cpp picks the table of the active instruction set.

#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>

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

/// The place of each choice in StructureKernels' arrays. The table is filled
/// (kernels_isa.inc) and read (dispatch.cpp) through these, so a reordered enum cannot make a
/// query run another test's kernel; a new enumerator makes the switch warn (-Wswitch) until
/// it has a place, and the table's completeness check fails until it has its kernels.
/// TriangleTest::watertight_no_tie_break has a place among the counting kernels only: for
/// closest hits it would change nothing but which of two equal hits is kept (query.hpp).
inline constexpr std::size_t closest_test_count = 2;
inline constexpr std::size_t count_test_count = 3;
inline constexpr std::size_t padding_count = 2;
[[nodiscard]] constexpr std::size_t kernel_slot(TriangleTest test) noexcept
{
    switch (test) {
    case TriangleTest::watertight:
        return 0;
    case TriangleTest::moller_trumbore:
        return 1;
    case TriangleTest::watertight_no_tie_break:
        return 2;
    }
    return 0;
}
[[nodiscard]] constexpr std::size_t kernel_slot(Padding padding) noexcept
{
    switch (padding) {
    case Padding::conservative:
        return 0;
    case Padding::none:
        return 1;
    }
    return 0;
}

template <class Structure>
struct StructureKernels {
    /// [kernel_slot(TriangleTest)][kernel_slot(Padding)][counting]
    ClosestKernel<Structure> closest[closest_test_count][padding_count][2];
    /// [counting]; watertight test, conservative padding
    AnyKernel<Structure> any[2];
    /// [kernel_slot(TriangleTest)]; conservative padding
    CountKernel<Structure> count[count_test_count];
    /// watertight test, conservative padding
    AllKernel<Structure> all;
    PointKernel<Structure> closest_point;
    /// One bit per slot, set by the setters below as kernels_isa.inc fills the table. The
    /// completeness check reads these bits instead of comparing kernel addresses with null,
    /// which sanitizer builds do not allow in a constant expression.
    std::uint32_t filled = 0;

    static constexpr std::size_t closest_slots = closest_test_count * padding_count * 2;
    static constexpr std::size_t slot_count = closest_slots + 2 + count_test_count + 2;

    constexpr void set_closest(TriangleTest test, Padding padding, bool counting,
                               ClosestKernel<Structure> kernel) noexcept
    {
        const std::size_t t = kernel_slot(test);
        const std::size_t p = kernel_slot(padding);
        const std::size_t c = counting ? 1 : 0;
        closest[t][p][c] = kernel;
        mark((t * padding_count + p) * 2 + c);
    }
    constexpr void set_any(bool counting, AnyKernel<Structure> kernel) noexcept
    {
        any[counting ? 1 : 0] = kernel;
        mark(closest_slots + (counting ? 1 : 0));
    }
    constexpr void set_count(TriangleTest test, CountKernel<Structure> kernel) noexcept
    {
        count[kernel_slot(test)] = kernel;
        mark(closest_slots + 2 + kernel_slot(test));
    }
    constexpr void set_all(AllKernel<Structure> kernel) noexcept
    {
        all = kernel;
        mark(closest_slots + 2 + count_test_count);
    }
    constexpr void set_closest_point(PointKernel<Structure> kernel) noexcept
    {
        closest_point = kernel;
        mark(closest_slots + 3 + count_test_count);
    }

    /// The closest-hit kernel of one choice of test, padding and counting;
    /// watertight_no_tie_break runs the watertight kernel.
    [[nodiscard]] constexpr ClosestKernel<Structure> closest_for(TriangleTest test,
                                                                 Padding padding,
                                                                 bool counting) const noexcept
    {
        const std::size_t t = test == TriangleTest::moller_trumbore ? kernel_slot(test) : 0;
        return closest[t][kernel_slot(padding)][counting ? 1 : 0];
    }
    /// The counting kernel of one triangle test.
    [[nodiscard]] constexpr CountKernel<Structure> count_for(TriangleTest test) const noexcept
    {
        return count[kernel_slot(test)];
    }
    /// True once every slot has been set.
    [[nodiscard]] constexpr bool is_complete() const noexcept
    {
        return filled == (std::uint32_t{1} << slot_count) - 1;
    }

private:
    constexpr void mark(std::size_t slot) noexcept { filled |= std::uint32_t{1} << slot; }
};

struct KernelTable {
    StructureKernels<SplitGrid> split_grid;
    StructureKernels<Bvh> bvh;
    StructureKernels<KdTree> kd_tree;
    StructureKernels<UniformGrid> uniform_grid;

    [[nodiscard]] constexpr bool is_complete() const noexcept
    {
        return split_grid.is_complete() && bvh.is_complete() && kd_tree.is_complete() &&
               uniform_grid.is_complete();
    }

    template <class Structure>
    [[nodiscard]] const StructureKernels<Structure>& of() const noexcept
    {
        if constexpr (std::is_same_v<Structure, SplitGrid>) return split_grid;
        else if constexpr (std::is_same_v<Structure, Bvh>) return bvh;
        else if constexpr (std::is_same_v<Structure, KdTree>) return kd_tree;
        else return uniform_grid;
    }
};

/// The kernels compiled for each instruction set: the scalar ones everywhere; sse2 where the
/// compiler targets x86-64 (libsplitgrid/CMakeLists.txt builds kernels_sse2.cpp there only);
/// avx2 and avx512 where GCC targets it (SG_KERNEL_AVX2 / SG_KERNEL_AVX512 defined by CMake).
const KernelTable& scalar_kernels() noexcept;
#if defined(__x86_64__)
const KernelTable& sse2_kernels() noexcept;
#endif
#ifdef SG_KERNEL_AVX2
const KernelTable& avx2_kernels() noexcept;
#endif
#ifdef SG_KERNEL_AVX512
const KernelTable& avx512_kernels() noexcept;
#endif

}  // namespace sg::kernels
