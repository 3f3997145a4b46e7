#include "bench_structure.hpp"

#include <algorithm>
#include <chrono>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "cli_common.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/occupancy.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/traverse.hpp"

namespace sg::bench {
namespace {

using apps::seconds_since;

// Runs `query(rays, answers)` over `rays` in chunks with scratch answers (closest hits, or
// any-hit flags), for the work counting of count_work, which keeps no answer.
template <class Query>
void count_in_chunks(std::span<const Ray> rays, bool any_hit, const Query& query)
{
    constexpr std::size_t chunk = 1024;
    std::vector<Hit> hits(std::min(chunk, rays.size()));
    std::vector<std::uint8_t> flags(hits.size());
    for (std::size_t begin = 0; begin < rays.size(); begin += chunk) {
        const std::span<const Ray> part = rays.subspan(begin, std::min(chunk, rays.size() - begin));
        if (any_hit) query(part, std::span<std::uint8_t>(flags.data(), part.size()));
        else query(part, std::span<Hit>(hits.data(), part.size()));
    }
}

// The point and multi-hit queries of one of our structures: the library's, on the structure
// and the mesh its owner holds (both referred to, so a rebuild is seen).
template <class Structure>
class OwnPointQueries final : public PointQueries {
public:
    OwnPointQueries(const Structure& structure, const MeshView& mesh)
        : structure_(structure), mesh_(mesh)
    {
    }
    std::string unavailable(PointQuery) const override { return ""; }
    bool exact_distances() const override { return true; }
    void count_intersections(std::span<const Ray> rays,
                             std::span<std::int32_t> counts) const override
    {
        if constexpr (std::is_same_v<Structure, SplitGrid>)
            sg::count_intersections(structure_, mesh_, rays, counts);
        else
            structure_.count_intersections(mesh_, rays, counts);
    }
    void occupancy(std::span<const Vec3f> points, std::span<float> inside,
                   TriangleTest test) const override
    {
        sg::compute_occupancy(structure_, mesh_, points, inside, 1, test);
    }
    void closest_points(std::span<const Vec3f> points,
                        std::span<ClosestPoint> out) const override
    {
        sg::closest_points(structure_, mesh_, points, out);
    }

private:
    const Structure& structure_;
    const MeshView& mesh_;
};

class SplitGridStructure final : public BenchStructure {
public:
    SplitGridStructure(const MeshView& mesh, BuildConfig config, unsigned threads)
        : mesh_(mesh), config_(config)
    {
        config_.threads = threads;
        const auto start = std::chrono::steady_clock::now();
        grid_ = build_split_grid(mesh, config_);
        build_seconds_ = seconds_since(start);
    }
    /// Builds again on `moved` (the same arrays, vertices moved) into the grid's own memory
    /// (rebuild_split_grid); returns the seconds it took.
    double rebuild(const MeshView& moved)
    {
        mesh_ = moved;
        const auto start = std::chrono::steady_clock::now();
        rebuild_split_grid(grid_, moved, config_);
        return seconds_since(start);
    }
    double build_seconds() const override { return build_seconds_; }
    std::size_t structure_bytes() const override { return grid_.memory_bytes(); }
    std::size_t reference_count() const override { return sg::reference_count(grid_); }
    bool supports(const QueryVariant&) const override { return true; }
    void intersect(std::span<const Ray> rays, std::span<Hit> hits,
                   const QueryVariant& variant) const override
    {
        sg::intersect(grid_, mesh_, rays, hits, nullptr, variant);
    }
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> out) const override
    {
        sg::occluded(grid_, mesh_, rays, out);
    }
    bool count_work(std::span<const Ray> rays, bool any_hit, TraversalCounters& sum) const override
    {
        count_in_chunks(rays, any_hit, [&](std::span<const Ray> r, auto hits_or_flags) {
            if constexpr (std::is_same_v<decltype(hits_or_flags), std::span<Hit>>)
                sg::intersect(grid_, mesh_, r, hits_or_flags, &sum);
            else
                sg::occluded(grid_, mesh_, r, hits_or_flags, &sum);
        });
        return true;
    }
    const PointQueries* point_queries() const override { return &points_; }

private:
    MeshView mesh_;
    BuildConfig config_;
    SplitGrid grid_;
    double build_seconds_ = 0.0;
    OwnPointQueries<SplitGrid> points_{grid_, mesh_};
};

// The comparison structures share one adaptor: the same build/query interface shape.
template <class Structure>
class BaselineStructure final : public BenchStructure {
public:
    BaselineStructure(const MeshView& mesh, typename Structure::Config config, unsigned threads)
        : mesh_(mesh)
    {
        config.threads = threads;
        const auto start = std::chrono::steady_clock::now();
        structure_ = Structure::build(mesh, config);
        build_seconds_ = seconds_since(start);
    }
    double build_seconds() const override { return build_seconds_; }
    std::size_t structure_bytes() const override { return structure_.memory_bytes(); }
    std::size_t reference_count() const override { return structure_.reference_count(); }
    bool supports(const QueryVariant&) const override { return true; }
    void intersect(std::span<const Ray> rays, std::span<Hit> hits,
                   const QueryVariant& variant) const override
    {
        structure_.intersect(mesh_, rays, hits, nullptr, variant);
    }
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> out) const override
    {
        structure_.occluded(mesh_, rays, out);
    }
    bool count_work(std::span<const Ray> rays, bool any_hit, TraversalCounters& sum) const override
    {
        count_in_chunks(rays, any_hit, [&](std::span<const Ray> r, auto hits_or_flags) {
            if constexpr (std::is_same_v<decltype(hits_or_flags), std::span<Hit>>)
                structure_.intersect(mesh_, r, hits_or_flags, &sum);
            else
                structure_.occluded(mesh_, r, hits_or_flags, &sum);
        });
        return true;
    }

    const PointQueries* point_queries() const override { return &points_; }

    /// The structure itself, for the dynamic workload's refit.
    Structure& get() noexcept { return structure_; }

private:
    MeshView mesh_;
    Structure structure_;
    double build_seconds_ = 0.0;
    OwnPointQueries<Structure> points_{structure_, mesh_};
};

// Any structure, built anew on every frame (the one before released first, so that its
// memory goes back to the allocator for the new build).
class RebuiltEachFrame final : public FrameStructureBase {
public:
    RebuiltEachFrame(std::string name, const MeshView& mesh, const StructureConfigs& configs,
                     unsigned threads)
        : name_(std::move(name)), configs_(configs), threads_(threads),
          built_(build_structure(name_, mesh, configs_, threads_))
    {
    }
    const BenchStructure& structure() const override { return *built_; }

protected:
    double next_frame(const MeshView& moved) override
    {
        built_.reset();
        built_ = build_structure(name_, moved, configs_, threads_);
        return built_->build_seconds();
    }

private:
    std::string name_;
    StructureConfigs configs_;
    unsigned threads_;
    std::unique_ptr<BenchStructure> built_;
};

// The Split Grid rebuilt on every frame into the memory of the one before
// (rebuild_split_grid).
class SplitGridRebuilt final : public FrameStructureBase {
public:
    SplitGridRebuilt(const MeshView& mesh, const BuildConfig& config, unsigned threads)
        : grid_(mesh, config, threads)
    {
    }
    const BenchStructure& structure() const override { return grid_; }

protected:
    double next_frame(const MeshView& moved) override { return grid_.rebuild(moved); }

private:
    SplitGridStructure grid_;
};

// Our BVH built on the first frame and refitted on every later one.
class BvhRefitted final : public FrameStructureBase {
public:
    BvhRefitted(const MeshView& mesh, const BvhConfig& config, unsigned threads)
        : bvh_(mesh, config, threads), threads_(threads)
    {
    }
    const BenchStructure& structure() const override { return bvh_; }

protected:
    double next_frame(const MeshView& moved) override
    {
        const auto start = std::chrono::steady_clock::now();
        bvh_.get().refit(moved, threads_);
        return seconds_since(start);
    }

private:
    BaselineStructure<Bvh> bvh_;
    unsigned threads_;
};

}  // namespace

std::vector<std::string> frame_structure_names()
{
    std::vector<std::string> names = structure_names();
    names.push_back("bvh_refit");
    if (has_embree()) {
        names.push_back("embree_low");
        names.push_back("embree_refit");
    }
    return names;
}

std::unique_ptr<FrameStructure> make_frame_structure(const std::string& name,
                                                     const MeshView& mesh,
                                                     const StructureConfigs& configs,
                                                     unsigned threads)
{
    if (name == "splitgrid")
        return std::make_unique<SplitGridRebuilt>(mesh, configs.split_grid, threads);
    if (name == "splitgrid_poster")
        return std::make_unique<SplitGridRebuilt>(
            mesh, apply_build_preset(configs.split_grid, "poster"), threads);
    if (name == "bvh_refit") return std::make_unique<BvhRefitted>(mesh, configs.bvh, threads);
    if (has_embree()) {
        if (name == "embree") return embree_frames(mesh, EmbreeFrameMode::medium, threads);
        if (name == "embree_low") return embree_frames(mesh, EmbreeFrameMode::low, threads);
        if (name == "embree_refit") return embree_frames(mesh, EmbreeFrameMode::refit, threads);
    }
    return std::make_unique<RebuiltEachFrame>(name, mesh, configs, threads);
}

std::string_view point_query_name(PointQuery query) noexcept
{
    switch (query) {
    case PointQuery::count: return "count";
    case PointQuery::occupancy: return "occupancy";
    case PointQuery::closest: return "closest";
    }
    return "";
}

std::string variant_name(const QueryVariant& variant)
{
    std::string name =
        variant.test == TriangleTest::watertight ? "watertight" : "moller-trumbore";
    if (variant.padding == Padding::none) name += "-nopad";
    return name;
}

std::vector<QueryVariant> all_variants()
{
    return {{TriangleTest::watertight, Padding::conservative},
            {TriangleTest::watertight, Padding::none},
            {TriangleTest::moller_trumbore, Padding::conservative},
            {TriangleTest::moller_trumbore, Padding::none}};
}

std::vector<std::string> structure_names()
{
    std::vector<std::string> names{"splitgrid", "splitgrid_poster", "uniform_grid", "kd_tree",
                                   "bvh"};
    if (has_embree()) names.push_back("embree");
    return names;
}

std::unique_ptr<BenchStructure> build_structure(const std::string& name, const MeshView& mesh,
                                                const StructureConfigs& configs,
                                                unsigned threads)
{
    if (name == "splitgrid")
        return std::make_unique<SplitGridStructure>(mesh, configs.split_grid, threads);
    if (name == "splitgrid_poster")
        return std::make_unique<SplitGridStructure>(
            mesh, apply_build_preset(configs.split_grid, "poster"), threads);
    if (name == "uniform_grid")
        return std::make_unique<BaselineStructure<UniformGrid>>(mesh, configs.uniform_grid,
                                                                 threads);
    if (name == "kd_tree")
        return std::make_unique<BaselineStructure<KdTree>>(mesh, configs.kd_tree, threads);
    if (name == "bvh") return std::make_unique<BaselineStructure<Bvh>>(mesh, configs.bvh, threads);
    if (name == "embree" && has_embree()) return build_embree(mesh, configs.embree_robust, threads);
    throw ConfigError("unknown structure '" + name + "'");
}

}  // namespace sg::bench
