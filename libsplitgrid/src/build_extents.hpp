#pragma once

// The Split Grid builder's first seam: each triangle's extent inside a node's box (its piece
// clipped to the box, as floats rounded outward), the arrays that carry them down the tree,
// and the summary a node's planning reads from them (split_planning.hpp).

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/build_config.hpp"
#include "splitgrid/clip.hpp"
#include "splitgrid/float_step.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/vec3.hpp"

namespace sg::detail {

// Nodes with fewer triangles than this do their per-triangle work serially, and their
// subtrees are built by one thread (NodeBuilder::build_serial): below it the task overhead
// outweighs the work. The grid depends on it only through rounding: above it a straddling
// triangle is clipped to each cell's box, below it to the node's box and cut at the cells'
// planes (the same pieces up to double rounding). It does not depend on the thread count.
inline constexpr std::size_t parallel_grain = 4096;

// What every step of one build reads: the mesh, the parameters and the boundary pad
// (boundary_pad of the scene's box).
struct BuildContext {
    const MeshView& mesh;
    const BuildConfig& config;
    float pad;
};

// Clipped extent of one triangle inside a node box, in floats rounded outward, and the
// size of the whole (unclipped) triangle. `known` is false for an extent not computed yet.
struct TriExtent {
    Vec3f lower;
    Vec3f upper;
    Vec3f size;
    bool is_empty = false;
    bool known = false;
};

// Leaves the elements a container adds without arguments (std::vector's resize) unwritten,
// where std::allocator fills them (with zeros, or a type's default member initializers):
// the top of the tree sizes its arrays of triangle ids and extents and then writes every
// element, and filling them first was a pass over tens of megabytes per level
// (docs/notebook/build.md, "The top nodes' triangles handed out in parallel"). For types whose
// bytes may be left as they are until written: trivially copyable and destructible (so that
// the allocation itself creates them, as for malloc).
template <class T>
struct UninitializedAllocator {
    using value_type = T;
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);

    UninitializedAllocator() noexcept = default;
    template <class U>
    UninitializedAllocator(const UninitializedAllocator<U>& /*other*/) noexcept
    {
    }

    T* allocate(std::size_t n) { return std::allocator<T>{}.allocate(n); }
    void deallocate(T* p, std::size_t n) noexcept { std::allocator<T>{}.deallocate(p, n); }
    void construct(T* /*p*/) noexcept {}
    template <class... Args>
    void construct(T* p, Args&&... args)
    {
        ::new (static_cast<void*>(p)) T(std::forward<Args>(args)...);
    }

    template <class U>
    bool operator==(const UninitializedAllocator<U>& /*other*/) const noexcept
    {
        return true;
    }
};

// The triangle ids and extents of a node in the parallel top of the tree.
using TriangleIds = std::vector<std::uint32_t, UninitializedAllocator<std::uint32_t>>;
using ExtentArray = std::vector<TriExtent, UninitializedAllocator<TriExtent>>;

// What planning a node needs from its triangles' extents, gathered in one pass over them: the
// tight box of the clipped pieces and, per axis, the mean size of the whole triangles whose
// pieces are not empty (BuildConfig::min_cell_width; zero where there are none, and when
// min_cell_width is off).
struct ExtentSummary {
    Aabb tight;
    std::array<double, 3> mean_size{};
};

// The extents a node's steps read (plan_cell, distribute), one per triangle of the node, in
// the node's order: stored in an array...
struct StoredExtents {
    TriExtent* items;
    std::size_t count;

    std::size_t size() const noexcept { return count; }
    const TriExtent& operator[](std::size_t k) const noexcept { return items[k]; }
};

// ... or, at the root, computed where they are read: every triangle lies in the root's box,
// so its extent there is its own bounding box, whose corners are floats already (what
// rounded_extent gives for it: the clipped_extent of a triangle inside its box). The root
// then fills no array of them, a large part of a build that faulted in fresh memory every
// time (docs/notebook/build.md, "The root without an array of extents").
struct WholeExtents {
    const MeshView* mesh;
    const std::uint32_t* tris;
    std::size_t count;

    std::size_t size() const noexcept { return count; }
    TriExtent operator[](std::size_t k) const noexcept
    {
        const Vec3f a = mesh->vertex(tris[k], 0);
        const Vec3f b = mesh->vertex(tris[k], 1);
        const Vec3f c = mesh->vertex(tris[k], 2);
        // triangle_box and size_of in floats: the same box and sizes, without the conversions
        // to double, in a step the root takes up to three times per triangle; through
        // triangle_box and size_of the whole build was measurably slower.
        TriExtent e;
        e.known = true;
        for (int i = 0; i < 3; ++i) {
            e.lower[i] = std::min({a[i], b[i], c[i]});
            e.upper[i] = std::max({a[i], b[i], c[i]});
            // As size_of: the difference in double, then rounded to float.
            e.size[i] = static_cast<float>(double(e.upper[i]) - double(e.lower[i]));
        }
        return e;
    }
};

// The extent of a clipped piece in floats, rounded outward so it still contains it.
[[nodiscard]] inline TriExtent rounded_extent(const Aabbd& clipped, Vec3f size) noexcept
{
    TriExtent e;
    e.known = true;
    for (int k = 0; k < 3; ++k) {
        e.lower[k] = float_not_above(clipped.lower[k]);
        e.upper[k] = float_not_below(clipped.upper[k]);
    }
    e.size = size;
    return e;
}

// The extent of a triangle that does not touch the box.
[[nodiscard]] inline TriExtent empty_extent() noexcept
{
    TriExtent e;
    e.known = true;
    e.is_empty = true;
    return e;
}

// Triangle `tri`'s extent inside `clip_box` (a node's box, padded): its piece clipped to the
// box, or its bounding box clipped to it when BuildConfig::clip_triangles is off.
[[nodiscard]] TriExtent clipped_extent(const BuildContext& context, std::uint32_t tri,
                                       const Aabbd& clip_box) noexcept;

// Clips, to `box` padded by the boundary pad, the n triangles `tris` whose entry in
// `extents` is not known yet.
void clip_unknown(const BuildContext& context, const Aabb& box, const std::uint32_t* tris,
                  TriExtent* extents, std::size_t n);

// The tight box (min and max are exact, so any order gives the same box, up to the sign
// of a zero, which the pad added to each side of it erases) and the mean sizes, in one
// pass. Below parallel_grain triangles the sizes are summed in the triangles' order; from
// parallel_grain up in parallel, in pieces that the triangle count alone fixes (halved
// until at most parallel_grain), added in a fixed order
// (tbb::parallel_deterministic_reduce): either way the sums do not depend on the thread
// count. Defined for StoredExtents and WholeExtents.
template <class Extents>
[[nodiscard]] ExtentSummary summarize(const BuildContext& context, const Extents& extents);

}  // namespace sg::detail
