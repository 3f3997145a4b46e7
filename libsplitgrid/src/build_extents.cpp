#include "build_extents.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace sg::detail {
namespace {

// A triangle's bounding box `whole` intersected with `clip_box`
// (BuildConfig::clip_triangles off); false when they do not touch.
bool clip_triangle_box(const Aabbd& whole, const Aabbd& clip_box, Aabbd& out) noexcept
{
    for (int k = 0; k < 3; ++k) {
        out.lower[k] = std::max(whole.lower[k], clip_box.lower[k]);
        out.upper[k] = std::min(whole.upper[k], clip_box.upper[k]);
        if (out.lower[k] > out.upper[k]) return false;
    }
    return true;
}

// A whole triangle's size per axis (TriExtent::size) from its bounding box.
Vec3f size_of(const Aabbd& whole) noexcept
{
    Vec3f size;
    for (int k = 0; k < 3; ++k) size[k] = static_cast<float>(whole.upper[k] - whole.lower[k]);
    return size;
}

// body(begin, end) over [0, n): serially below parallel_grain, else in parallel blocks.
template <class F>
void run(std::size_t n, const F& body)
{
    if (n < parallel_grain) {
        body(0, n);
        return;
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, parallel_grain / 4),
                      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
}

}  // namespace

TriExtent clipped_extent(const BuildContext& context, std::uint32_t tri,
                         const Aabbd& clip_box) noexcept
{
    const Vec3d a(context.mesh.vertex(tri, 0));
    const Vec3d b(context.mesh.vertex(tri, 1));
    const Vec3d c(context.mesh.vertex(tri, 2));
    const Aabbd whole = triangle_box(a, b, c);
    Aabbd clipped;
    if (context.config.clip_triangles ? !clip_triangle_bounds(a, b, c, clip_box, clipped)
                                      : !clip_triangle_box(whole, clip_box, clipped))
        return empty_extent();
    return rounded_extent(clipped, size_of(whole));
}

void clip_unknown(const BuildContext& context, const Aabb& box, const std::uint32_t* tris,
                  TriExtent* extents, std::size_t n)
{
    const Aabbd clip_box = Aabbd::from(box).padded(context.pad);
    run(n, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k)
            if (!extents[k].known) extents[k] = clipped_extent(context, tris[k], clip_box);
    });
}

template <class Extents>
ExtentSummary summarize(const BuildContext& context, const Extents& extents)
{
    struct Sums {
        Aabb tight;
        std::array<double, 3> size{};
        std::size_t kept = 0;
    };
    const bool sizes = context.config.min_cell_width > 0.0;
    auto body = [&](const tbb::blocked_range<std::size_t>& r, Sums sums) {
        for (std::size_t k = r.begin(); k < r.end(); ++k) {
            const TriExtent& e = extents[k];
            if (e.is_empty) continue;
            sums.tight.extend(Aabb{e.lower, e.upper});
            if (!sizes) continue;
            for (int i = 0; i < 3; ++i) sums.size[static_cast<std::size_t>(i)] += e.size[i];
            ++sums.kept;
        }
        return sums;
    };
    const tbb::blocked_range<std::size_t> all(0, extents.size(), parallel_grain);
    const Sums sums =
        extents.size() < parallel_grain
            ? body(all, Sums{})
            : tbb::parallel_deterministic_reduce(all, Sums{}, body, [](Sums a, const Sums& b) {
                  a.tight.extend(b.tight);
                  for (std::size_t i = 0; i < 3; ++i) a.size[i] += b.size[i];
                  a.kept += b.kept;
                  return a;
              });
    ExtentSummary summary;
    summary.tight = sums.tight;
    if (sums.kept > 0)
        for (std::size_t i = 0; i < 3; ++i)
            summary.mean_size[i] = sums.size[i] / static_cast<double>(sums.kept);
    return summary;
}

template ExtentSummary summarize(const BuildContext&, const StoredExtents&);
template ExtentSummary summarize(const BuildContext&, const WholeExtents&);

}  // namespace sg::detail
