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

/// The place of each choice in StructureKernels::closest. The table is filled
/// (kernels_isa.inc) and read (dispatch.cpp) through these, so a reordered enum cannot make a
/// query run another test's kernel; a new enumerator makes the switch warn (-Wswitch) until
/// it has a place, and the table's completeness check fails until it has its kernels.
inline constexpr std::size_t triangle_test_count = 2;
inline constexpr std::size_t padding_count = 2;
[[nodiscard]] constexpr std::size_t kernel_slot(TriangleTest test) noexcept
{
    switch (test) {
    case TriangleTest::watertight:
        return 0;
    case TriangleTest::moller_trumbore:
        return 1;
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
    ClosestKernel<Structure> closest[triangle_test_count][padding_count][2];
    /// [counting]; watertight test, conservative padding
    AnyKernel<Structure> any[2];

    /// The closest-hit kernel of one choice of test, padding and counting.
    [[nodiscard]] constexpr ClosestKernel<Structure> closest_for(TriangleTest test,
                                                                 Padding padding,
                                                                 bool counting) const noexcept
    {
        return closest[kernel_slot(test)][kernel_slot(padding)][counting ? 1 : 0];
    }
    /// True once every slot holds a kernel.
    [[nodiscard]] constexpr bool is_complete() const noexcept
    {
        for (const auto& by_padding : closest)
            for (const auto& by_counting : by_padding)
                for (const auto kernel : by_counting)
                    if (kernel == nullptr) return false;
        return any[0] != nullptr && any[1] != nullptr;
    }
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
