// The traversal kernels of every instruction set compiled in (query.hpp): each must return
// bit-identical answers, and the batched triangle test must compute exactly what the scalar
// watertight test computes (brute force, which is plain scalar code, is the reference). The
// scalar kernels, which every processor runs, are the reference of the comparisons between
// instruction sets.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "splitgrid/baselines/bvh.hpp"
#include "splitgrid/baselines/kd_tree.hpp"
#include "splitgrid/baselines/uniform_grid.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/closest_point.hpp"
#include "splitgrid/query.hpp"
#include "splitgrid/ray_triangle.hpp"
#include "splitgrid/traverse.hpp"
#include "support/oracle.hpp"
#include "support/random_scene.hpp"

namespace sg::test {
namespace {

const Aabb scene_box{{0, 0, 0}, {10, 10, 10}};

constexpr Isa every_isa[] = {Isa::scalar, Isa::sse2, Isa::avx2, Isa::avx512};

// Restores the instruction set the process started with.
class IsaGuard {
public:
    IsaGuard() : saved_(kernel_isa()) {}
    ~IsaGuard() { set_kernel_isa(saved_); }
    IsaGuard(const IsaGuard&) = delete;
    IsaGuard& operator=(const IsaGuard&) = delete;

private:
    Isa saved_;
};

std::vector<Isa> supported_isas()
{
    std::vector<Isa> out;
    for (Isa isa : every_isa)
        if (isa_supported(isa)) out.push_back(isa);
    return out;
}

// Rays of every kind the kernels treat apart: random, aimed at triangles, at edge midpoints
// and vertices (exact zero edge functions take the double-precision path), with zero
// direction components, and from far away.
std::vector<Ray> mixed_rays(const Mesh& mesh)
{
    std::vector<Ray> rays = random_rays(11, 3000, scene_box);
    const auto aimed = rays_at_triangles(12, 3000, scene_box, mesh.view());
    rays.insert(rays.end(), aimed.begin(), aimed.end());
    const MeshView view = mesh.view();
    for (std::uint32_t k = 0; k < 2000; ++k) {
        const std::uint32_t tri = k % static_cast<std::uint32_t>(mesh.triangles.size());
        Ray r = aimed[k];
        const Vec3f target = k % 2 == 0 ? (view.vertex(tri, 0) + view.vertex(tri, 1)) * 0.5f
                                        : view.vertex(tri, 2);
        r.direction = target - r.origin;
        rays.push_back(r);
        if (k % 4 == 0) r.direction[static_cast<int>(k / 4 % 3)] = 0.0f;
        rays.push_back(r);
        Ray far = r;
        far.origin = target - normalize(r.direction) * 1e6f;
        far.direction = target - far.origin;
        rays.push_back(far);
    }
    return rays;
}

struct Answers {
    std::vector<Hit> closest;
    std::vector<Hit> moller;
    std::vector<std::uint8_t> any;
};

template <class Query>
Answers answers_of(const Query& query, const std::vector<Ray>& rays)
{
    Answers a;
    a.closest.resize(rays.size());
    a.moller.resize(rays.size());
    a.any.resize(rays.size());
    query(rays, a);
    return a;
}

bool bit_identical(const Hit& a, const Hit& b)
{
    return a.triangle == b.triangle && std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) &&
           std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
           std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v);
}

// Runs `query` under every supported instruction set and requires answers bit-identical to
// the scalar kernels'.
template <class Query>
void expect_same_on_every_isa(const Query& query, const std::vector<Ray>& rays)
{
    const IsaGuard guard;
    set_kernel_isa(Isa::scalar);
    const Answers reference = answers_of(query, rays);
    for (Isa isa : supported_isas()) {
        set_kernel_isa(isa);
        const Answers a = answers_of(query, rays);
        std::size_t differ = 0;
        for (std::size_t k = 0; k < rays.size(); ++k)
            differ += bit_identical(reference.closest[k], a.closest[k]) &&
                              bit_identical(reference.moller[k], a.moller[k]) &&
                              reference.any[k] == a.any[k]
                          ? 0
                          : 1;
        EXPECT_EQ(differ, 0u) << isa_name(isa);
    }
}

TEST(KernelIsa, EveryInstructionSetGivesBitIdenticalAnswers)
{
    const Mesh mesh = random_triangles(10, 3000, scene_box, 1.0f);
    const MeshView view = mesh.view();
    const std::vector<Ray> rays = mixed_rays(mesh);
    const QueryOptions moller{TriangleTest::moller_trumbore, Padding::conservative};
    const SplitGrid grid = build_checked(mesh);
    expect_same_on_every_isa(
        [&](const std::vector<Ray>& r, Answers& a) {
            intersect(grid, view, r, a.closest);
            intersect(grid, view, r, a.moller, nullptr, moller);
            occluded(grid, view, r, a.any);
        },
        rays);
    const auto check = [&](const auto& s) {
        expect_same_on_every_isa(
            [&](const std::vector<Ray>& r, Answers& a) {
                s.intersect(view, r, a.closest);
                s.intersect(view, r, a.moller, nullptr, moller);
                s.occluded(view, r, a.any);
            },
            rays);
    };
    check(Bvh::build(view));
    check(KdTree::build(view));
    check(UniformGrid::build(view));
    std::string tested;
    for (Isa isa : supported_isas()) tested += std::string(isa_name(isa)) + " ";
    RecordProperty("instruction_sets", tested);
}

bool bit_identical(const ClosestPoint& a, const ClosestPoint& b)
{
    const auto bits = [](float x) { return std::bit_cast<std::uint32_t>(x); };
    return a.triangle == b.triangle && bits(a.distance) == bits(b.distance) &&
           bits(a.u) == bits(b.u) && bits(a.v) == bits(b.v) && bits(a.point.x) == bits(b.point.x) &&
           bits(a.point.y) == bits(b.point.y) && bits(a.point.z) == bits(b.point.z);
}

// Closest points (brute force is the oracle, bit for bit: the same distance computation and
// tie rule) and hit counts (the same on every instruction set as on the scalar kernels, and
// each ray's count that of brute force's distinct hits) of every structure, on every
// instruction set: the batched point lanes and the scalar search, the batched and the
// one-at-a-time leaves.
TEST(KernelIsa, ClosestPointsAndCountsAreTheSameOnEveryInstructionSet)
{
    const Mesh mesh = random_triangles(40, 2000, scene_box, 1.0f);
    const MeshView view = mesh.view();
    std::vector<Vec3f> points;
    for (const Ray& r : random_rays(41, 1500, scene_box)) points.push_back(r.origin);
    for (const Ray& r : rays_at_triangles(42, 500, scene_box, view))
        points.push_back(r.origin + r.direction);  // on the surface
    std::vector<ClosestPoint> expected(points.size());
    for (std::size_t k = 0; k < points.size(); ++k)
        expected[k] = closest_point_brute_force(view, points[k]);
    const std::vector<Ray> rays = mixed_rays(mesh);
    const IsaGuard guard;
    std::vector<std::int32_t> reference_counts;  // the Split Grid's on the scalar kernels
    const auto check = [&](const char* name, const auto& closest, const auto& count) {
        for (Isa isa : supported_isas()) {
            set_kernel_isa(isa);
            std::vector<ClosestPoint> found(points.size());
            closest(points, found);
            std::size_t differ = 0;
            for (std::size_t k = 0; k < points.size(); ++k)
                differ += bit_identical(expected[k], found[k]) ? 0 : 1;
            EXPECT_EQ(differ, 0u) << name << " on " << isa_name(isa);
            std::vector<std::int32_t> counts(rays.size());
            count(counts);
            if (reference_counts.empty()) reference_counts = counts;
            EXPECT_EQ(counts, reference_counts) << name << " on " << isa_name(isa);
        }
    };
    const SplitGrid grid = build_checked(mesh);
    check(
        "split grid", [&](const auto& p, auto& out) { closest_points(grid, view, p, out); },
        [&](auto& counts) { count_intersections(grid, view, rays, counts); });
    const auto check_structure = [&](const char* name, const auto& s) {
        check(
            name, [&](const auto& p, auto& out) { closest_points(s, view, p, out); },
            [&](auto& counts) { s.count_intersections(view, rays, counts); });
    };
    check_structure("bvh", Bvh::build(view));
    check_structure("kd-tree", KdTree::build(view));
    check_structure("uniform grid", UniformGrid::build(view));
    // The counts are those of brute force: each triangle hit once.
    std::size_t wrong_counts = 0;
    for (std::size_t k = 0; k < rays.size(); k += 7) {
        std::int32_t n = 0;
        for (std::uint32_t tri = 0; tri < view.triangle_count(); ++tri) {
            float t, u, v;
            const Ray& r = rays[k];
            n += intersect_triangle(WatertightRay(r), view.vertex(tri, 0),
                                    view.vertex(tri, 1), view.vertex(tri, 2), r.t_min, r.t_max,
                                    t, u, v)
                     ? 1
                     : 0;
        }
        wrong_counts += n == reference_counts[k] ? 0 : 1;
    }
    EXPECT_EQ(wrong_counts, 0u);
}

// Wherever the kernels and brute force report the same triangle, t, u and v are the same
// bits: the batched test of the active instruction set computes what intersect_triangle does.
TEST(KernelIsa, BatchedTestMatchesTheScalarTestBitForBit)
{
    const Mesh mesh = random_triangles(20, 3000, scene_box, 1.0f);
    const std::vector<Ray> rays = mixed_rays(mesh);
    const SplitGrid grid = build_checked(mesh);
    const Bvh bvh = Bvh::build(mesh.view());
    std::size_t same_triangle = 0, bits_differ = 0, disagreements = 0;
    for (const Ray& r : rays) {
        const Hit expected = intersect_brute_force(mesh.view(), r);
        for (const Hit& h : {intersect(grid, mesh.view(), r), bvh.intersect(mesh.view(), r)}) {
            disagreements += same_closest_hit(expected, h) ? 0 : 1;
            if (!h.is_hit() || h.triangle != expected.triangle) continue;
            ++same_triangle;
            bits_differ += bit_identical(expected, h) ? 0 : 1;
        }
    }
    EXPECT_EQ(disagreements, 0u) << isa_name(kernel_isa());
    EXPECT_GT(same_triangle, rays.size() / 2);
    EXPECT_EQ(bits_differ, 0u) << isa_name(kernel_isa());
}

// The batched test reads each vertex as a 16-byte row, which for the mesh's last vertex would
// reach past the array. Here the vertices lie in an allocation of exactly their size and every
// triangle uses the last vertex: the hits must equal brute force's, and a read past the end
// is a heap overflow for the sanitizer builds.
TEST(KernelIsa, TheLastVertexIsReadWithinTheMeshsArray)
{
    constexpr std::uint32_t ring = 40;
    const auto vertices = std::make_unique<Vec3f[]>(ring + 1);
    for (std::uint32_t k = 0; k < ring; ++k) {
        const double a = 2.0 * std::numbers::pi * k / ring;
        vertices[k] = Vec3f{static_cast<float>(5.0 + 4.0 * std::cos(a)),
                            static_cast<float>(5.0 + 4.0 * std::sin(a)), static_cast<float>(k % 3)};
    }
    vertices[ring] = Vec3f{5.0f, 5.0f, 7.0f};  // the apex: the last vertex, in every triangle
    std::vector<Triangle> triangles;
    for (std::uint32_t k = 0; k < ring; ++k)
        triangles.push_back(Triangle{{k, (k + 1) % ring, ring}});
    const MeshView view{std::span<const Vec3f>(vertices.get(), ring + 1), triangles};
    std::vector<Ray> rays = rays_at_triangles(30, 2000, scene_box, view);
    for (std::size_t k = 0; k < 500; ++k) {  // at the apex itself (zero edge functions)
        Ray r = rays[k];
        r.direction = vertices[ring] - r.origin;
        rays.push_back(r);
    }
    const SplitGrid grid = build_split_grid(view, BuildConfig{});
    const Bvh bvh = Bvh::build(view);
    std::size_t hits = 0, disagreements = 0;
    for (const Ray& r : rays) {
        const Hit expected = intersect_brute_force(view, r);
        hits += expected.is_hit() ? 1 : 0;
        for (const Hit& h : {intersect(grid, view, r), bvh.intersect(view, r)})
            disagreements += same_closest_hit(expected, h) ? 0 : 1;
    }
    EXPECT_EQ(disagreements, 0u) << isa_name(kernel_isa());
    EXPECT_GT(hits, rays.size() / 2);
}

// SG_ISA in the environment chooses the kernels (ctest runs the traversal suites once per
// instruction set this way); unset, the most capable supported one runs.
TEST(KernelIsa, EnvironmentChoosesTheInstructionSet)
{
    const char* requested = std::getenv("SG_ISA");
    if (requested != nullptr && *requested != '\0') {
        const std::string name(requested);
        bool known = false;
        for (Isa isa : every_isa) {
            if (name != isa_name(isa)) continue;
            known = true;
            if (!isa_supported(isa)) GTEST_SKIP() << name << " is not supported by this processor";
            EXPECT_EQ(kernel_isa(), isa);
            EXPECT_TRUE(kernel_isa_note().empty());
        }
        EXPECT_TRUE(known) << name;
        return;
    }
    Isa best = Isa::scalar;
    for (Isa isa : supported_isas()) best = isa;
    EXPECT_EQ(kernel_isa(), best);
}

TEST(KernelIsa, UnsupportedInstructionSetIsRefused)
{
    for (Isa isa : every_isa) {
        if (isa_supported(isa)) continue;
        EXPECT_THROW(set_kernel_isa(isa), ConfigError) << isa_name(isa);
    }
    EXPECT_TRUE(isa_supported(Isa::scalar));
#if defined(__x86_64__)
    EXPECT_TRUE(isa_supported(Isa::sse2));
#else
    EXPECT_FALSE(isa_supported(Isa::sse2));
#endif
}

}  // namespace
}  // namespace sg::test
