#include "splitgrid/baselines/bvh.hpp"

#include <algorithm>
#include <limits>
#include <memory>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

#include "../config_check.hpp"
#include "build_common.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"

namespace sg {
namespace {

// Nodes with at least this many triangles build their two subtrees as parallel tasks and
// bin in parallel; the subtrees are then concatenated in the serial builder's order.
constexpr std::size_t parallel_threshold = 32768;

constexpr std::uint32_t max_bins = 64;

// A finished subtree in the final layout, node indices local to it (root at 0); leaves'
// reference ranges are global, since the triangles are partitioned in place.
struct Subtree {
    std::vector<BvhNode> nodes;
    std::uint32_t depth = 0;
};

// A triangle's padded box and id, partitioned in place node by node (contiguous, so binning
// reads memory in order).
struct PrimRef {
    Aabb box;
    std::uint32_t tri;
};

// A triangle's box widened by `pad` on each side and rounded outward: the box its leaf must
// hold (the build's and the refit's).
Aabb padded_triangle_box(const MeshView& mesh, std::uint32_t tri, float pad) noexcept
{
    Aabb box;
    for (int c = 0; c < 3; ++c) box.extend(mesh.vertex(tri, c));
    for (int k = 0; k < 3; ++k) {
        box.lower[k] = detail::float_below(double(box.lower[k]) - pad);
        box.upper[k] = detail::float_above(double(box.upper[k]) + pad);
    }
    return box;
}

// The coordinate binning and partitioning use: the box centre.
// Writes `box` into slot i of `node`.
void set_slot_box(BvhWideNode& node, int i, const Aabb& box) noexcept
{
    for (int k = 0; k < 3; ++k) {
        node.lower[k][i] = box.lower[k];
        node.upper[k][i] = box.upper[k];
    }
}

// The union of the boxes of `node`'s used slots.
Aabb slots_box(const BvhWideNode& node) noexcept
{
    Aabb box;
    for (int i = 0; i < BvhWideNode::width && node.is_used(i); ++i)
        for (int k = 0; k < 3; ++k) {
            box.lower[k] = std::min(box.lower[k], node.lower[k][i]);
            box.upper[k] = std::max(box.upper[k], node.upper[k][i]);
        }
    return box;
}

float centroid(const PrimRef& p, int axis) noexcept
{
    return 0.5f * p.box.lower[axis] + 0.5f * p.box.upper[axis];
}

// Box of a node's triangles and box of their centroids.
struct Extent {
    Aabb bounds;
    Aabb centroids;
    void add(const PrimRef& p) noexcept
    {
        bounds.extend(p.box);
        centroids.extend(Vec3f{centroid(p, 0), centroid(p, 1), centroid(p, 2)});
    }
    void add(const Extent& o) noexcept
    {
        bounds.extend(o.bounds);
        centroids.extend(o.centroids);
    }
};

// Per axis and bin (entry axis * max_bins + bin): box and number of the triangles whose
// centroid falls in it.
struct Bins {
    std::array<Aabb, 3 * max_bins> bounds;
    std::array<std::uint32_t, 3 * max_bins> count{};
    // Empties the first `bins` bins of each axis (the others are not used).
    void reset(std::uint32_t bins) noexcept
    {
        for (std::size_t k = 0; k < 3; ++k)
            for (std::size_t i = k * max_bins; i < k * max_bins + bins; ++i) {
                bounds[i] = Aabb{};
                count[i] = 0;
            }
    }
    void add(const Bins& o, std::uint32_t bins) noexcept
    {
        for (std::size_t k = 0; k < 3; ++k)
            for (std::size_t i = k * max_bins; i < k * max_bins + bins; ++i) {
                bounds[i].extend(o.bounds[i]);
                count[i] += o.count[i];
            }
    }
};

// How to split a node: triangles whose centroid falls in a bin below `bin` on `axis` go
// left. `median` splits the range in the middle instead (all centroids coincide).
struct Split {
    int axis = 0;
    std::uint32_t bin = 0;
    bool median = false;
};

// Maps a centroid coordinate to its bin on one axis: the one mapping binning and
// partitioning share.
struct BinMap {
    float lo = 0.0f;
    float scale = 0.0f;  // bins / extent; 0 for an axis without extent
    std::uint32_t last = 0;
    [[nodiscard]] std::uint32_t operator()(float c) const noexcept
    {
        const float b = (c - lo) * scale;
        return b > 0.0f ? std::min(last, static_cast<std::uint32_t>(b)) : 0u;
    }
};

class BvhBuilder {
public:
    BvhBuilder(const BvhConfig& config, const MeshView& mesh, float pad)
        : config_(config), prims_(mesh.triangle_count())
    {
        const std::size_t n = mesh.triangle_count();
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t t = r.begin(); t != r.end(); ++t) {
                                  const auto tri = static_cast<std::uint32_t>(t);
                                  prims_[t] = PrimRef{padded_triangle_box(mesh, tri, pad), tri};
                              }
                          });
    }

    Subtree build_all()
    {
        const Extent root = measure(0, prims_.size());
        return build(0, prims_.size(), root, 0);
    }

    /// The triangle ids in leaf order (after build_all).
    std::vector<std::uint32_t> refs() const
    {
        std::vector<std::uint32_t> refs(prims_.size());
        for (std::size_t i = 0; i < prims_.size(); ++i) refs[i] = prims_[i].tri;
        return refs;
    }

private:
    Subtree build(std::size_t begin, std::size_t end, const Extent& extent, std::uint32_t depth)
    {
        Subtree out;
        if (end - begin < parallel_threshold) {
            out.nodes.resize(1);
            build_serial(out, 0, begin, end, extent, depth);
            return out;
        }
        Split split;
        if (!choose_split(begin, end, extent, depth, split)) {
            out.nodes.push_back(make_leaf(extent.bounds, begin, end));
            out.depth = depth;
            return out;
        }
        Extent left_extent, right_extent;
        const std::size_t mid = partition(begin, end, extent, split, left_extent, right_extent);
        Subtree left, right;
        tbb::parallel_invoke([&] { left = build(begin, mid, left_extent, depth + 1); },
                             [&] { right = build(mid, end, right_extent, depth + 1); });
        out.depth = std::max(left.depth, right.depth);
        out.nodes.reserve(left.nodes.size() + right.nodes.size() + 1);
        // [this node, left root, right root, rest of left, rest of right]: left node j > 0
        // moves to j + 2, right node j > 0 to j + left size + 1, as the serial build places them.
        const std::size_t left_offset = 2;
        const std::size_t right_offset = left.nodes.size() + 1;
        out.nodes.push_back(BvhNode::make_inner(extent.bounds, split.axis, 1));
        out.nodes.push_back(relocated(left.nodes[0], left_offset));
        out.nodes.push_back(relocated(right.nodes[0], right_offset));
        for (std::size_t j = 1; j < left.nodes.size(); ++j)
            out.nodes.push_back(relocated(left.nodes[j], left_offset));
        for (std::size_t j = 1; j < right.nodes.size(); ++j)
            out.nodes.push_back(relocated(right.nodes[j], right_offset));
        return out;
    }

    void build_serial(Subtree& out, std::size_t slot, std::size_t begin, std::size_t end,
                      const Extent& extent, std::uint32_t depth)
    {
        Split split;
        if (!choose_split(begin, end, extent, depth, split)) {
            out.nodes[slot] = make_leaf(extent.bounds, begin, end);
            out.depth = std::max(out.depth, depth);
            return;
        }
        Extent left_extent, right_extent;
        const std::size_t mid = partition(begin, end, extent, split, left_extent, right_extent);
        const std::size_t children = out.nodes.size();
        if (children + 2 > std::numeric_limits<std::uint32_t>::max())
            throw InputError("BVH: more than 2^32 - 1 nodes");
        out.nodes.resize(children + 2);
        out.nodes[slot] = BvhNode::make_inner(extent.bounds, split.axis, static_cast<std::uint32_t>(children));
        build_serial(out, children, begin, mid, left_extent, depth + 1);
        build_serial(out, children + 1, mid, end, right_extent, depth + 1);
    }

    static BvhNode relocated(const BvhNode& node, std::size_t offset)
    {
        if (node.is_leaf()) return node;
        const std::size_t child = node.first_child() + offset;
        if (child > std::numeric_limits<std::uint32_t>::max() - 1)
            throw InputError("BVH: more than 2^32 - 1 nodes");
        return BvhNode::make_inner(node.bounds, node.axis(), static_cast<std::uint32_t>(child));
    }

    static BvhNode make_leaf(const Aabb& bounds, std::size_t begin, std::size_t end)
    {
        if (end - begin > BvhNode::max_count)
            throw InputError("BVH: a leaf would hold more than 2^30 - 1 triangles; raise max_depth");
        return BvhNode::make_leaf(bounds, static_cast<std::uint32_t>(begin),
                                  static_cast<std::uint32_t>(end - begin));
    }

    // Runs body(b, e, value) over [begin, end), in parallel for large ranges, joining the
    // partial values with join(a, b); only exact operations (min, max, integer sums) are
    // joined, so the result does not depend on the partition.
    template <class Value, class Body, class Join>
    static Value reduce(std::size_t begin, std::size_t end, const Value& identity, const Body& body,
                        const Join& join)
    {
        if (end - begin < parallel_threshold) {
            Value v = identity;
            body(begin, end, v);
            return v;
        }
        return tbb::parallel_reduce(
            tbb::blocked_range<std::size_t>(begin, end, 8192), identity,
            [&](const tbb::blocked_range<std::size_t>& r, Value v) {
                body(r.begin(), r.end(), v);
                return v;
            },
            [&](Value a, const Value& b) {
                join(a, b);
                return a;
            });
    }

    Extent measure(std::size_t begin, std::size_t end) const
    {
        return reduce(
            begin, end, Extent{},
            [&](std::size_t b, std::size_t e, Extent& x) {
                for (std::size_t i = b; i < e; ++i) x.add(prims_[i]);
            },
            [](Extent& a, const Extent& b) { a.add(b); });
    }

    // Bins for a node of n triangles: config.bins, but no more than n (at least 2), since
    // most of them would stay empty and the sweep costs per bin.
    std::uint32_t bin_count(std::size_t n) const noexcept
    {
        return static_cast<std::uint32_t>(std::clamp<std::size_t>(n, 2, config_.bins));
    }

    std::array<BinMap, 3> bin_maps(const Extent& extent, std::uint32_t bins) const noexcept
    {
        std::array<BinMap, 3> maps;
        for (int k = 0; k < 3; ++k) {
            const float width = extent.centroids.extent(k);
            auto& m = maps[static_cast<std::size_t>(k)];
            m.lo = extent.centroids.lower[k];
            m.scale = width > 0.0f ? static_cast<float>(bins) / width : 0.0f;
            m.last = bins - 1;
        }
        return maps;
    }

    // Half the surface area, in double (float products overflow for boxes near FLT_MAX).
    // Precondition: the box is not empty.
    static double half_area(const Aabb& b) noexcept
    {
        const double dx = double(b.upper.x) - b.lower.x;
        const double dy = double(b.upper.y) - b.lower.y;
        const double dz = double(b.upper.z) - b.lower.z;
        return dx * (dy + dz) + dy * dz;
    }

    bool choose_split(std::size_t begin, std::size_t end, const Extent& extent, std::uint32_t depth,
                      Split& split) const
    {
        const std::size_t n = end - begin;
        if (n <= config_.leaf_size || depth >= config_.max_depth) return false;
        const std::uint32_t count = bin_count(n);
        const std::array<BinMap, 3> maps = bin_maps(extent, count);
        if (maps[0].scale == 0.0f && maps[1].scale == 0.0f && maps[2].scale == 0.0f) {
            // Nothing to tell the triangles apart: a leaf if small enough, else halves.
            if (n <= config_.max_leaf_size) return false;
            split.axis = extent.bounds.longest_axis();
            split.median = true;
            return true;
        }
        auto fill = [&](std::size_t b, std::size_t e, Bins& x) {
            for (std::size_t i = b; i < e; ++i) {
                const PrimRef& p = prims_[i];
                const std::size_t slot_x = maps[0](centroid(p, 0));
                const std::size_t slot_y = max_bins + maps[1](centroid(p, 1));
                const std::size_t slot_z = 2 * max_bins + maps[2](centroid(p, 2));
                x.bounds[slot_x].extend(p.box);
                x.bounds[slot_y].extend(p.box);
                x.bounds[slot_z].extend(p.box);
                ++x.count[slot_x];
                ++x.count[slot_y];
                ++x.count[slot_z];
            }
        };
        // Small nodes bin into this thread's scratch (no 5 KB copy per node); nothing in
        // between can run another node on this thread, since binning calls no oneTBB.
        static thread_local Bins scratch;
        const Bins* bins_ptr = &scratch;
        std::unique_ptr<Bins> large;
        if (n < parallel_threshold) {
            scratch.reset(count);
            fill(begin, end, scratch);
        } else {
            large = std::make_unique<Bins>(reduce(begin, end, Bins{}, fill,
                                                  [&](Bins& a, const Bins& b) { a.add(b, count); }));
            bins_ptr = large.get();
        }
        const Bins& bins = *bins_ptr;
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < 3; ++k) {
            if (maps[k].scale == 0.0f) continue;
            const Aabb* bin_bounds = bins.bounds.data() + k * max_bins;
            const std::uint32_t* bin_count = bins.count.data() + k * max_bins;
            // Right-to-left: area times count of everything from bin i up (only entries
            // 1 .. count - 1 are written and read).
            std::array<double, max_bins> right_cost;
            Aabb box;
            std::size_t right = 0;
            for (std::uint32_t i = count - 1; i > 0; --i) {
                if (bin_count[i] > 0) {
                    box.extend(bin_bounds[i]);
                    right += bin_count[i];
                }
                right_cost[i] = right > 0 ? half_area(box) * static_cast<double>(right) : 0.0;
            }
            box = Aabb{};
            std::size_t left = 0;
            for (std::uint32_t i = 1; i < count; ++i) {
                if (bin_count[i - 1] == 0) continue;  // the same split as the bin before
                box.extend(bin_bounds[i - 1]);
                left += bin_count[i - 1];
                if (left == n) break;
                const double cost = half_area(box) * static_cast<double>(left) + right_cost[i];
                if (cost < best) {
                    best = cost;
                    split.axis = static_cast<int>(k);
                    split.bin = i;
                }
            }
        }
        if (!(best < std::numeric_limits<double>::infinity())) return false;
        const double area = half_area(extent.bounds);
        const double split_cost = config_.traversal_cost + (area > 0.0 ? best / area : 0.0);
        return n > config_.max_leaf_size || split_cost < static_cast<double>(n);
    }

    // Moves the left triangles of `split` before the right ones (in place, Hoare style) and
    // measures both sides on the way.
    std::size_t partition(std::size_t begin, std::size_t end, const Extent& extent,
                          const Split& split, Extent& left, Extent& right)
    {
        if (split.median) {
            const std::size_t mid = begin + (end - begin) / 2;
            left = measure(begin, mid);
            right = measure(mid, end);
            return mid;
        }
        const BinMap map = bin_maps(extent, bin_count(end - begin))[static_cast<std::size_t>(split.axis)];
        auto goes_left = [&](const PrimRef& p) { return map(centroid(p, split.axis)) < split.bin; };
        std::size_t i = begin, j = end;
        for (;;) {
            while (i < j && goes_left(prims_[i])) left.add(prims_[i++]);
            while (i < j && !goes_left(prims_[j - 1])) right.add(prims_[--j]);
            if (i >= j) break;
            std::swap(prims_[i], prims_[j - 1]);
        }
        return i;
    }

    const BvhConfig& config_;
    std::vector<PrimRef> prims_;
};

}  // namespace

void BvhConfig::validate() const
{
    using detail::check_config_range;
    check_config_range("BvhConfig", "bins", bins, 2, max_bins);
    check_config_range("BvhConfig", "max_leaf_size", max_leaf_size, 1, 1u << 20);
    check_config_range("BvhConfig", "leaf_size", leaf_size, 1, max_leaf_size);
    check_config_range("BvhConfig", "traversal_cost", traversal_cost, 0.0, 1e6, true);
    check_config_range("BvhConfig", "max_depth", max_depth, 1, bvh_max_supported_depth);
    check_config_range("BvhConfig", "threads", threads, 0, 1024);
}

Bvh Bvh::build(const MeshView& mesh, const BvhConfig& config)
{
    config.validate();
    Bvh bvh;
    Subtree built;
    detail::run_with_threads(config.threads, [&] {
        const Aabb scene = detail::checked_build_bounds(mesh, "BVH");
        bvh.triangle_count_ = static_cast<std::uint32_t>(mesh.triangle_count());
        if (mesh.triangle_count() == 0) return;
        BvhBuilder builder(config, mesh, boundary_pad(scene));
        built = builder.build_all();
        bvh.refs_ = builder.refs();
    });
    bvh.depth_ = built.depth;
    bvh.collapse(built.nodes);
    return bvh;
}

// Each wide node takes a binary inner node's two children and, while it has fewer than width,
// opens the inner one of largest surface area (its children take its slot), so that the
// boxes a ray is most likely to enter are tested together. Depth first, parents before
// children; a function of the binary tree alone. A root that is a leaf becomes a wide node
// with that one leaf.
void Bvh::collapse(std::span<const BvhNode> binary)
{
    wide_.clear();
    leaf_count_ = 0;
    box_ = Aabb{};
    if (binary.empty()) return;
    constexpr int width = BvhWideNode::width;
    struct Pending {
        std::uint32_t wide;  // the wide node whose slot it fills
        int slot;
        std::uint32_t binary;  // the binary node whose children it holds
    };
    std::vector<Pending> pending{{0, -1, 0}};
    while (!pending.empty()) {
        const Pending p = pending.back();
        pending.pop_back();
        const auto index = static_cast<std::uint32_t>(wide_.size());
        if (p.slot >= 0) wide_[p.wide].child[p.slot] = index;
        std::array<std::uint32_t, width> slots{};
        int used = 1;
        if (binary[p.binary].is_leaf()) {
            slots[0] = p.binary;  // the root is a leaf
        } else {
            slots[0] = binary[p.binary].first_child();
            slots[1] = slots[0] + 1;
            used = 2;
        }
        while (used < width) {
            int open = -1;
            double open_area = -1.0;
            for (int i = 0; i < used; ++i) {
                const BvhNode& n = binary[slots[static_cast<std::size_t>(i)]];
                if (n.is_leaf()) continue;
                const double area = n.bounds.surface_area();
                if (area > open_area) {
                    open = i;
                    open_area = area;
                }
            }
            if (open < 0) break;
            const std::uint32_t opened = binary[slots[static_cast<std::size_t>(open)]].first_child();
            for (int i = used; i > open + 1; --i)
                slots[static_cast<std::size_t>(i)] = slots[static_cast<std::size_t>(i - 1)];
            slots[static_cast<std::size_t>(open)] = opened;
            slots[static_cast<std::size_t>(open + 1)] = opened + 1;
            ++used;
        }
        BvhWideNode wide{};
        for (int i = 0; i < width; ++i) {
            wide.child[i] = BvhWideNode::unused_slot;
            wide.count[i] = 0;
            Aabb box;  // empty: +infinity below, -infinity above
            if (i < used) {
                const BvhNode& n = binary[slots[static_cast<std::size_t>(i)]];
                box = n.bounds;
                if (n.is_leaf()) {
                    wide.child[i] = n.first_ref();
                    wide.count[i] = n.ref_count();
                    ++leaf_count_;
                }
            }
            set_slot_box(wide, i, box);
        }
        wide_.push_back(wide);
        // Children in reverse, so that they are laid out in slot order.
        for (int i = used; i-- > 0;)
            if (!binary[slots[static_cast<std::size_t>(i)]].is_leaf())
                pending.push_back({index, i, slots[static_cast<std::size_t>(i)]});
    }
    box_ = binary[0].bounds;
}

void Bvh::refit(const MeshView& mesh, unsigned threads)
{
    detail::run_with_threads(threads, [&] {
        const Aabb scene = detail::checked_build_bounds(mesh, "BVH refit");
        if (mesh.triangle_count() != triangle_count_)
            throw InputError("BVH refit: the mesh has " + std::to_string(mesh.triangle_count()) +
                             " triangles, the BVH was built on " + std::to_string(triangle_count_));
        if (wide_.empty()) return;
        const float pad = boundary_pad(scene);
        // Leaf slots first, in parallel: each reads only its own triangles.
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, wide_.size(), 1024),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t w = r.begin(); w != r.end(); ++w) {
                                  BvhWideNode& node = wide_[w];
                                  for (int i = 0; i < BvhWideNode::width; ++i) {
                                      if (!node.is_used(i) || !node.is_leaf(i)) continue;
                                      Aabb box;
                                      for (std::uint32_t j = 0; j < node.count[i]; ++j)
                                          box.extend(padded_triangle_box(
                                              mesh, refs_[node.child[i] + j], pad));
                                      set_slot_box(node, i, box);
                                  }
                              }
                          });
    });
    if (wide_.empty()) return;
    // Then the inner slots, children before parents: a node's children always follow it.
    for (std::size_t w = wide_.size(); w-- > 0;) {
        BvhWideNode& node = wide_[w];
        for (int i = 0; i < BvhWideNode::width; ++i)
            if (node.is_used(i) && !node.is_leaf(i))
                set_slot_box(node, i, slots_box(wide_[node.child[i]]));
    }
    box_ = slots_box(wide_[0]);
}

}  // namespace sg
