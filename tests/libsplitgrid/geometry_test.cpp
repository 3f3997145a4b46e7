// Small pieces checked against independent arithmetic: the resolution formula, the cell
// mapping, the float steps, clipping against the separating-axis test, the watertight triangle test.

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "splitgrid/aabb.hpp"
#include "splitgrid/cell_math.hpp"
#include "splitgrid/clip.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/float_step.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/ray_triangle.hpp"
#include "splitgrid/resolution.hpp"

namespace sg {
namespace {

TEST(Resolution, FollowsTheGaussianFormula)
{
    BuildConfig c;
    c.resolution_min = 2;
    c.resolution_max = 66;
    c.resolution_sigma = 100.0;
    EXPECT_EQ(node_resolution(c, 0), 2u);
    // 2 + 64 * (1 - e^-0.5) = 27.18...
    EXPECT_EQ(node_resolution(c, 100), 27u);
    // 2 + 64 * (1 - e^-2) = 57.33...
    EXPECT_EQ(node_resolution(c, 200), 57u);
    EXPECT_EQ(node_resolution(c, 100000), 66u);
    for (std::size_t n = 0; n < 2000; n += 7)
        EXPECT_LE(node_resolution(c, n), node_resolution(c, n + 7)) << "not monotone at " << n;
}

// A box grows by another side by side, so an empty box (the default, +inf / -inf corners)
// adds nothing; growing by its corners as points made the result infinite.
TEST(Aabb, ExtendByAnEmptyBoxKeepsTheBox)
{
    Aabb box{{-1.0f, 2.0f, 0.5f}, {3.0f, 4.0f, 0.5f}};
    box.extend(Aabb{});
    EXPECT_EQ(box.lower, (Vec3f{-1.0f, 2.0f, 0.5f}));
    EXPECT_EQ(box.upper, (Vec3f{3.0f, 4.0f, 0.5f}));

    Aabb empty;
    empty.extend(Aabb{});
    EXPECT_TRUE(empty.is_empty());
    empty.extend(box);
    EXPECT_EQ(empty.lower, (Vec3f{-1.0f, 2.0f, 0.5f}));
    EXPECT_EQ(empty.upper, (Vec3f{3.0f, 4.0f, 0.5f}));

    box.extend(Aabb{{-2.0f, 3.0f, 0.0f}, {0.0f, 5.0f, 0.25f}});
    EXPECT_EQ(box.lower, (Vec3f{-2.0f, 2.0f, 0.0f}));
    EXPECT_EQ(box.upper, (Vec3f{3.0f, 5.0f, 0.5f}));
}

TEST(CellMath, BoundariesAreMonotoneAndLocateAgreesWithLinearSearch)
{
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-1000.0f, 1000.0f);
    for (int trial = 0; trial < 200; ++trial) {
        float lo = u(rng), hi = u(rng);
        if (lo > hi) std::swap(lo, hi);
        const std::uint32_t n = 1 + static_cast<std::uint32_t>(trial % 70);
        const CellMath cm(lo, hi, n);
        EXPECT_EQ(cm.boundary(0), lo);
        EXPECT_EQ(cm.boundary(n), hi);
        for (std::uint32_t i = 0; i < n; ++i) EXPECT_LE(cm.boundary(i), cm.boundary(i + 1));
        for (int q = 0; q < 50; ++q) {
            const float x =
                q % 5 == 0 ? cm.boundary(static_cast<std::uint32_t>(q) % (n + 1))
                           : std::min(hi, lo + (hi - lo) * (static_cast<float>(q) / 49.0f));
            std::uint32_t lowest = n, highest = 0;
            for (std::uint32_t i = 0; i < n; ++i)
                if (cm.boundary(i) <= x && x <= cm.boundary(i + 1)) {
                    lowest = std::min(lowest, i);
                    highest = std::max(highest, i);
                }
            ASSERT_LT(lowest, n) << "no cell contains " << x;
            EXPECT_EQ(cm.locate_lowest(x), lowest);
            EXPECT_EQ(cm.locate_highest(x), highest);
        }
    }
}

// locate_cells, which finds four coordinates' cells at once, against a linear search over the
// boundaries: coordinates on boundaries, between them, one float step off them and outside
// [lo, hi], flat nodes (width 0) and counts that are not a multiple of four.
TEST(CellMath, LocateCellsAgreesWithLinearSearch)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1000.0f, 1000.0f);
    for (int trial = 0; trial < 300; ++trial) {
        float lo = u(rng), hi = u(rng);
        if (lo > hi) std::swap(lo, hi);
        if (trial % 25 == 0) hi = lo;  // flat
        const std::uint32_t n = 1 + static_cast<std::uint32_t>(trial % 70);
        const CellMath cm(lo, hi, n);
        std::vector<float> xs;
        for (std::uint32_t i = 0; i <= n; ++i) {
            const float b = cm.boundary(i);
            xs.insert(xs.end(), {b, std::nextafter(b, -INFINITY), std::nextafter(b, INFINITY)});
        }
        for (int q = 0; q < 40; ++q) xs.push_back(lo + (hi - lo) * (static_cast<float>(q) / 39.0f));
        xs.insert(xs.end(), {lo - 1.0f, hi + 1.0f, -1e30f, 1e30f});
        std::shuffle(xs.begin(), xs.end(), rng);
        xs.resize(xs.size() - static_cast<std::size_t>(trial % 4));
        std::vector<float> ys(xs.rbegin(), xs.rend());
        std::vector<std::uint32_t> first(xs.size()), last(xs.size());
        locate_cells(cm, xs.data(), ys.data(), xs.size(), first.data(), last.data());
        // The cells locate_lowest and locate_highest are defined to give, by linear search:
        // the first cell whose upper boundary is not below x (the last cell if none is), and
        // the last cell whose lower boundary is not above x (the first if none is). Inside
        // [lo, hi] these are the lowest and highest cells whose closed interval holds x.
        auto search = [&](float x, bool lowest) {
            if (lowest) {
                for (std::uint32_t i = 0; i + 1 < n; ++i)
                    if (x <= cm.boundary(i + 1)) return i;
                return n - 1;
            }
            for (std::uint32_t i = n - 1; i > 0; --i)
                if (x >= cm.boundary(i)) return i;
            return 0u;
        };
        for (std::size_t k = 0; k < xs.size(); ++k) {
            ASSERT_EQ(first[k], search(xs[k], true)) << "x " << xs[k] << ", n " << n;
            ASSERT_EQ(last[k], search(ys[k], false)) << "x " << ys[k] << ", n " << n;
        }
    }
}

// The float steps the builders round with, against libm's nextafter on a spread of bit
// patterns of every kind (zeros, denormals, normals, infinities, NaN) and the bound that
// rounding to the nearest float not above (below) a double must meet.
TEST(FloatStep, StepsAsNextafterAndRoundsOutward)
{
    constexpr float inf = std::numeric_limits<float>::infinity();
    auto same = [](float a, float b) {
        return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b) ||
               (std::isnan(a) && std::isnan(b));
    };
    std::vector<std::uint32_t> patterns{0x00000000u, 0x80000000u, 0x00000001u, 0x80000001u,
                                        0x007FFFFFu, 0x807FFFFFu, 0x00800000u, 0x80800000u,
                                        0x7F7FFFFFu, 0xFF7FFFFFu, 0x7F800000u, 0xFF800000u,
                                        0x7FC00000u, 0xFFC00000u, 0x7F800001u, 0xFF800001u,
                                        0x7FFFFFFFu, 0xFFFFFFFFu, 0x3F800000u, 0xBF800000u};
    for (std::uint64_t bits = 0; bits <= 0xFFFFFFFFu; bits += 65521)
        patterns.push_back(static_cast<std::uint32_t>(bits));
    for (const std::uint32_t bits : patterns) {
        const float f = std::bit_cast<float>(bits);
        EXPECT_TRUE(same(next_float_down(f), std::nextafter(f, -inf))) << std::hex << bits;
        EXPECT_TRUE(same(next_float_up(f), std::nextafter(f, inf))) << std::hex << bits;
    }

    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
    std::uniform_int_distribution<int> exponent(-160, 140);
    for (int trial = 0; trial < 200000; ++trial) {
        const double x = std::ldexp(mantissa(rng), exponent(rng));
        const float below = float_not_above(x);
        const float above = float_not_below(x);
        // Not beyond x, and the next float is: the nearest float on each side.
        ASSERT_LE(static_cast<double>(below), x) << x;
        ASSERT_GT(static_cast<double>(std::nextafter(below, inf)), x) << x;
        ASSERT_GE(static_cast<double>(above), x) << x;
        ASSERT_LT(static_cast<double>(std::nextafter(above, -inf)), x) << x;
    }
    // A double that is a float is its own rounding, on both sides.
    for (const float f : {0.0f, -0.0f, 1.0f, -1.0f, std::numeric_limits<float>::denorm_min(),
                          -std::numeric_limits<float>::denorm_min(),
                          std::numeric_limits<float>::max(), -std::numeric_limits<float>::max()}) {
        EXPECT_TRUE(same(float_not_above(static_cast<double>(f)), f)) << f;
        EXPECT_TRUE(same(float_not_below(static_cast<double>(f)), f)) << f;
    }
    // Beyond the float range: the largest float on the near side, an infinity on the far one.
    EXPECT_EQ(float_not_above(1e39), std::numeric_limits<float>::max());
    EXPECT_EQ(float_not_below(1e39), inf);
    EXPECT_EQ(float_not_below(-1e39), -std::numeric_limits<float>::max());
    EXPECT_EQ(float_not_above(-1e39), -inf);
}

TEST(Clip, AgreesWithTheSeparatingAxisTest)
{
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    const Aabbd box{{-1, -1, -1}, {1, 1, 1}};
    int overlaps = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const Vec3d a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
        Aabbd out;
        const bool clipped = clip_triangle_bounds(a, b, c, box, out);
        const bool sat = triangle_overlaps_box(a, b, c, box);
        ASSERT_EQ(clipped, sat) << "trial " << trial;
        if (!clipped) continue;
        ++overlaps;
        for (int k = 0; k < 3; ++k) {
            EXPECT_GE(out.lower[k], box.lower[k]);
            EXPECT_LE(out.upper[k], box.upper[k]);
            // The clipped extent lies inside the triangle's own extent.
            EXPECT_GE(out.lower[k], std::min({a[k], b[k], c[k]}));
            EXPECT_LE(out.upper[k], std::max({a[k], b[k], c[k]}));
        }
    }
    EXPECT_GT(overlaps, 1000);
}

TEST(Clip, PiecesInSlabsAgreeWithClippingToTheSlabsBox)
{
    // The builder clips a straddling triangle once to its node's box and reads each cell's
    // piece from the polygon; clipping the triangle to the cell's box directly is the oracle.
    // Two kinds of input: random coordinates, and coordinates and planes on a lattice of
    // quarter units, where vertices lie on planes, slabs have zero width and triangles
    // degenerate into segments and points.
    const Aabbd box{{-1, -1, -1}, {1, 1, 1}};
    int pieces = 0, empty = 0, touching = 0;
    // One object for every triangle, as the builder uses it: nothing of a clip may leak into
    // the next one.
    ClippedTriangle polygon;
    auto check = [&](const Vec3d& a, const Vec3d& b, const Vec3d& c, int axis, double lo,
                     double hi, int trial) {
        Aabbd whole;
        ASSERT_EQ(polygon.clip(a, b, c, box), clip_triangle_bounds(a, b, c, box, whole))
            << "trial " << trial;
        if (!clip_triangle_bounds(a, b, c, box, whole)) return;
        Aabbd slab_box = box;
        slab_box.lower[axis] = lo;
        slab_box.upper[axis] = hi;
        Aabbd expected, piece;
        const bool direct = clip_triangle_bounds(a, b, c, slab_box, expected);
        const bool from_polygon = polygon.slab_bounds(axis, slab_box, piece);
        if (from_polygon != direct) {
            // Allowed only where the piece one of them finds merely touches the box: flat on
            // an axis, at one of the box's faces (a point or an edge on a plane, found or
            // lost by rounding; the builder's pad is far wider).
            const Aabbd& found = direct ? expected : piece;
            bool touches = false;
            for (int k = 0; k < 3; ++k)
                touches = touches || (found.upper[k] - found.lower[k] <= 1e-12 &&
                                      (std::abs(found.lower[k] - slab_box.lower[k]) <= 1e-12 ||
                                       std::abs(found.upper[k] - slab_box.upper[k]) <= 1e-12));
            EXPECT_TRUE(touches) << "trial " << trial << ": the direct clip is "
                                 << (direct ? "not " : "") << "empty, the piece from the polygon "
                                 << (from_polygon ? "not " : "") << "empty";
            ++touching;
            return;
        }
        if (!direct) {
            ++empty;
            return;
        }
        ++pieces;
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(piece.lower[k], expected.lower[k], 1e-12) << "trial " << trial;
            EXPECT_NEAR(piece.upper[k], expected.upper[k], 1e-12) << "trial " << trial;
        }
    };
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    std::uniform_int_distribution<int> axis_of(0, 2);
    std::uniform_int_distribution<int> quarter(-8, 8);
    for (int trial = 0; trial < 20000; ++trial) {
        const Vec3d a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
        double lo = u(rng) * 0.5, hi = u(rng) * 0.5;
        if (lo > hi) std::swap(lo, hi);
        check(a, b, c, axis_of(rng), lo, hi, trial);
    }
    EXPECT_EQ(touching, 0) << "random coordinates do not graze a plane";
    const int random_pieces = pieces, random_empty = empty;
    EXPECT_GT(random_pieces, 1000);
    EXPECT_GT(random_empty, 1000);
    auto q = [&] { return 0.25 * quarter(rng); };
    for (int trial = 0; trial < 20000; ++trial) {
        const Vec3d a{q(), q(), q()};
        const Vec3d b = trial % 7 == 0 ? a : Vec3d{q(), q(), q()};
        const Vec3d c = trial % 11 == 0 ? b : Vec3d{q(), q(), q()};
        double lo = std::clamp(q(), -1.0, 1.0), hi = trial % 5 == 0 ? lo : std::clamp(q(), -1.0, 1.0);
        if (lo > hi) std::swap(lo, hi);
        check(a, b, c, axis_of(rng), lo, hi, 20000 + trial);
    }
    EXPECT_GT(pieces - random_pieces, 1000);
    EXPECT_GT(empty - random_empty, 1000);
    // Disagreements are grazing contacts only, and rare even where every vertex lies on a
    // lattice of planes.
    EXPECT_LT(touching, 40);
}

TEST(Clip, ClippedBoundsAreTightForAKnownCase)
{
    // The triangle (0,0,0) (4,0,0) (0,4,0) inside the box [1,2]^2 x [-1,1]: the clipped
    // polygon is the whole square [1,2]^2 (the hypotenuse x + y = 4 is beyond it).
    Aabbd out;
    ASSERT_TRUE(clip_triangle_bounds({0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {{1, 1, -1}, {2, 2, 1}}, out));
    EXPECT_DOUBLE_EQ(out.lower.x, 1.0);
    EXPECT_DOUBLE_EQ(out.upper.x, 2.0);
    EXPECT_DOUBLE_EQ(out.upper.y, 2.0);
    EXPECT_DOUBLE_EQ(out.lower.z, 0.0);
    EXPECT_DOUBLE_EQ(out.upper.z, 0.0);
    // Box [2.5,3]^2: only the corner region below x + y = 4 is inside, so y <= 1.5.
    ASSERT_TRUE(clip_triangle_bounds({0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {{2.5, 0, -1}, {3, 3, 1}}, out));
    EXPECT_DOUBLE_EQ(out.upper.y, 1.5);
    // Touching at one corner counts.
    EXPECT_TRUE(clip_triangle_bounds({0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {{4, 0, 0}, {5, 1, 1}}, out));
    EXPECT_FALSE(clip_triangle_bounds({0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {{2.1, 2.1, -1}, {3, 3, 1}}, out));
}

TEST(MollerTrumbore, HitsLieOnTheTriangleAndAgreeWithTheWatertightTestAwayFromEdges)
{
    // Rays from random points towards random interior points of random triangles: both tests
    // must hit, at the same t to a few ulps; and rays aimed clearly outside must miss in both.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> coord(-10.0f, 10.0f);
    std::uniform_real_distribution<float> bary(0.05f, 0.9f);
    int compared = 0;
    for (int k = 0; k < 20000; ++k) {
        const Vec3f a{coord(rng), coord(rng), coord(rng)};
        const Vec3f b{coord(rng), coord(rng), coord(rng)};
        const Vec3f c{coord(rng), coord(rng), coord(rng)};
        float wu = bary(rng), wv = bary(rng);
        if (wu + wv > 0.95f) continue;
        const Vec3f target = a * (1.0f - wu - wv) + b * wu + c * wv;
        const Vec3f origin{coord(rng) * 3.0f, coord(rng) * 3.0f, coord(rng) * 3.0f};
        const Ray ray{origin, target - origin, 0.0f, 10.0f};
        // Skip rays nearly in the triangle's plane, where no float test is exact.
        const Vec3f n = normalize(cross(b - a, c - a));
        if (std::abs(dot(n, normalize(ray.direction))) < 0.05f) continue;
        float t1, u1, v1, t2, u2, v2;
        ASSERT_TRUE(intersect_triangle(WatertightRay(ray), a, b, c, 0.0f, 10.0f, t1, u1, v1)) << k;
        ASSERT_TRUE(intersect_triangle_moller_trumbore(ray.origin, ray.direction, a, b, c, 0.0f, 10.0f, t2, u2, v2)) << k;
        EXPECT_NEAR(t2, 1.0f, 1e-3f) << k;
        EXPECT_NEAR(t1, t2, 1e-3f) << k;
        EXPECT_NEAR(u2, wu, 1e-3f) << k;
        EXPECT_NEAR(v2, wv, 1e-3f) << k;
        // Beyond a corner, outside the triangle: both miss.
        const Vec3f outside = a + (a - (b + c) * 0.5f) * 0.5f;
        const Ray away{origin, outside - origin, 0.0f, 10.0f};
        EXPECT_FALSE(intersect_triangle(WatertightRay(away), a, b, c, 0.0f, 10.0f, t1, u1, v1)) << k;
        EXPECT_FALSE(intersect_triangle_moller_trumbore(away.origin, away.direction, a, b, c, 0.0f, 10.0f, t2, u2, v2)) << k;
        ++compared;
    }
    EXPECT_GT(compared, 8000);
}

TEST(Mesh, CleanDropsExactlyTheBadTriangles)
{
    Mesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {std::nanf(""), 0, 0}};
    mesh.triangles = {Triangle{{0, 1, 2}},  // good
                      Triangle{{0, 1, 3}},  // collinear: zero area
                      Triangle{{0, 1, 4}},  // NaN corner
                      Triangle{{0, 1, 9}},  // index out of range
                      Triangle{{2, 2, 1}},  // repeated corner: zero area
                      Triangle{{2, 1, 0}}}; // good
    const CleanReport r = clean_mesh(mesh);
    EXPECT_EQ(r.degenerate_triangles, 2u);
    EXPECT_EQ(r.nonfinite_triangles, 1u);
    EXPECT_EQ(r.bad_index_triangles, 1u);
    ASSERT_EQ(mesh.triangles.size(), 2u);
    EXPECT_EQ(mesh.triangles[1], (Triangle{{2, 1, 0}}));
}

// The message check_mesh throws for `mesh`, or "" if it passes.
std::string check_mesh_error(const MeshView& mesh)
{
    try {
        check_mesh(mesh);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// checked_bounds's message for `mesh` on `threads` threads, or "" if it passes; `box` is set
// to its result when it passes.
std::string checked_bounds_error(const MeshView& mesh, int threads, Aabb& box)
{
    std::string error;
    tbb::task_arena(threads).execute([&] {
        try {
            box = checked_bounds(mesh);
        } catch (const InputError& e) {
            error = e.what();
        }
    });
    return error;
}

TEST(Mesh, CheckedBoundsIsBoundsBitForBitAndFailsAsCheckMesh)
{
    // Triangles and no vertices: refused, without reading a vertex.
    Mesh empty;
    empty.triangles = {Triangle{{0, 0, 0}}};
    Aabb unused;
    EXPECT_NE(checked_bounds_error(empty.view(), 1, unused), "");

    std::mt19937 rng(91);
    std::uniform_real_distribution<float> u(-5.0f, 5.0f);
    for (const std::size_t n : {std::size_t{1000}, std::size_t{300000}}) {  // serial, parallel
        Mesh mesh;
        std::uniform_real_distribution<float> above(1.0f, 5.0f);
        for (std::size_t k = 0; k < 3 * n / 2; ++k)
            mesh.vertices.push_back({u(rng), u(rng), above(rng)});
        // The lowest z is a zero of either sign; -0 is met first (triangle 0), +0 in a later
        // block, and the box keeps the first.
        mesh.vertices[n / 3] = {1.0f, -7.0f, -0.0f};
        mesh.vertices[n / 2] = {2.0f, 7.0f, 0.0f};
        std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(n - 1));
        for (std::size_t t = 0; t < n; ++t) {
            Triangle tri{{pick(rng), pick(rng), pick(rng)}};
            for (std::uint32_t& i : tri.v)
                if (i == n / 3 || i == n / 2) i = 0;
            mesh.triangles.push_back(tri);
        }
        mesh.triangles[0].v[1] = static_cast<std::uint32_t>(n / 3);
        mesh.triangles[3 * n / 4].v[2] = static_cast<std::uint32_t>(n / 2);
        // Unreferenced vertices, far out and one not finite: ignored by both.
        mesh.vertices[n + 1] = {1e30f, -1e30f, 1e30f};
        mesh.vertices[n + 2] = {std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f};
        const Aabb expected = bounds(mesh.view());
        ASSERT_EQ(expected.upper.y, 7.0f);
        ASSERT_TRUE(std::signbit(expected.lower.z));
        for (const int threads : {1, 2, 4}) {
            Aabb box;
            ASSERT_EQ(checked_bounds_error(mesh.view(), threads, box), "");
            for (int k = 0; k < 3; ++k) {
                EXPECT_EQ(std::bit_cast<std::uint32_t>(box.lower[k]),
                          std::bit_cast<std::uint32_t>(expected.lower[k]));
                EXPECT_EQ(std::bit_cast<std::uint32_t>(box.upper[k]),
                          std::bit_cast<std::uint32_t>(expected.upper[k]));
            }
        }
        // Two bad triangles, or two bad vertices: the first bad triangle in the mesh's order
        // is named, as check_mesh names it.
        for (int kind = 0; kind < 2; ++kind) {
            Mesh bad = mesh;
            if (kind == 0) {
                bad.triangles[n - 5].v[0] = static_cast<std::uint32_t>(bad.vertices.size());
                bad.triangles[n / 5].v[2] = static_cast<std::uint32_t>(bad.vertices.size() + 7);
            } else {
                bad.vertices[bad.triangles[n - 5].v[1]].z = std::numeric_limits<float>::infinity();
                bad.vertices[bad.triangles[n / 5].v[0]].x = std::numeric_limits<float>::quiet_NaN();
            }
            std::size_t first = 0;  // the first triangle with a bad index or corner
            while (std::none_of(bad.triangles[first].v.begin(), bad.triangles[first].v.end(),
                                [&](std::uint32_t i) {
                                    return i >= bad.vertices.size() || !is_finite(bad.vertices[i]);
                                }))
                ++first;
            const std::string named = kind == 0 ? "triangle " + std::to_string(first) + " has"
                                                : "(of triangle " + std::to_string(first) + ")";
            const std::string expected_error = check_mesh_error(bad.view());
            ASSERT_NE(expected_error.find(named), std::string::npos) << expected_error;
            for (const int threads : {1, 2, 4}) {
                Aabb box;
                EXPECT_EQ(checked_bounds_error(bad.view(), threads, box), expected_error);
            }
        }
    }
}

}  // namespace
}  // namespace sg
