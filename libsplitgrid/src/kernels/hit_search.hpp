#pragma once

// Traversal kernels, part 3: the bookkeeping of one query (closest or any hit, the work
// counters) and the mailbox of the structures that reference a triangle from several cells.

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

/// The state of one query: the closest hit so far (or, with any_hit, whether one was found),
/// the window [t_min, best_t] the next triangle is tested over, and the work counters when
/// `counting` (a separate instantiation, so that the fast path carries no counting code).
template <bool any_hit, bool counting>
class HitSearch {
public:
    HitSearch(float t_min, float t_max, TraversalCounters* counters) noexcept
        : t_min_(t_min), best_t_(t_max), counters_(counters)
    {
    }

    [[nodiscard]] float t_min() const noexcept { return t_min_; }
    /// t_max of the ray until a hit is found, then the closest hit's t.
    [[nodiscard]] float best_t() const noexcept { return best_t_; }
    [[nodiscard]] bool found() const noexcept { return found_; }
    /// True once an any-hit query may stop.
    [[nodiscard]] bool done() const noexcept { return any_hit && found_; }
    [[nodiscard]] const Hit& hit() const noexcept { return hit_; }

    /// Offers a hit of triangle `tri` at t (already known to lie in [t_min, best_t()]): kept
    /// if it is closer than the hit so far, or as close with a smaller triangle id, so that
    /// the answer does not depend on the order the walk meets triangles in (it is the one
    /// intersect_brute_force finds in id order). True if kept.
    bool offer(float t, std::uint32_t tri, float u, float v) noexcept
    {
        if (found_ && !(t < best_t_ || (t == best_t_ && tri < hit_.triangle))) return false;
        found_ = true;
        best_t_ = t;
        hit_ = Hit{t, tri, u, v};
        return true;
    }

    void count_node() noexcept
    {
        if constexpr (counting) ++counters_->nodes_visited;
    }
    void count_cell() noexcept
    {
        if constexpr (counting) ++counters_->cells_visited;
    }
    void count_triangles(std::uint32_t n) noexcept
    {
        if constexpr (counting) counters_->triangles_tested += n;
    }

private:
    float t_min_;
    float best_t_;
    bool found_ = false;
    Hit hit_;
    TraversalCounters* counters_;
};

/// The state of a multi-hit query (count_intersections, list_intersections): every hit in
/// [t_min, t_max], appended to `hits` in the order the walk finds them. The window never
/// shrinks, so the walk visits every cell and node the ray crosses in it. A triangle that
/// several cells reference can be offered more than once (the mailbox forgets on a
/// collision); sort_distinct_hits removes the copies afterwards, so no copy can slip through.
class HitCollector {
public:
    HitCollector(float t_min, float t_max, std::vector<Hit>& hits) noexcept
        : t_min_(t_min), t_max_(t_max), hits_(hits)
    {
    }

    [[nodiscard]] float t_min() const noexcept { return t_min_; }
    [[nodiscard]] float best_t() const noexcept { return t_max_; }
    [[nodiscard]] static constexpr bool done() noexcept { return false; }

    /// Records the hit; never "kept" in HitSearch's sense (nothing ends the walk).
    bool offer(float t, std::uint32_t tri, float u, float v) noexcept
    {
        hits_.push_back(Hit{t, tri, u, v});
        return false;
    }

    static constexpr void count_node() noexcept {}
    static constexpr void count_cell() noexcept {}
    static constexpr void count_triangles(std::uint32_t) noexcept {}

private:
    float t_min_;
    float t_max_;
    std::vector<Hit>& hits_;
};

/// The triangles one query has tested, for structures that reference a triangle from several
/// cells (Amanatides and Woo 1987): a triangle met again is skipped, since its answer cannot
/// change (the window only shrinks). Direct-mapped on the id's low bits, so a look-up is one
/// load and one compare; a collision forgets the older triangle, which is then tested again
/// (correct, only slower). Neighbouring cells share triangles with nearby ids, which the low
/// bits tell apart. Lives on the query's stack: concurrent queries share nothing.
class Mailbox {
public:
    Mailbox() noexcept { std::memset(slots_, 0xFF, sizeof slots_); }
#if SG_KERNEL_ISA_LEVEL >= 2
    /// Of the lanes set in `lanes`, those whose id was not recorded (or was evicted since);
    /// records the ids of all lanes. Every lane must hold an id that is tested now: the
    /// unused ones a copy of a used one. One gather and eight stores.
    std::uint32_t filter(vint id, std::uint32_t lanes) noexcept
    {
        const vint slot = id & static_cast<std::int32_t>(size - 1);
        const std::uint32_t seen = lane_bits(gather(slots_, slot) == id);
        for (int l = 0; l < 8; ++l) slots_[slot[l]] = id[l];
        return lanes & ~seen;
    }
#else
    /// True if `id` was not recorded (or was evicted since); records it. The scalar kernels'
    /// filter, one triangle at a time.
    bool is_fresh(std::uint32_t id) noexcept
    {
        const auto word = static_cast<std::int32_t>(id);
        std::int32_t& slot = slots_[id & (size - 1)];
        if (slot == word) return false;
        slot = word;
        return true;
    }
#endif

private:
    static constexpr std::uint32_t size = 32;
    std::int32_t slots_[size];
};

/// Stands in for a Mailbox in structures that reference every triangle once (the BVH).
struct NoMailbox {
#if SG_KERNEL_ISA_LEVEL >= 2
    static constexpr std::uint32_t filter(vint, std::uint32_t lanes) noexcept { return lanes; }
#else
    static constexpr bool is_fresh(std::uint32_t) noexcept { return true; }
#endif
};

}  // namespace sg::kernels::SG_KERNEL_ISA
