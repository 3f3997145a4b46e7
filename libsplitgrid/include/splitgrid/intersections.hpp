#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "splitgrid/ray.hpp"

namespace sg {

/// Every hit along each ray of a batch: the answer of list_intersections, in the layout of
/// Open3D's RaycastingScene::list_intersections. The hits of ray k are
/// hits[ray_splits[k] .. ray_splits[k + 1]), sorted by t, and on equal t by triangle id (Open3D
/// leaves the order unspecified); each triangle appears at most once per ray, however many
/// cells reference it. ray_ids[i] is the ray of hits[i] (its index in the batch).
struct IntersectionList {
    std::vector<std::uint64_t> ray_splits{0};
    std::vector<std::uint32_t> ray_ids;
    std::vector<Hit> hits;

    /// Rays listed so far.
    [[nodiscard]] std::size_t ray_count() const noexcept { return ray_splits.size() - 1; }
    friend bool operator==(const IntersectionList&, const IntersectionList&) = default;
};

/// The lists of consecutive batches of rays as one list, the rays numbered on from one batch
/// to the next (the lists of a batch split into chunks, e.g. one per thread, joined in order).
[[nodiscard]] IntersectionList concatenate(std::span<const IntersectionList> parts);

/// The hits in `hits` (all hits of one ray, found in any order, a triangle possibly more than
/// once) sorted by t, then triangle id, each triangle once. A triangle tested twice along one
/// ray returns the same t, so its copies end up next to each other. Returns the new size.
std::size_t sort_distinct_hits(std::span<Hit> hits) noexcept;

}  // namespace sg
