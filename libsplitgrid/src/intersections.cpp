#include "splitgrid/intersections.hpp"

#include <algorithm>

namespace sg {

IntersectionList concatenate(std::span<const IntersectionList> parts)
{
    IntersectionList out;
    std::size_t rays = 0, hits = 0;
    for (const IntersectionList& part : parts) {
        rays += part.ray_count();
        hits += part.hits.size();
    }
    out.ray_splits.reserve(rays + 1);
    out.ray_ids.reserve(hits);
    out.hits.reserve(hits);
    std::uint32_t first_ray = 0;
    for (const IntersectionList& part : parts) {
        const std::uint64_t first_hit = out.hits.size();
        for (std::size_t k = 1; k < part.ray_splits.size(); ++k)
            out.ray_splits.push_back(first_hit + part.ray_splits[k]);
        for (std::uint32_t id : part.ray_ids) out.ray_ids.push_back(first_ray + id);
        out.hits.insert(out.hits.end(), part.hits.begin(), part.hits.end());
        first_ray += static_cast<std::uint32_t>(part.ray_count());
    }
    return out;
}

std::size_t sort_distinct_hits(std::span<Hit> hits) noexcept
{
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
        return a.t < b.t || (a.t == b.t && a.triangle < b.triangle);
    });
    const auto end = std::unique(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
        return a.triangle == b.triangle;
    });
    return static_cast<std::size_t>(end - hits.begin());
}

}  // namespace sg
