#pragma once

// The brute-force oracle cases every comparison structure (uniform grid, kd-tree, BVH) must
// pass, as a typed test pattern: each <structure>_test.cpp specialises BaselineTraits and
// instantiates the pattern. The scenes are the Split Grid's failure modes (traverse_test.cpp)
// plus geometry and ray origins placed exactly on the structure's own planes.

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "splitgrid/query.hpp"
#include "splitgrid/ray_triangle.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/traverse.hpp"
#include "support/oracle.hpp"
#include "support/random_scene.hpp"

namespace sg::test {

/// Per-structure hooks, specialised by each test file:
///   static void check(const S&, const MeshView&);  // independent structural/coverage checks
///   static std::vector<std::pair<int, float>> planes(const S&);  // (axis, coordinate) of
///       the planes the traversal decides on: cell planes, split planes, box faces
///   static typename S::Config stable_planes_config();  // a config whose planes do not move
///       when triangles are added inside the scene's box (for TrianglesOnStructurePlanes)
///   static std::uint32_t depth(const S&);  static std::uint32_t depth_limit(std::size_t n);
template <class S>
struct BaselineTraits;

template <class S>
S build_checked_baseline(const Mesh& mesh, const typename S::Config& config = {})
{
    S s = S::build(mesh.view(), config);
    BaselineTraits<S>::check(s, mesh.view());
    return s;
}

template <class S>
void expect_baseline_agrees(const S& s, const Mesh& mesh, const std::vector<Ray>& rays,
                            std::size_t min_hits = 1)
{
    const OracleReport r = compare_structure_with_brute_force(s, mesh.view(), rays);
    EXPECT_EQ(r.closest_disagreements, 0u) << r.first_failure;
    EXPECT_EQ(r.any_hit_disagreements, 0u) << r.first_failure;
    EXPECT_GE(r.hits, min_hits) << "the rays should hit something, or the test proves little";
}

inline const Aabb baseline_scene_box{{0, 0, 0}, {10, 10, 10}};

/// `count` rays with origins exactly on the given planes (cycled), random directions; every
/// second one has its direction component on the plane's axis set to +0.0 or -0.0 (the ray
/// lies in the plane).
inline std::vector<Ray> rays_on_planes(const std::vector<std::pair<int, float>>& planes,
                                       std::size_t count, const Aabb& box, std::uint32_t seed)
{
    std::vector<Ray> rays = random_rays(seed, count, box);
    if (planes.empty()) return rays;
    for (std::size_t k = 0; k < rays.size(); ++k) {
        const auto& [axis, coord] = planes[k % planes.size()];
        Ray& r = rays[k];
        r.origin[axis] = coord;
        if (k % 4 == 1) r.direction[axis] = 0.0f;
        if (k % 4 == 3) r.direction[axis] = -0.0f;
        if (r.direction == Vec3f{}) r.direction[(axis + 1) % 3] = 1.0f;
    }
    return rays;
}

/// Every `stride`-th plane, so that large structures give a sample spread over the tree.
inline std::vector<std::pair<int, float>> sample_planes(std::vector<std::pair<int, float>> planes,
                                                        std::size_t most)
{
    if (planes.size() <= most) return planes;
    std::vector<std::pair<int, float>> sample;
    const std::size_t stride = planes.size() / most;
    for (std::size_t k = 0; k < planes.size() && sample.size() < most; k += stride)
        sample.push_back(planes[k]);
    return sample;
}

/// A square of two triangles in the plane axis = coord, spanning [lo, hi] on the other axes.
inline Mesh axis_square(int axis, float coord, float lo, float hi)
{
    Mesh m;
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int c = 0; c < 4; ++c) {
        Vec3f p;
        p[axis] = coord;
        p[a1] = (c & 1) ? hi : lo;
        p[a2] = (c & 2) ? hi : lo;
        m.vertices.push_back(p);
    }
    m.triangles = {Triangle{{0, 1, 3}}, Triangle{{0, 3, 2}}};
    return m;
}

/// The ConfigError message of config.validate(), or "" if it passes.
template <class Config>
std::string config_error(const Config& config)
{
    try {
        config.validate();
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

template <class S>
class BaselineOracle : public ::testing::Test {};
TYPED_TEST_SUITE_P(BaselineOracle);

TYPED_TEST_P(BaselineOracle, RandomSoupsAgreeWithBruteForce)
{
    for (std::uint32_t seed : {1u, 2u}) {
        const Mesh mesh = random_triangles(seed, 2000, baseline_scene_box, 1.0f);
        const auto s = build_checked_baseline<TypeParam>(mesh);
        auto rays = random_rays(seed + 100, 3000, baseline_scene_box);
        const auto aimed = rays_at_triangles(seed + 200, 3000, baseline_scene_box, mesh.view());
        rays.insert(rays.end(), aimed.begin(), aimed.end());
        expect_baseline_agrees(s, mesh, rays, 3000);
    }
}

TYPED_TEST_P(BaselineOracle, RayWindowsAgreeWithBruteForce)
{
    const Mesh mesh = random_triangles(7, 2000, baseline_scene_box, 1.5f);
    const auto s = build_checked_baseline<TypeParam>(mesh);
    auto rays = rays_at_triangles(8, 10000, baseline_scene_box, mesh.view());
    set_random_windows(rays, 9, -0.2f, 1.5f);
    rays[0].t_min = rays[0].t_max = 0.5f;  // an empty-width window
    expect_baseline_agrees(s, mesh, rays, 1000);
}

TYPED_TEST_P(BaselineOracle, ZeroDirectionComponentsAgreeWithBruteForce)
{
    const Mesh mesh = random_triangles(11, 2000, baseline_scene_box, 1.0f);
    const auto s = build_checked_baseline<TypeParam>(mesh);
    const std::vector<Ray> rays = zero_direction_rays(12, 10000, baseline_scene_box, mesh);
    expect_baseline_agrees(s, mesh, rays, 1000);
}

TYPED_TEST_P(BaselineOracle, RaysAtTheEdgesOfTheFloatRangeAgreeWithBruteForce)
{
    // Crossings near FLT_MAX on one axis or all (BoxRay and KernelRay::extreme), and windows
    // and origins at the ends of the range.
    const Mesh mesh = random_triangles(63, 2000, baseline_scene_box, 1.0f);
    const auto s = build_checked_baseline<TypeParam>(mesh);
    const std::vector<Ray> rays = float_range_edge_rays(64, 2000, baseline_scene_box, mesh.view());
    for (const Ray& r : rays) ASSERT_TRUE(is_valid(r));
    expect_baseline_agrees(s, mesh, rays, 2000);
}

TYPED_TEST_P(BaselineOracle, RaysOnStructurePlanesAgreeWithBruteForce)
{
    const Mesh mesh = random_triangles(21, 2000, baseline_scene_box, 1.0f);
    const auto s = build_checked_baseline<TypeParam>(mesh);
    const auto planes = sample_planes(BaselineTraits<TypeParam>::planes(s), 2000);
    ASSERT_GE(planes.size(), 10u);
    expect_baseline_agrees(s, mesh, rays_on_planes(planes, 10000, baseline_scene_box, 22), 1000);
}

TYPED_TEST_P(BaselineOracle, PlanarSceneAndRaysInItsPlane)
{
    const Aabb around{{-1, -1, -1}, {41, 41, 41}};
    for (int axis = 0; axis < 3; ++axis) {
        const Mesh mesh = axis_plane(axis, 3.0f, 30);  // 1800 triangles in one plane
        const auto s = build_checked_baseline<TypeParam>(mesh);
        auto rays = random_rays(31, 2000, around);
        const auto aimed = rays_at_triangles(32, 2000, around, mesh.view());
        rays.insert(rays.end(), aimed.begin(), aimed.end());
        append_rays_in_plane(rays, axis, 3.0f, 1500);  // rays lying in the triangles' plane
        expect_baseline_agrees(s, mesh, rays, 1500);
    }
}

// Axis-aligned squares lying exactly on planes the structure built for a first scene, then
// the structure rebuilt with them; rays start on those planes and on the new structure's.
TYPED_TEST_P(BaselineOracle, TrianglesOnStructurePlanes)
{
    using Traits = BaselineTraits<TypeParam>;
    Mesh mesh = random_triangles(41, 1500, baseline_scene_box, 1.0f);
    const auto config = Traits::stable_planes_config();
    const auto first = build_checked_baseline<TypeParam>(mesh, config);
    const auto planes = sample_planes(Traits::planes(first), 60);
    const Aabb scene = bounds(mesh.view());
    std::size_t added = 0;
    for (const auto& [axis, coord] : planes) {
        if (!(coord > scene.lower[axis] && coord < scene.upper[axis])) continue;
        const float lo = 1.0f + static_cast<float>(added % 5);
        append(mesh, axis_square(axis, coord, lo, lo + 3.0f));
        ++added;
    }
    ASSERT_GE(added, 10u);
    ASSERT_EQ(bounds(mesh.view()), scene) << "the squares must not move the planes";
    const auto s = build_checked_baseline<TypeParam>(mesh, config);
    auto all_planes = planes;
    const auto second = sample_planes(Traits::planes(s), 500);
    all_planes.insert(all_planes.end(), second.begin(), second.end());
    auto rays = rays_on_planes(all_planes, 8000, baseline_scene_box, 42);
    const auto aimed = rays_at_triangles(43, 3000, baseline_scene_box, mesh.view());
    rays.insert(rays.end(), aimed.begin(), aimed.end());
    expect_baseline_agrees(s, mesh, rays, 3000);
}

// Squares on the planes 0, 2, ..., 8 of every axis, and axis-aligned rays through the lattice
// points where their edges and corners meet.
TYPED_TEST_P(BaselineOracle, AxisPlanesAndAxisRaysThroughVertices)
{
    Mesh mesh;
    for (int axis = 0; axis < 3; ++axis)
        for (int offset = 0; offset <= 8; offset += 2)
            append(mesh, axis_plane(axis, float(offset), 8));
    const auto s = build_checked_baseline<TypeParam>(mesh);
    const Aabb box{{-0.5f, -0.5f, -0.5f}, {8.5f, 8.5f, 8.5f}};
    auto rays = random_rays(51, 4000, box);
    const auto aimed = rays_at_triangles(52, 4000, box, mesh.view());
    rays.insert(rays.end(), aimed.begin(), aimed.end());
    const auto axis_rays = axis_rays_through_lattice(53, 4000, 8, true);
    rays.insert(rays.end(), axis_rays.begin(), axis_rays.end());
    expect_baseline_agrees(s, mesh, rays, 4000);
}

// Rays from 10^6 scene sizes away, where a plane crossing is off by several cells and far
// more than the build-time pad, aimed at points where two of the structure's planes meet (cell
// edges) and at triangle centres: only the traversal's widening keeps them from slipping past
// cells they touch. Without it (Padding::None) every structure loses some of these rays.
TYPED_TEST_P(BaselineOracle, RaysFromFarAwayThroughEdges)
{
    const Mesh mesh = random_triangles(151, 2000, baseline_scene_box, 1.0f);
    const auto s = build_checked_baseline<TypeParam>(mesh);
    const auto planes = BaselineTraits<TypeParam>::planes(s);
    std::mt19937 rng(152);
    std::uniform_int_distribution<std::size_t> pick(0, planes.size() - 1);
    std::uniform_real_distribution<float> u(0.0f, 10.0f);
    std::vector<Ray> rays = random_rays(153, 8000, Aabb{{0, 0, 0}, {1, 1, 1}});
    for (std::size_t k = 0; k < rays.size(); ++k) {
        Vec3f target{u(rng), u(rng), u(rng)};
        if (k % 4 != 0) {
            const auto [a1, c1] = planes[pick(rng)];
            const auto [a2, c2] = planes[pick(rng)];
            target[a1] = c1;
            target[a2] = c2;
        } else {
            const auto t = static_cast<std::uint32_t>(pick(rng) % mesh.triangles.size());
            const MeshView view = mesh.view();
            target = (view.vertex(t, 0) + view.vertex(t, 1) + view.vertex(t, 2)) * (1.0f / 3.0f);
        }
        Ray& r = rays[k];
        r.origin = target - r.direction * 1e7f;
        r.direction = target - r.origin;
    }
    expect_baseline_agrees(s, mesh, rays, 2000);
    std::size_t unpadded_misses = 0;
    for (const Ray& r : rays)
        unpadded_misses += same_closest_hit(intersect_brute_force(mesh.view(), r),
                                            s.intersect(mesh.view(), r, nullptr, QueryOptions{TriangleTest::watertight, Padding::none}))
                               ? 0
                               : 1;
    EXPECT_GT(unpadded_misses, 0u) << "the rays should be hard enough to need the widening";
}

// A closed sphere: every ray from inside must hit it.
TYPED_TEST_P(BaselineOracle, ClosedSphereHasNoLeaks)
{
    const Mesh mesh = uv_sphere({1.0f, 2.0f, 3.0f}, 5.0f, 64, 128);
    const auto s = build_checked_baseline<TypeParam>(mesh);
    const auto rays = random_rays(61, 40000, Aabb{{-1.5f, -0.5f, 0.5f}, {3.5f, 4.5f, 5.5f}});
    std::size_t misses = 0, not_occluded = 0;
    for (const Ray& r : rays) {
        misses += s.intersect(mesh.view(), r).is_hit() ? 0 : 1;
        not_occluded += s.occluded(mesh.view(), r) ? 0 : 1;
    }
    EXPECT_EQ(misses, 0u);
    EXPECT_EQ(not_occluded, 0u);
    expect_baseline_agrees(s, mesh, std::vector<Ray>(rays.begin(), rays.begin() + 1200), 1200);
}

// The same far from the origin, where a float ulp is about 0.016 and rounding matters most.
TYPED_TEST_P(BaselineOracle, FarFromOriginSphereHasNoLeaks)
{
    const Vec3f center{148376.0f, 1234.0f, -223423.0f};
    const Mesh mesh = uv_sphere(center, 20.0f, 48, 96);
    const auto s = build_checked_baseline<TypeParam>(mesh);
    const Vec3f half{8.0f, 8.0f, 8.0f};
    auto rays = random_rays(71, 40000, Aabb{center - half, center + half});
    for (std::size_t k = 0; k < rays.size(); k += 4) {  // some along the axes, +0 and -0
        const auto axis = static_cast<int>(k / 4 % 3);
        rays[k].direction = {};
        rays[k].direction[axis] = (k & 8) ? 1.0f : -1.0f;
        rays[k].direction[(axis + 1) % 3] = (k & 16) ? 0.0f : -0.0f;
    }
    std::size_t misses = 0;
    for (const Ray& r : rays) misses += s.intersect(mesh.view(), r).is_hit() ? 0 : 1;
    EXPECT_EQ(misses, 0u);
    // Rays from outside too: aimed at triangles from a box around the sphere.
    auto oracle_rays = std::vector<Ray>(rays.begin(), rays.begin() + 1200);
    const Vec3f far{40.0f, 40.0f, 40.0f};
    const auto aimed = rays_at_triangles(72, 1500, Aabb{center - far, center + far}, mesh.view());
    oracle_rays.insert(oracle_rays.end(), aimed.begin(), aimed.end());
    expect_baseline_agrees(s, mesh, oracle_rays, 2000);
}

TYPED_TEST_P(BaselineOracle, EmptyMeshMissesEverything)
{
    const Mesh mesh;
    const auto s = build_checked_baseline<TypeParam>(mesh);
    const auto rays = random_rays(81, 100, baseline_scene_box);
    for (const Ray& r : rays) {
        const Hit h = s.intersect(mesh.view(), r);
        EXPECT_FALSE(h.is_hit());
        EXPECT_EQ(h.t, r.t_max);
        EXPECT_FALSE(s.occluded(mesh.view(), r));
    }
    EXPECT_LT(s.memory_bytes(), 256u);
}

TYPED_TEST_P(BaselineOracle, SingleTriangle)
{
    Mesh mesh;
    mesh.vertices = {{1, 1, 1}, {4, 1, 2}, {2, 5, 3}};
    mesh.triangles = {Triangle{{0, 1, 2}}};
    const auto s = build_checked_baseline<TypeParam>(mesh);
    auto rays = rays_at_triangles(91, 3000, baseline_scene_box, mesh.view());
    const auto random = random_rays(92, 3000, baseline_scene_box);
    rays.insert(rays.end(), random.begin(), random.end());
    // Through the corners exactly, along the axes.
    for (const Vec3f& v : mesh.vertices)
        for (int axis = 0; axis < 3; ++axis) {
            Ray r;
            r.origin = v;
            r.origin[axis] -= 3.0f;
            r.direction[axis] = 1.0f;
            rays.push_back(r);
        }
    expect_baseline_agrees(s, mesh, rays, 2500);
}

// Hundreds of copies of one triangle (nothing can separate them) and a fan around one vertex:
// the build must stop at a bounded depth and still find every hit.
TYPED_TEST_P(BaselineOracle, IdenticalTrianglesTerminate)
{
    Mesh mesh;
    mesh.vertices = {{1, 1, 1}, {6, 2, 1}, {3, 7, 4}};
    for (int k = 0; k < 500; ++k) mesh.triangles.push_back(Triangle{{0, 1, 2}});
    std::mt19937 rng(101);
    std::uniform_real_distribution<float> u(0.0f, 10.0f);
    const auto hub = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back({5, 5, 5});
    for (int k = 0; k < 300; ++k) {
        const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
        mesh.vertices.push_back({u(rng), u(rng), u(rng)});
        mesh.vertices.push_back({u(rng), u(rng), u(rng)});
        mesh.triangles.push_back(Triangle{{hub, base, base + 1}});
    }
    const auto s = build_checked_baseline<TypeParam>(mesh);
    EXPECT_LE(BaselineTraits<TypeParam>::depth(s),
              BaselineTraits<TypeParam>::depth_limit(mesh.triangles.size()));
    auto rays = rays_at_triangles(102, 3000, baseline_scene_box, mesh.view());
    const auto random = random_rays(103, 2000, baseline_scene_box);
    rays.insert(rays.end(), random.begin(), random.end());
    expect_baseline_agrees(s, mesh, rays, 2500);
}

TYPED_TEST_P(BaselineOracle, InvalidRaysMissWithoutTouchingTheStructure)
{
    const Mesh mesh = random_triangles(111, 200, baseline_scene_box, 1.0f);
    const auto s = build_checked_baseline<TypeParam>(mesh);
    const std::vector<Ray> bad = invalid_rays();
    for (const Ray& r : bad) {
        TraversalCounters counters;
        EXPECT_FALSE(s.intersect(mesh.view(), r, &counters).is_hit());
        EXPECT_FALSE(s.occluded(mesh.view(), r, &counters));
        EXPECT_EQ(counters.cells_visited + counters.nodes_visited + counters.triangles_tested, 0u);
    }
}

// Large enough for the parallel paths of every builder (subtrees built as separate tasks and
// concatenated), which must give the same structure, and a correct one.
TYPED_TEST_P(BaselineOracle, BuildIsIndependentOfThreadCount)
{
    const Aabb box{{0, 0, 0}, {40, 40, 40}};
    const Mesh mesh = random_triangles(121, 50000, box, 1.0f);
    typename TypeParam::Config config;
    config.threads = 1;
    const auto one = TypeParam::build(mesh.view(), config);
    for (unsigned threads : {2u, 3u}) {
        config.threads = threads;
        EXPECT_TRUE(TypeParam::build(mesh.view(), config) == one) << threads << " threads";
    }
    EXPECT_GT(one.memory_bytes(), 50000u * 4u);
    auto rays = rays_at_triangles(122, 250, box, mesh.view());
    const auto random = random_rays(123, 150, box);
    rays.insert(rays.end(), random.begin(), random.end());
    expect_baseline_agrees(one, mesh, rays, 250);
}

TYPED_TEST_P(BaselineOracle, CountersSeeTheWork)
{
    const Mesh mesh = random_triangles(131, 2000, baseline_scene_box, 1.0f);
    const auto s = build_checked_baseline<TypeParam>(mesh);
    const auto rays = rays_at_triangles(132, 1000, baseline_scene_box, mesh.view());
    std::size_t tests = 0;
    for (const Ray& r : rays) {
        TraversalCounters c;
        (void)s.intersect(mesh.view(), r, &c);
        EXPECT_GE(c.cells_visited + c.nodes_visited, 1u);
        tests += c.triangles_tested;
    }
    // The structure must test far fewer triangles than brute force would.
    EXPECT_LT(tests, rays.size() * mesh.triangles.size() / 20);
}

// The closest hit of the Moeller-Trumbore test over all triangles in id order (the first of
// equal t): the oracle of a query run with TriangleTest::moller_trumbore.
inline Hit moller_trumbore_brute_force(const MeshView& mesh, const Ray& ray)
{
    Hit best;
    best.t = ray.t_max;
    for (std::uint32_t tri = 0; tri < mesh.triangle_count(); ++tri) {
        float t, u, v;
        if (intersect_triangle_moller_trumbore(ray.origin, ray.direction, mesh.vertex(tri, 0),
                                               mesh.vertex(tri, 1), mesh.vertex(tri, 2),
                                               ray.t_min, best.t, t, u, v) &&
            !(best.is_hit() && !(t < best.t)))
            best = Hit{t, tri, u, v};
    }
    return best;
}

// The query options reach the kernels: with the Moeller-Trumbore test the structure finds
// what that test finds over all triangles (rays aimed at edges, where it differs from the
// watertight test), and without the widening it is still a working traversal.
TYPED_TEST_P(BaselineOracle, QueryOptionsChooseTheTestAndPadding)
{
    const Mesh mesh = random_triangles(141, 2000, baseline_scene_box, 1.0f);
    const auto s = build_checked_baseline<TypeParam>(mesh);
    std::vector<Ray> rays = rays_at_triangles(142, 2000, baseline_scene_box, mesh.view());
    // Half of them aimed exactly at edge midpoints, where the two tests part ways.
    for (std::size_t k = 0; k < rays.size(); k += 2) {
        const auto tri = static_cast<std::uint32_t>(k % mesh.triangles.size());
        const Vec3f mid = (mesh.view().vertex(tri, 0) + mesh.view().vertex(tri, 1)) * 0.5f;
        rays[k].direction = mid - rays[k].origin;
    }
    const QueryOptions moller{TriangleTest::moller_trumbore, Padding::conservative};
    std::size_t moller_disagreements = 0, tests_differ = 0, unpadded_agreements = 0;
    for (const Ray& r : rays) {
        const Hit expected = moller_trumbore_brute_force(mesh.view(), r);
        const Hit h = s.intersect(mesh.view(), r, nullptr, moller);
        moller_disagreements += same_closest_hit(expected, h) ? 0 : 1;
        const Hit watertight = intersect_brute_force(mesh.view(), r);
        tests_differ += same_closest_hit(watertight, expected) ? 0 : 1;
        const Hit unpadded =
            s.intersect(mesh.view(), r, nullptr, QueryOptions{TriangleTest::watertight, Padding::none});
        unpadded_agreements += same_closest_hit(watertight, unpadded) ? 1 : 0;
    }
    EXPECT_EQ(moller_disagreements, 0u);
    EXPECT_GT(tests_differ, 0u) << "the rays should tell the two triangle tests apart";
    // Without the widening the traversal may lose a rare ray near an edge, but it must still
    // be a working traversal.
    EXPECT_GE(unpadded_agreements, rays.size() * 99 / 100);
}

REGISTER_TYPED_TEST_SUITE_P(BaselineOracle, RandomSoupsAgreeWithBruteForce,
                            RayWindowsAgreeWithBruteForce, ZeroDirectionComponentsAgreeWithBruteForce,
                            RaysAtTheEdgesOfTheFloatRangeAgreeWithBruteForce,
                            RaysOnStructurePlanesAgreeWithBruteForce, PlanarSceneAndRaysInItsPlane,
                            TrianglesOnStructurePlanes, AxisPlanesAndAxisRaysThroughVertices,
                            RaysFromFarAwayThroughEdges,
                            ClosedSphereHasNoLeaks, FarFromOriginSphereHasNoLeaks,
                            EmptyMeshMissesEverything, SingleTriangle, IdenticalTrianglesTerminate,
                            InvalidRaysMissWithoutTouchingTheStructure,
                            BuildIsIndependentOfThreadCount, CountersSeeTheWork,
                            QueryOptionsChooseTheTestAndPadding);

}  // namespace sg::test
