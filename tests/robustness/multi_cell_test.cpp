// Row 5 of docs/ROBUSTNESS.md: triangles referenced by several cells. A hit found while
// testing a leaf may lie in a later cell, behind a closer triangle the walk has not reached
// yet; the traversal must not stop at it.
// - Constructed: a long triangle L referenced by the cell the ray starts in, whose hit is
//   several cells further on, and a small triangle S in a cell in between. The test proves
//   that layout on the built grid (which leaves hold L and S, where the hit points are), then
//   requires S, as brute force does; along +-x, +-y, +-z, with and without a small tilt.
// - Random: long thin triangles mixed with small ones, closest and any hit against brute
//   force (culled_oracle.hpp, exactly brute force's answers) on every ray.

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "culled_oracle.hpp"
#include "robustness_support.hpp"
#include "support/random_scene.hpp"

namespace sg::test {
namespace {

// The leaf cell whose box holds `p` (the lowest cell where p lies on a boundary), or an
// empty cell when p lies outside the root box or in space cut away by bounding planes.
CellRef leaf_at(const SplitGrid& grid, Vec3f p)
{
    for (int k = 0; k < 3; ++k)
        if (p[k] < grid.root_box.lower[k] || p[k] > grid.root_box.upper[k]) return {};
    CellRef cell = grid.root;
    while (cell.is_inner()) {
        const GridNode& node = grid.nodes[cell.child()];
        const float x = p[node.axis()];
        if (x < node.lo || x > node.hi) return {};
        const CellMath cm(node.lo, node.hi, node.resolution());
        cell = node_cell(grid, node, cm.locate_lowest(x));
    }
    return cell;
}

bool references(const SplitGrid& grid, CellRef leaf, std::uint32_t triangle)
{
    for (const std::uint32_t t : leaf_triangles(grid, leaf))
        if (t == triangle) return true;
    return false;
}

// A scene in canonical coordinates (the ray runs along +x), mapped onto `axis` and `sign`.
struct Mapping {
    int axis;
    float sign;
    [[nodiscard]] Vec3f operator()(Vec3f c) const
    {
        Vec3f w;
        w[axis] = sign * c.x;
        w[(axis + 1) % 3] = c.y;
        w[(axis + 2) % 3] = c.z;
        return w;
    }
};

struct Layout {
    Mesh mesh;
    std::uint32_t long_tri = 0;
    std::uint32_t small_tri = 0;
};

// Filler triangles away from the ray's tube make the builder cut the long axis into many
// cells; L descends slowly towards the ray line and meets it at x = hit_x; S stands across
// the ray at x = small_x.
Layout make_layout(const Mapping& map, float small_x, float hit_x, std::uint32_t seed)
{
    Layout layout;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> ux(0.0f, 16.0f), uyz(-4.0f, 4.0f), e(-0.15f, 0.15f);
    while (layout.mesh.triangles.size() < 1000) {
        const Vec3f a{ux(rng), uyz(rng), uyz(rng)};
        if (std::fabs(a.y) < 1.5f && std::fabs(a.z) < 1.5f) continue;  // keep the tube clear
        const auto base = static_cast<std::uint32_t>(layout.mesh.vertices.size());
        const Vec3f b = a + Vec3f{e(rng), e(rng), e(rng)};
        const Vec3f c = a + Vec3f{e(rng), e(rng), e(rng)};
        for (const Vec3f v : {a, b, c}) layout.mesh.vertices.push_back(map(v));
        layout.mesh.triangles.push_back(Triangle{{base, base + 1, base + 2}});
    }
    auto add = [&](Vec3f a, Vec3f b, Vec3f c) {
        const auto base = static_cast<std::uint32_t>(layout.mesh.vertices.size());
        for (const Vec3f v : {a, b, c}) layout.mesh.vertices.push_back(map(v));
        layout.mesh.triangles.push_back(Triangle{{base, base + 1, base + 2}});
        return static_cast<std::uint32_t>(layout.mesh.triangles.size() - 1);
    };
    // y = 0.02 (1 - x / hit_x): 0.02 above the ray at x = 0, on it at x = hit_x.
    const float end_y = 0.02f * (1.0f - 16.0f / hit_x);
    layout.long_tri = add({0.0f, 0.02f, -1.0f}, {0.0f, 0.02f, 1.0f}, {16.0f, end_y, 0.0f});
    layout.small_tri = add({small_x, -0.05f, -0.05f}, {small_x, 0.05f, -0.05f},
                           {small_x, 0.0f, 0.05f});
    return layout;
}

TEST(MultiCell, HitInALaterCellDoesNotHideACloserTriangleInAnEarlierOne)
{
    std::mt19937 rng(51);
    std::uniform_real_distribution<float> small_at(3.0f, 7.0f), gap(2.0f, 4.0f);
    std::size_t cases = 0;
    for (int axis = 0; axis < 3; ++axis)
        for (const float sign : {1.0f, -1.0f})
            for (int config = 0; config < 4; ++config) {
                const Mapping map{axis, sign};
                const float small_x = small_at(rng);
                const float hit_x = small_x + gap(rng);
                const Layout layout =
                    make_layout(map, small_x, hit_x, static_cast<std::uint32_t>(rng()));
                // A root of 64 cells along the long axis, so that the ray's start, S and L's
                // hit fall into three different leaves (the premise checked below).
                BuildConfig build;
                build.resolution_max = 64;
                // The premise is about the cells of one node; one-cell nodes around the
                // leaves would move the ray's start outside every leaf.
                build.bounding_nodes = false;
                const SplitGrid grid = build_checked(layout.mesh, build);
                // Tilted away from L, which then meets the ray a little later.
                for (const Vec3f tilt : {Vec3f{1, 0, 0}, Vec3f{1, -0.0002f, 0},
                                         Vec3f{1, -0.0001f, 0.0003f}}) {
                    SCOPED_TRACE("axis " + std::to_string(axis) + " sign " +
                                 std::to_string(sign) + " config " + std::to_string(config));
                    Ray ray;
                    ray.origin = map({0.5f, 0.0f, 0.0f});
                    ray.direction = map(tilt);
                    // The premise, on the built grid: L is in the leaf the ray starts in, S
                    // is not, and L's hit lies in a later leaf than S's.
                    const Hit on_long = intersect_brute_force(
                        MeshView{layout.mesh.vertices,
                                 std::span(layout.mesh.triangles).subspan(layout.long_tri, 1)},
                        ray);
                    ASSERT_TRUE(on_long.is_hit());
                    const CellRef start = leaf_at(grid, ray.origin);
                    const CellRef at_small = leaf_at(grid, map({small_x, 0.0f, 0.0f}));
                    const CellRef at_long = leaf_at(grid, ray.origin + ray.direction * on_long.t);
                    ASSERT_TRUE(start.is_leaf());
                    ASSERT_TRUE(references(grid, start, layout.long_tri));
                    ASSERT_FALSE(references(grid, start, layout.small_tri));
                    ASSERT_TRUE(references(grid, at_small, layout.small_tri));
                    ASSERT_FALSE(at_long == start);
                    ASSERT_FALSE(at_long == at_small);

                    const Hit truth = intersect_brute_force(layout.mesh.view(), ray);
                    ASSERT_EQ(truth.triangle, layout.small_tri);
                    const Hit hit = intersect(grid, layout.mesh.view(), ray);
                    EXPECT_EQ(hit.triangle, layout.small_tri);
                    EXPECT_EQ(hit.t, truth.t);
                    EXPECT_TRUE(occluded(grid, layout.mesh.view(), ray));
                    ++cases;
                }
            }
    EXPECT_EQ(cases, 72u);
}

// Needles and slivers: two long edges of length 3 to 10 in a box of 10 and a width of 0.001
// to 0.02, in random directions.
Mesh long_thin_triangles(std::uint32_t seed, std::size_t count, const Aabb& box)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f);
    Mesh mesh;
    auto unit = [&] {
        for (;;) {
            const Vec3f v{s(rng), s(rng), s(rng)};
            if (const float l = length(v); l > 0.1f && l <= 1.0f) return v * (1.0f / l);
        }
    };
    for (std::size_t t = 0; t < count; ++t) {
        Vec3f a;
        for (int k = 0; k < 3; ++k) a[k] = box.lower[k] + u(rng) * box.extent(k);
        const Vec3f along = unit();
        const Vec3f b = a + along * (3.0f + 7.0f * u(rng));
        const Vec3f side = normalize(cross(along, unit()));
        const Vec3f c = a + (b - a) * u(rng) + side * (0.001f + 0.019f * u(rng));
        const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
        mesh.vertices.insert(mesh.vertices.end(), {a, b, c});
        mesh.triangles.push_back(Triangle{{base, base + 1, base + 2}});
    }
    return mesh;
}

TEST(MultiCell, LongThinTrianglesAmongSmallOnesAgreeWithBruteForce)
{
    const Aabb box{{0, 0, 0}, {10, 10, 10}};
    const std::size_t each = pick_size(10000, 100000);
    Mesh mesh = long_thin_triangles(52, each, box);
    append(mesh, random_triangles(53, each, box, 0.1f));
    const SplitGrid grid = build_checked(mesh);
    const std::size_t n = pick_size(20000, 1000000);
    std::vector<Ray> rays = rays_at_triangles(54, n / 2, box, mesh.view());
    const auto random = random_rays(55, n - rays.size(), box);
    rays.insert(rays.end(), random.begin(), random.end());

    const CulledOracle oracle(mesh.view());
    const std::vector<Ray> sample(rays.begin(), rays.begin() + 300);
    ASSERT_EQ(oracle.self_check(sample), 0u) << "the culled oracle differs from brute force";
    const OracleReport r = oracle.compare(grid, rays);
    std::size_t referenced_long = 0, references = 0;
    for (const auto& leaf : all_leaves(grid))
        for (std::uint32_t t : leaf) {
            referenced_long += t < each ? 1 : 0;
            ++references;
        }
    std::printf("[ multi    ] %zu long thin + %zu small triangles, %zu references (%.1f per long "
                "triangle): %zu rays, %zu disagreements, %zu hits\n",
                each, each, references,
                static_cast<double>(referenced_long) / static_cast<double>(each), r.rays,
                r.closest_disagreements + r.any_hit_disagreements, r.hits);
    EXPECT_EQ(r.closest_disagreements, 0u) << r.first_failure;
    EXPECT_EQ(r.any_hit_disagreements, 0u) << r.first_failure;
    EXPECT_GT(r.hits, n / 2);
}

}  // namespace
}  // namespace sg::test
