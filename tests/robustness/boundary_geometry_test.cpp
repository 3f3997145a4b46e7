// Row 4 of docs/ROBUSTNESS.md: geometry on cell boundaries. A 3D checkerboard of unit cubes
// (shared lattice vertices), placed so that cell boundaries coincide exactly with the cubes'
// faces: with the lattice in [2^16 - n, 2^16] the boundary pad (2^-20 of the largest
// coordinate) is exactly 1/16, the root box is the lattice widened by 1/16, and a forced
// resolution of 16 n + 2 makes every cell exactly 1/16 wide, so every 16th cell boundary is
// a lattice plane. The top three levels split x, y and z that way (max_depth 2; a floor and a
// ceiling over the lattice give every column the same extent in z). The test
// first proves that premise on the built grid, then compares random rays, rays aimed at
// triangles, vertices and edge midpoints, and rays grazing every face (lying in its plane,
// through its centre, along its edges and diagonals) with brute force.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "robustness_support.hpp"
#include "splitgrid/builder.hpp"
#include "support/random_scene.hpp"

namespace sg::test {
namespace {

constexpr int lattice = 4;             // cubes per axis
constexpr float top = 65536.0f;        // 2^16
constexpr float pad = 1.0f / 16.0f;    // top * 2^-20, builder.hpp's boundary_pad
constexpr int cells_per_unit = 16;     // cells of width `pad` per cube
constexpr float bottom = top - lattice;

struct Checkerboard {
    Mesh mesh;
    std::vector<std::array<int, 3>> cubes;  // lower corner offsets of the filled cubes
};

Checkerboard make_checkerboard()
{
    Checkerboard board;
    constexpr int side = lattice + 1;
    auto vertex = [](int i, int j, int k) {
        return static_cast<std::uint32_t>((i * side + j) * side + k);
    };
    for (int i = 0; i < side; ++i)
        for (int j = 0; j < side; ++j)
            for (int k = 0; k < side; ++k)
                board.mesh.vertices.push_back({bottom + float(i), bottom + float(j),
                                               bottom + float(k)});
    for (int i = 0; i < lattice; ++i)
        for (int j = 0; j < lattice; ++j)
            for (int k = 0; k < lattice; ++k) {
                if ((i + j + k) % 2 != 0) continue;
                board.cubes.push_back({i, j, k});
                // Two triangles per face; each face as the quad of its four lattice corners.
                for (int axis = 0; axis < 3; ++axis)
                    for (int side_k = 0; side_k < 2; ++side_k) {
                        std::array<std::uint32_t, 4> q{};
                        for (int c = 0; c < 4; ++c) {
                            std::array<int, 3> p{i, j, k};
                            p[static_cast<std::size_t>(axis)] += side_k;
                            p[static_cast<std::size_t>((axis + 1) % 3)] += c & 1;
                            p[static_cast<std::size_t>((axis + 2) % 3)] += (c >> 1) & 1;
                            q[static_cast<std::size_t>(c)] = vertex(p[0], p[1], p[2]);
                        }
                        board.mesh.triangles.push_back(Triangle{{q[0], q[1], q[3]}});
                        board.mesh.triangles.push_back(Triangle{{q[0], q[3], q[2]}});
                    }
            }
    // A floor and a ceiling over the whole lattice (its z faces), so that every column of
    // the grid holds geometry from z = bottom to z = top and the nodes that split z have the
    // same bounding planes as the root.
    for (int j = 0; j < lattice; ++j)
        for (int i = 0; i < lattice; ++i)
            for (int k : {0, lattice}) {
                const std::uint32_t a = vertex(i, j, k), b = vertex(i + 1, j, k);
                const std::uint32_t c = vertex(i, j + 1, k), d = vertex(i + 1, j + 1, k);
                board.mesh.triangles.push_back(Triangle{{a, b, d}});
                board.mesh.triangles.push_back(Triangle{{a, d, c}});
            }
    return board;
}

BuildConfig forced_unit_cells()
{
    BuildConfig config;
    config.resolution_min = cells_per_unit * lattice + 2;
    config.resolution_max = config.resolution_min;
    config.min_cell_width = 0.0;
    config.stop_by_cost = false;
    config.max_depth = 2;
    return config;
}

// Rays lying in the plane of a cube face, crossing the face: axis-aligned through its
// centre and along its four edges, along both diagonals, and random in-plane directions
// through random points of the face; starting outside the face and, for some, on it.
std::vector<Ray> grazing_rays(const Checkerboard& board, std::uint32_t seed, int per_face)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Ray> rays;
    for (const auto& cube : board.cubes)
        for (int axis = 0; axis < 3; ++axis)
            for (int side_k = 0; side_k < 2; ++side_k) {
                const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
                Vec3f corner{bottom + float(cube[0]), bottom + float(cube[1]),
                             bottom + float(cube[2])};
                corner[axis] += float(side_k);
                auto in_face = [&](float s1, float s2) {
                    Vec3f p = corner;
                    p[a1] += s1;
                    p[a2] += s2;
                    return p;
                };
                auto add = [&](Vec3f through, Vec3f direction) {
                    direction[axis] = (rays.size() % 2 == 0) ? 0.0f : -0.0f;
                    Ray r;
                    r.direction = direction;
                    r.origin = through - direction * 3.0f;  // 3 units back: outside the face
                    rays.push_back(r);
                    r.origin = through;  // on the face
                    rays.push_back(r);
                };
                Vec3f e1{}, e2{};
                e1[a1] = 1.0f;
                e2[a2] = 1.0f;
                add(in_face(0.5f, 0.5f), e1);
                add(in_face(0.5f, 0.5f), e2 * -1.0f);
                add(in_face(0.0f, 0.5f), e2);  // along the edges
                add(in_face(1.0f, 0.5f), e2 * -1.0f);
                add(in_face(0.5f, 0.0f), e1);
                add(in_face(0.5f, 1.0f), e1 * -1.0f);
                add(in_face(0.0f, 0.0f), e1 + e2);  // along the diagonals
                add(in_face(1.0f, 0.0f), e2 - e1);
                for (int k = 0; k < per_face; ++k) {
                    const float angle = 6.2831853f * u(rng);
                    add(in_face(u(rng), u(rng)), e1 * std::cos(angle) + e2 * std::sin(angle));
                }
            }
    return rays;
}

TEST(Checkerboard, CellBoundariesCoincideWithFacesAndRaysAgreeWithBruteForce)
{
    const Checkerboard board = make_checkerboard();
    const SplitGrid grid = build_checked(board.mesh, forced_unit_cells());

    // The premise: the nodes of the top three levels split x, y and z into cells of width
    // `pad` starting one pad below the lattice, so every 16th boundary is a lattice plane.
    ASSERT_EQ(boundary_pad(bounds(board.mesh.view())), pad);
    const std::vector<NodeBox> nodes = node_boxes(grid);
    std::array<std::size_t, 3> per_depth{};
    std::array<bool, 3> axis_seen{};
    for (const NodeBox& nb : nodes) {
        ++per_depth[nb.depth];
        const GridNode& node = grid.nodes[nb.node];
        axis_seen[static_cast<std::size_t>(node.axis())] = true;
        const CellMath cm(node.lo, node.hi, node.resolution());
        ASSERT_EQ(node.resolution(), static_cast<std::uint32_t>(cells_per_unit * lattice + 2));
        for (std::uint32_t i = 0; i <= node.resolution(); ++i)
            ASSERT_EQ(cm.boundary(i), bottom - pad + float(i) * pad) << "node " << nb.node;
        for (int k = 0; k <= lattice; ++k)
            ASSERT_EQ(cm.boundary(static_cast<std::uint32_t>(1 + cells_per_unit * k)),
                      bottom + float(k));
    }
    ASSERT_EQ(per_depth[0], 1u);
    ASSERT_GT(per_depth[1], 0u);
    ASSERT_GT(per_depth[2], 0u);
    ASSERT_TRUE(axis_seen[0] && axis_seen[1] && axis_seen[2]);

    const Aabb box{{bottom - 1.5f, bottom - 1.5f, bottom - 1.5f},
                   {top + 1.5f, top + 1.5f, top + 1.5f}};
    ASSERT_EQ(nodes.size(), grid.nodes.size());
    const std::size_t n = pick_size(100000, 1000000);
    std::vector<Ray> rays = random_rays(41, n / 2, box);
    const auto aimed = rays_at_triangles(42, n / 4, box, board.mesh.view());
    rays.insert(rays.end(), aimed.begin(), aimed.end());
    // Exactly through lattice points (vertices) and the midpoints of lattice edges.
    std::mt19937 rng(43);
    std::uniform_int_distribution<int> coord(0, lattice);
    std::uniform_int_distribution<int> edge_axis(0, 2);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    while (rays.size() < n) {
        Vec3f target;
        for (int k = 0; k < 3; ++k) target[k] = bottom + float(coord(rng));
        // Every other target the midpoint of a lattice edge instead of a lattice point.
        const int a = edge_axis(rng);
        if (rays.size() % 2 == 0 && target[a] < top) target[a] += 0.5f;
        Vec3f from;
        for (int k = 0; k < 3; ++k) from[k] = box.lower[k] + u(rng) * box.extent(k);
        if (const auto r = ray_through(from, target)) rays.push_back(*r);
    }
    const auto grazing = grazing_rays(board, 44, static_cast<int>(pick_size(4, 40)));
    rays.insert(rays.end(), grazing.begin(), grazing.end());

    const OracleReport r = parallel_compare(grid, board.mesh.view(), rays);
    std::printf("[ boundary ] %zu cubes, %zu triangles, %zu nodes; %zu rays (%zu grazing a "
                "face): %zu disagreements, %zu hits\n",
                board.cubes.size(), board.mesh.triangles.size(), grid.nodes.size(), r.rays,
                grazing.size(), r.closest_disagreements + r.any_hit_disagreements, r.hits);
    EXPECT_EQ(r.closest_disagreements, 0u) << r.first_failure;
    EXPECT_EQ(r.any_hit_disagreements, 0u) << r.first_failure;
    EXPECT_GT(r.hits, rays.size() / 4);
}

}  // namespace
}  // namespace sg::test
