#pragma once

// The table of traversal kernels: every structure's closest-hit and any-hit batch queries,
// for each triangle test, padding and counting choice, as compiled for one instruction set
// (kernels_<isa>.cpp). dispatch.cpp picks the table of the active instruction set.

#include <cstdint>
#include <span>

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

template <class Structure>
struct StructureKernels {
    /// [TriangleTest][Padding][counting]
    ClosestKernel<Structure> closest[2][2][2];
    /// [counting]; watertight test, conservative padding
    AnyKernel<Structure> any[2];
};

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
