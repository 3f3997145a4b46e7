#include "bench_structure.hpp"

#include <chrono>

#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/traverse.hpp"

namespace sg::bench {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void add(TraversalCounters& sum, const TraversalCounters& c)
{
    sum.nodes_visited += c.nodes_visited;
    sum.cells_visited += c.cells_visited;
    sum.triangles_tested += c.triangles_tested;
}

// Calls f.template operator()<Test, padding>() for the variant's policies, so that each
// variant's per-ray loop is compiled with its test and padding inlined.
template <class F>
void with_policies(const QueryVariant& v, F&& f)
{
    const bool pad = v.padding == Padding::Conservative;
    if (v.test == TriangleTestKind::Watertight) {
        if (pad) f.template operator()<WatertightTest, Padding::Conservative>();
        else f.template operator()<WatertightTest, Padding::None>();
    } else {
        if (pad) f.template operator()<MollerTrumboreTest, Padding::Conservative>();
        else f.template operator()<MollerTrumboreTest, Padding::None>();
    }
}

class SplitGridStructure final : public BenchStructure {
public:
    SplitGridStructure(const MeshView& mesh, BuildConfig config, unsigned threads) : mesh_(mesh)
    {
        config.threads = threads;
        const auto start = std::chrono::steady_clock::now();
        grid_ = build_split_grid(mesh, config);
        build_seconds_ = seconds_since(start);
    }
    double build_seconds() const override { return build_seconds_; }
    std::size_t structure_bytes() const override { return grid_.memory_bytes(); }
    std::size_t reference_count() const override { return grid_.triangle_refs.size(); }
    bool supports(const QueryVariant&) const override { return true; }
    void intersect(std::span<const Ray> rays, std::span<Hit> hits,
                   const QueryVariant& variant) const override
    {
        with_policies(variant, [&]<class Test, Padding padding>() {
            for (std::size_t k = 0; k < rays.size(); ++k)
                hits[k] = intersect_with<Test, padding>(grid_, mesh_, rays[k]);
        });
    }
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> out) const override
    {
        for (std::size_t k = 0; k < rays.size(); ++k)
            out[k] = sg::occluded(grid_, mesh_, rays[k]) ? 1 : 0;
    }
    bool count_work(std::span<const Ray> rays, bool any_hit, TraversalCounters& sum) const override
    {
        for (const Ray& r : rays) {
            TraversalCounters c;
            if (any_hit) (void)sg::occluded(grid_, mesh_, r, &c);
            else (void)sg::intersect(grid_, mesh_, r, &c);
            add(sum, c);
        }
        return true;
    }

private:
    MeshView mesh_;
    SplitGrid grid_;
    double build_seconds_ = 0.0;
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
        with_policies(variant, [&]<class Test, Padding padding>() {
            for (std::size_t k = 0; k < rays.size(); ++k)
                hits[k] = structure_.template intersect_with<Test, padding>(mesh_, rays[k]);
        });
    }
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> out) const override
    {
        for (std::size_t k = 0; k < rays.size(); ++k)
            out[k] = structure_.occluded(mesh_, rays[k]) ? 1 : 0;
    }
    bool count_work(std::span<const Ray> rays, bool any_hit, TraversalCounters& sum) const override
    {
        for (const Ray& r : rays) {
            TraversalCounters c;
            if (any_hit) (void)structure_.occluded(mesh_, r, &c);
            else (void)structure_.intersect(mesh_, r, &c);
            add(sum, c);
        }
        return true;
    }

private:
    MeshView mesh_;
    Structure structure_;
    double build_seconds_ = 0.0;
};

}  // namespace

std::string variant_name(const QueryVariant& variant)
{
    std::string name =
        variant.test == TriangleTestKind::Watertight ? "watertight" : "moller-trumbore";
    if (variant.padding == Padding::None) name += "-nopad";
    return name;
}

std::vector<QueryVariant> all_variants()
{
    return {{TriangleTestKind::Watertight, Padding::Conservative},
            {TriangleTestKind::Watertight, Padding::None},
            {TriangleTestKind::MollerTrumbore, Padding::Conservative},
            {TriangleTestKind::MollerTrumbore, Padding::None}};
}

std::vector<std::string> structure_names()
{
    std::vector<std::string> names{"splitgrid", "uniform_grid", "kd_tree", "bvh"};
    if (has_embree()) names.push_back("embree");
    return names;
}

std::unique_ptr<BenchStructure> build_structure(const std::string& name, const MeshView& mesh,
                                                const StructureConfigs& configs,
                                                unsigned threads)
{
    if (name == "splitgrid")
        return std::make_unique<SplitGridStructure>(mesh, configs.split_grid, threads);
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
