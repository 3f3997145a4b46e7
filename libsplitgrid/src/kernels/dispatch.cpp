// Chooses the traversal kernels of the processor's instruction set (query.hpp) and routes
// every query to them.

#include <atomic>
#include <cstdlib>
#include <string>
#include <string_view>

#include "kernel_table.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/query.hpp"

namespace sg {
namespace {

const kernels::KernelTable* table_of(Isa isa) noexcept
{
    switch (isa) {
#ifdef SG_KERNEL_AVX512
    case Isa::avx512:
        return &kernels::avx512_kernels();
#endif
#ifdef SG_KERNEL_AVX2
    case Isa::avx2:
        return &kernels::avx2_kernels();
#endif
#if defined(__x86_64__)
    case Isa::sse2:
        return &kernels::sse2_kernels();
#endif
    case Isa::scalar:
        return &kernels::scalar_kernels();
    default:
        return nullptr;
    }
}

bool cpu_runs(Isa isa) noexcept
{
#if defined(__x86_64__) && defined(__GNUC__)
    __builtin_cpu_init();
    switch (isa) {
    case Isa::scalar:
    case Isa::sse2:
        return true;
    case Isa::avx2:
        return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
               __builtin_cpu_supports("bmi2");
    case Isa::avx512:
        return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
               __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
               __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
               __builtin_cpu_supports("bmi2");
    }
    return false;
#else
    return isa == Isa::scalar;
#endif
}

struct Selection {
    Isa isa;
    std::string note;
};

constexpr Isa every_isa[] = {Isa::scalar, Isa::sse2, Isa::avx2, Isa::avx512};

Selection initial_selection()
{
    Isa best = Isa::scalar;
    for (Isa isa : every_isa)
        if (isa_supported(isa)) best = isa;
    const char* requested = std::getenv("SG_ISA");
    if (requested == nullptr || *requested == '\0') return {best, {}};
    const std::string_view name(requested);
    std::string names;
    for (Isa isa : every_isa) {
        names += (names.empty() ? "" : ", ") + std::string(isa_name(isa));
        if (name != isa_name(isa)) continue;
        if (isa_supported(isa)) return {isa, {}};
        return {best, "SG_ISA=" + std::string(name) + " is not supported by this processor or " +
                          "build; using " + std::string(isa_name(best))};
    }
    return {best, "SG_ISA=" + std::string(name) + " is not one of " + names + "; using " +
                      std::string(isa_name(best))};
}

const Selection& startup_selection()
{
    static const Selection selection = initial_selection();
    return selection;
}

std::atomic<const kernels::KernelTable*>& active_table() noexcept
{
    static std::atomic<const kernels::KernelTable*> table{table_of(startup_selection().isa)};
    return table;
}
std::atomic<Isa>& active_isa() noexcept
{
    static std::atomic<Isa> isa{startup_selection().isa};
    return isa;
}

}  // namespace

std::string_view isa_name(Isa isa) noexcept
{
    switch (isa) {
    case Isa::scalar:
        return "scalar";
    case Isa::sse2:
        return "sse2";
    case Isa::avx2:
        return "avx2";
    case Isa::avx512:
        return "avx512";
    }
    return "unknown";
}

bool isa_supported(Isa isa) noexcept { return table_of(isa) != nullptr && cpu_runs(isa); }

Isa kernel_isa() noexcept { return active_isa().load(std::memory_order_relaxed); }

std::string_view kernel_isa_note() noexcept { return startup_selection().note; }

void set_kernel_isa(Isa isa)
{
    if (!isa_supported(isa))
        throw ConfigError("instruction set " + std::string(isa_name(isa)) +
                          " is not supported by this processor or build");
    active_table().store(table_of(isa), std::memory_order_relaxed);
    active_isa().store(isa, std::memory_order_relaxed);
}

namespace detail {

template <class Structure>
void closest_hits(const Structure& structure, const MeshView& mesh, std::span<const Ray> rays,
                  std::span<Hit> hits, TraversalCounters* total, const QueryOptions& options) noexcept
{
    const auto& k = active_table().load(std::memory_order_relaxed)->template of<Structure>();
    k.closest_for(options.test, options.padding, total != nullptr)(structure, mesh, rays, hits,
                                                                  total);
}

template <class Structure>
void any_hits(const Structure& structure, const MeshView& mesh, std::span<const Ray> rays,
              std::span<std::uint8_t> occluded, TraversalCounters* total) noexcept
{
    const auto& k = active_table().load(std::memory_order_relaxed)->template of<Structure>();
    k.any[total != nullptr](structure, mesh, rays, occluded, total);
}

template <class Structure>
void count_hits(const Structure& structure, const MeshView& mesh, std::span<const Ray> rays,
                std::span<std::int32_t> counts, TriangleTest test) noexcept
{
    const auto& k = active_table().load(std::memory_order_relaxed)->template of<Structure>();
    k.count_for(test)(structure, mesh, rays, counts);
}

template <class Structure>
void all_hits(const Structure& structure, const MeshView& mesh, std::span<const Ray> rays,
              IntersectionList& out)
{
    const auto& k = active_table().load(std::memory_order_relaxed)->template of<Structure>();
    k.all(structure, mesh, rays, out);
}

template void closest_hits(const SplitGrid&, const MeshView&, std::span<const Ray>, std::span<Hit>,
                           TraversalCounters*, const QueryOptions&) noexcept;
template void closest_hits(const Bvh&, const MeshView&, std::span<const Ray>, std::span<Hit>,
                           TraversalCounters*, const QueryOptions&) noexcept;
template void closest_hits(const KdTree&, const MeshView&, std::span<const Ray>, std::span<Hit>,
                           TraversalCounters*, const QueryOptions&) noexcept;
template void closest_hits(const UniformGrid&, const MeshView&, std::span<const Ray>,
                           std::span<Hit>, TraversalCounters*, const QueryOptions&) noexcept;
template void any_hits(const SplitGrid&, const MeshView&, std::span<const Ray>,
                       std::span<std::uint8_t>, TraversalCounters*) noexcept;
template void any_hits(const Bvh&, const MeshView&, std::span<const Ray>, std::span<std::uint8_t>,
                       TraversalCounters*) noexcept;
template void any_hits(const KdTree&, const MeshView&, std::span<const Ray>,
                       std::span<std::uint8_t>, TraversalCounters*) noexcept;
template void any_hits(const UniformGrid&, const MeshView&, std::span<const Ray>,
                       std::span<std::uint8_t>, TraversalCounters*) noexcept;

template <class Structure>
void closest_point_hits(const Structure& structure, const MeshView& mesh,
                        std::span<const Vec3f> points, std::span<const std::uint32_t> order,
                        std::span<ClosestPoint> out, float max_distance) noexcept
{
    const auto& k = active_table().load(std::memory_order_relaxed)->template of<Structure>();
    k.closest_point(structure, mesh, points, order, out, max_distance);
}

#define SG_INSTANTIATE_MULTI_HIT(Structure)                                                   \
    template void count_hits(const Structure&, const MeshView&, std::span<const Ray>,          \
                             std::span<std::int32_t>, TriangleTest) noexcept;                  \
    template void all_hits(const Structure&, const MeshView&, std::span<const Ray>,            \
                           IntersectionList&);                                                   \
    template void closest_point_hits(const Structure&, const MeshView&, std::span<const Vec3f>, \
                                     std::span<const std::uint32_t>, std::span<ClosestPoint>,    \
                                     float) noexcept;
SG_INSTANTIATE_MULTI_HIT(SplitGrid)
SG_INSTANTIATE_MULTI_HIT(Bvh)
SG_INSTANTIATE_MULTI_HIT(KdTree)
SG_INSTANTIATE_MULTI_HIT(UniformGrid)
#undef SG_INSTANTIATE_MULTI_HIT

}  // namespace detail
}  // namespace sg
