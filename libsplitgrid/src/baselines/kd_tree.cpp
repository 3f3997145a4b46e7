#include "splitgrid/baselines/kd_tree.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "../config_check.hpp"
#include "build_common.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/clip.hpp"
#include "splitgrid/error.hpp"

namespace sg {
namespace {

// Nodes with at least this many triangles build their two subtrees as parallel tasks (and
// clip in parallel); the subtrees are then concatenated in the serial builder's order.
constexpr std::size_t parallel_threshold = 32768;

// A triangle inside a node: the extent of its polygon clipped to the node's padded box,
// widened by the pad and rounded outward to floats. lo < hi on every axis, since pad > 0.
struct Prim {
    std::uint32_t tri;
    std::array<float, 3> lo;
    std::array<float, 3> hi;
};

// A finished subtree in the final layout, with node and reference indices local to it.
struct Subtree {
    std::vector<KdNode> nodes;
    std::vector<std::uint32_t> refs;
    std::uint32_t depth = 0;
};

struct SplitChoice {
    int axis = -1;
    float plane = 0.0f;
};

// Node indices and leaf sizes have 30 bits, reference positions 32.
std::uint32_t checked_index(std::size_t index)
{
    if (index > KdNode::max_index)
        throw InputError("kd-tree: more than 2^30 - 1 nodes, or references in one leaf");
    return static_cast<std::uint32_t>(index);
}
std::uint32_t checked_ref(std::size_t position)
{
    if (position >= std::numeric_limits<std::uint32_t>::max())
        throw InputError("kd-tree: more than 2^32 - 2 triangle references");
    return static_cast<std::uint32_t>(position);
}

class KdBuilder {
public:
    KdBuilder(const MeshView& mesh, const KdTreeConfig& config, float pad, std::uint32_t max_depth)
        : mesh_(mesh), config_(config), pad_(pad), max_depth_(max_depth)
    {
    }

    // The prims of every triangle that touches `box` (the root).
    std::vector<Prim> root_prims(const Aabb& box) const
    {
        const std::size_t n = mesh_.triangle_count();
        std::vector<Prim> all(n);
        std::vector<char> kept(n, 0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t t = r.begin(); t != r.end(); ++t)
                                  kept[t] = clip(static_cast<std::uint32_t>(t), box, all[t]) ? 1 : 0;
                          });
        std::vector<Prim> prims;
        prims.reserve(n);
        for (std::size_t t = 0; t < n; ++t)
            if (kept[t]) prims.push_back(all[t]);
        return prims;
    }

    // Large nodes: the two subtrees as parallel tasks, then concatenated.
    Subtree build(std::vector<Prim> prims, const Aabb& box, std::uint32_t depth) const
    {
        Subtree out;
        if (prims.size() < parallel_threshold) {
            build_serial(out, prims, box, depth);
            return out;
        }
        SplitChoice choice;
        if (!find_split(prims, box, depth, choice)) {
            make_leaf(out, prims, depth);
            return out;
        }
        Aabb below_box = box, above_box = box;
        below_box.upper[choice.axis] = choice.plane;
        above_box.lower[choice.axis] = choice.plane;
        std::vector<Prim> below, above;
        split_prims(prims, choice, below_box, above_box, below, above);
        prims = {};
        Subtree low, high;
        tbb::parallel_invoke([&] { low = build(std::move(below), below_box, depth + 1); },
                             [&] { high = build(std::move(above), above_box, depth + 1); });
        out.depth = std::max(low.depth, high.depth);
        out.nodes.reserve(1 + low.nodes.size() + high.nodes.size());
        out.nodes.push_back(
            KdNode::make_inner(choice.axis, choice.plane, checked_index(1 + low.nodes.size())));
        append(out, low);
        append(out, high);
        return out;
    }

private:
    void build_serial(Subtree& out, std::vector<Prim>& prims, const Aabb& box,
                      std::uint32_t depth) const
    {
        SplitChoice choice;
        if (!find_split(prims, box, depth, choice)) {
            make_leaf(out, prims, depth);
            return;
        }
        Aabb below_box = box, above_box = box;
        below_box.upper[choice.axis] = choice.plane;
        above_box.lower[choice.axis] = choice.plane;
        std::vector<Prim> below, above;
        split_prims(prims, choice, below_box, above_box, below, above);
        std::vector<Prim>().swap(prims);
        const std::size_t index = out.nodes.size();
        out.nodes.emplace_back();
        build_serial(out, below, below_box, depth + 1);
        out.nodes[index] =
            KdNode::make_inner(choice.axis, choice.plane, checked_index(out.nodes.size()));
        build_serial(out, above, above_box, depth + 1);
    }

    void make_leaf(Subtree& out, const std::vector<Prim>& prims, std::uint32_t depth) const
    {
        (void)checked_ref(out.refs.size() + prims.size());
        out.nodes.push_back(
            KdNode::make_leaf(static_cast<std::uint32_t>(out.refs.size()), checked_index(prims.size())));
        for (const Prim& p : prims) out.refs.push_back(p.tri);
        out.depth = std::max(out.depth, depth);
    }

    // Appends a subtree built on its own, shifting its node and reference indices.
    static void append(Subtree& out, const Subtree& part)
    {
        const std::size_t node_base = out.nodes.size();
        (void)checked_ref(out.refs.size() + part.refs.size());
        const auto ref_offset = static_cast<std::uint32_t>(out.refs.size());
        for (const KdNode& n : part.nodes)
            out.nodes.push_back(n.is_leaf()
                                    ? KdNode::make_leaf(n.first_ref() + ref_offset, n.ref_count())
                                    : KdNode::make_inner(n.axis(), n.split(),
                                                         checked_index(n.above_child() + node_base)));
        out.refs.insert(out.refs.end(), part.refs.begin(), part.refs.end());
    }

    // Clips triangle `tri` to `box` padded; false if nothing of it is within the pad.
    bool clip(std::uint32_t tri, const Aabb& box, Prim& out) const noexcept
    {
        Aabbd part;
        if (!clip_triangle_bounds(Vec3d(mesh_.vertex(tri, 0)), Vec3d(mesh_.vertex(tri, 1)),
                                  Vec3d(mesh_.vertex(tri, 2)), Aabbd::from(box).padded(pad_), part))
            return false;
        out.tri = tri;
        for (int k = 0; k < 3; ++k) {
            const auto uk = static_cast<std::size_t>(k);
            out.lo[uk] = detail::float_below(part.lower[k] - pad_);
            out.hi[uk] = detail::float_above(part.upper[k] + pad_);
        }
        return true;
    }

    // The cheapest plane by the SAH, if it beats keeping the node as a leaf.
    bool find_split(const std::vector<Prim>& prims, const Aabb& box, std::uint32_t depth,
                    SplitChoice& best) const
    {
        const std::size_t n = prims.size();
        if (n <= config_.leaf_size || depth >= max_depth_) return false;
        best.axis = -1;
        const double area = box.surface_area();
        if (!(area > 0.0)) return false;
        double best_scaled = static_cast<double>(n) * area;  // the leaf's cost, scaled
        for (int axis = 0; axis < 3; ++axis) {
            if (!(box.lower[axis] < box.upper[axis])) continue;
            // Surface areas of the two children, as functions of the plane.
            const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
            const double e1 = double(box.upper[a1]) - box.lower[a1];
            const double e2 = double(box.upper[a2]) - box.lower[a2];
            // The SAH cost times area / intersection_cost, to keep divisions out of the sweep.
            const double fixed = config_.traversal_cost / config_.intersection_cost * area;
            auto consider = [&](float plane, std::size_t below, std::size_t above) {
                if (!(box.lower[axis] < plane && plane < box.upper[axis])) return;
                const double d_below = double(plane) - box.lower[axis];
                const double d_above = double(box.upper[axis]) - plane;
                const double area_below = 2.0 * (d_below * (e1 + e2) + e1 * e2);
                const double area_above = 2.0 * (d_above * (e1 + e2) + e1 * e2);
                double cost = fixed + area_below * double(below) + area_above * double(above);
                if (below == 0 || above == 0) cost *= 1.0 - config_.empty_bonus;
                if (cost < best_scaled) {
                    best_scaled = cost;
                    best.axis = axis;
                    best.plane = plane;
                }
            };
            if (n < config_.exact_below)
                sweep_events(prims, axis, consider);
            else
                sweep_bins(prims, box, axis, consider);
        }
        return best.axis >= 0;
    }

    // Exact SAH: every triangle boundary is a candidate. Below a plane p are the triangles
    // starting before p, above it those ending after p.
    template <class Consider>
    static void sweep_events(const std::vector<Prim>& prims, int axis, const Consider& consider)
    {
        const std::size_t n = prims.size();
        const auto ua = static_cast<std::size_t>(axis);
        // This thread's buffers: the sweep calls no oneTBB, so no other node can use them
        // before it is done.
        static thread_local std::vector<float> starts, ends;
        starts.resize(n);
        ends.resize(n);
        for (std::size_t k = 0; k < n; ++k) {
            starts[k] = prims[k].lo[ua];
            ends[k] = prims[k].hi[ua];
        }
        std::sort(starts.begin(), starts.end());
        std::sort(ends.begin(), ends.end());
        std::size_t i = 0, j = 0;  // starts before the plane; ends at or before it
        while (i < n || j < n) {
            const float plane = i < n ? std::min(starts[i], ends[j]) : ends[j];
            std::size_t i_next = i, j_next = j;
            while (i_next < n && starts[i_next] == plane) ++i_next;
            while (j_next < n && ends[j_next] == plane) ++j_next;
            consider(plane, i, n - j_next);
            i = i_next;
            j = j_next;
        }
    }

    // Binned SAH: `bins` equal bins over the part of the node the triangles span, plus the
    // two planes that cut off the empty space at either end.
    template <class Consider>
    void sweep_bins(const std::vector<Prim>& prims, const Aabb& box, int axis,
                    const Consider& consider) const
    {
        const std::size_t n = prims.size();
        const auto ua = static_cast<std::size_t>(axis);
        float tight_lo = std::numeric_limits<float>::infinity();
        float tight_hi = -tight_lo;
        for (const Prim& p : prims) {
            tight_lo = std::min(tight_lo, p.lo[ua]);
            tight_hi = std::max(tight_hi, p.hi[ua]);
        }
        consider(tight_lo, 0, n);
        consider(tight_hi, n, 0);
        const double lo = std::max(tight_lo, box.lower[axis]);
        const double hi = std::min(tight_hi, box.upper[axis]);
        if (!(lo < hi)) return;
        const std::size_t bins = config_.bins;
        const double scale = static_cast<double>(bins) / (hi - lo);
        auto bin_of = [&](float x) {
            const double b = (double(x) - lo) * scale;
            return b <= 0.0 ? std::size_t{0}
                            : std::min(bins - 1, static_cast<std::size_t>(b));
        };
        std::vector<std::size_t> starts(bins, 0), ends(bins, 0);
        for (const Prim& p : prims) {
            ++starts[bin_of(p.lo[ua])];
            ++ends[bin_of(p.hi[ua])];
        }
        std::size_t below = 0, ended = 0;
        for (std::size_t b = 1; b < bins; ++b) {
            below += starts[b - 1];
            ended += ends[b - 1];
            const auto plane = static_cast<float>(lo + (hi - lo) * static_cast<double>(b) / static_cast<double>(bins));
            consider(plane, below, n - ended);
        }
    }

    // Distributes the prims to the children: below if they start before the plane, above if
    // they end after it; those doing both are clipped again to each child's padded box.
    void split_prims(const std::vector<Prim>& prims, const SplitChoice& choice,
                     const Aabb& below_box, const Aabb& above_box, std::vector<Prim>& below,
                     std::vector<Prim>& above) const
    {
        const auto ua = static_cast<std::size_t>(choice.axis);
        std::vector<std::uint32_t> straddling;
        for (std::size_t k = 0; k < prims.size(); ++k)
            if (prims[k].lo[ua] < choice.plane && prims[k].hi[ua] > choice.plane)
                straddling.push_back(static_cast<std::uint32_t>(k));
        std::vector<Prim> clipped_below(straddling.size()), clipped_above(straddling.size());
        std::vector<char> kept_below(straddling.size()), kept_above(straddling.size());
        auto clip_range = [&](std::size_t begin, std::size_t end) {
            for (std::size_t s = begin; s < end; ++s) {
                const std::uint32_t tri = prims[straddling[s]].tri;
                kept_below[s] = clip(tri, below_box, clipped_below[s]) ? 1 : 0;
                kept_above[s] = clip(tri, above_box, clipped_above[s]) ? 1 : 0;
            }
        };
        if (straddling.size() >= 1024)
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, straddling.size(), 256),
                              [&](const tbb::blocked_range<std::size_t>& r) { clip_range(r.begin(), r.end()); });
        else
            clip_range(0, straddling.size());
        below.reserve(prims.size() / 2 + straddling.size());
        above.reserve(prims.size() / 2 + straddling.size());
        std::size_t s = 0;
        for (std::size_t k = 0; k < prims.size(); ++k) {
            if (s < straddling.size() && straddling[s] == k) {
                if (kept_below[s]) below.push_back(clipped_below[s]);
                if (kept_above[s]) above.push_back(clipped_above[s]);
                ++s;
            } else if (prims[k].lo[ua] < choice.plane) {
                below.push_back(prims[k]);
            } else {
                above.push_back(prims[k]);
            }
        }
    }

    const MeshView& mesh_;
    const KdTreeConfig& config_;
    const float pad_;
    const std::uint32_t max_depth_;
};

}  // namespace

void KdTreeConfig::validate() const
{
    using detail::check_config_range;
    check_config_range("KdTreeConfig", "traversal_cost", traversal_cost, 0.0, 1e6, true);
    check_config_range("KdTreeConfig", "intersection_cost", intersection_cost, 0.0, 1e6, true);
    check_config_range("KdTreeConfig", "empty_bonus", empty_bonus, 0.0, 1.0);
    if (!(empty_bonus < 1.0)) throw ConfigError("KdTreeConfig.empty_bonus must be below 1");
    check_config_range("KdTreeConfig", "max_depth", max_depth, 0, kd_max_supported_depth);
    check_config_range("KdTreeConfig", "leaf_size", leaf_size, 1, 1u << 20);
    check_config_range("KdTreeConfig", "bins", bins, 2, 1024);
    check_config_range("KdTreeConfig", "exact_below", exact_below, 0, 1u << 30);
    check_config_range("KdTreeConfig", "threads", threads, 0, 1024);
}

std::uint32_t KdTreeConfig::depth_limit(std::size_t triangles) const noexcept
{
    if (max_depth > 0) return max_depth;
    const double n = static_cast<double>(std::max<std::size_t>(triangles, 1));
    const double automatic = std::round(8.0 + 1.3 * std::log2(n));
    return static_cast<std::uint32_t>(std::min<double>(automatic, kd_max_supported_depth));
}

KdTree KdTree::build(const MeshView& mesh, const KdTreeConfig& config)
{
    config.validate();
    KdTree tree;
    Subtree built;
    detail::run_with_threads(config.threads, [&] {
        const Aabb scene = detail::checked_build_bounds(mesh, "kd-tree");
        tree.triangle_count_ = static_cast<std::uint32_t>(mesh.triangle_count());
        if (mesh.triangle_count() == 0) return;
        const float pad = boundary_pad(scene);
        tree.box_ = padded_root_box(scene, pad);
        const KdBuilder builder(mesh, config, pad, config.depth_limit(mesh.triangle_count()));
        built = builder.build(builder.root_prims(tree.box_), tree.box_, 0);
    });
    tree.nodes_ = std::move(built.nodes);
    tree.refs_ = std::move(built.refs);
    tree.depth_ = built.depth;
    return tree;
}

std::size_t KdTree::leaf_count() const noexcept
{
    return static_cast<std::size_t>(
        std::count_if(nodes_.begin(), nodes_.end(), [](const KdNode& n) { return n.is_leaf(); }));
}

}  // namespace sg
