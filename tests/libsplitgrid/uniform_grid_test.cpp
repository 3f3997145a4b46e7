// The uniform grid: brute-force oracle cases (baseline_oracle_cases.hpp), its resolution rule,
// exact cell assignment checked with an independent separating-axis test, and config checks.

#include "splitgrid/baselines/uniform_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "baseline_oracle_cases.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/clip.hpp"
#include "splitgrid/error.hpp"

namespace sg::test {

template <>
struct BaselineTraits<UniformGrid> {
    // Every triangle is referenced by each cell whose box it overlaps (separating-axis test,
    // independent of the builder's clipping), and by no cell farther than the pad. Cells
    // farther than twice the pad from a triangle's bounding box are covered by counting: the
    // references found near the triangles must be all there are.
    static void check(const UniformGrid& grid, const MeshView& mesh)
    {
        ASSERT_EQ(grid.triangle_count(), mesh.triangle_count());
        if (mesh.triangle_count() == 0) {
            ASSERT_EQ(grid.cell_count(), 0u);
            return;
        }
        const float pad = boundary_pad(bounds(mesh));
        const std::array<CellMath, 3> cells{grid.axis_cells(0), grid.axis_cells(1), grid.axis_cells(2)};
        std::size_t references = 0;
        for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
            const Vec3d a(mesh.vertex(t, 0)), b(mesh.vertex(t, 1)), c(mesh.vertex(t, 2));
            std::uint32_t first[3], last[3];
            for (int k = 0; k < 3; ++k) {
                const auto uk = static_cast<std::size_t>(k);
                const float tri_lo = static_cast<float>(std::min({a[k], b[k], c[k]}));
                const float tri_hi = static_cast<float>(std::max({a[k], b[k], c[k]}));
                first[k] = cells[uk].locate_lowest(tri_lo - 2.0f * pad);
                last[k] = cells[uk].locate_highest(tri_hi + 2.0f * pad);
            }
            for (std::uint32_t z = first[2]; z <= last[2]; ++z)
                for (std::uint32_t y = first[1]; y <= last[1]; ++y)
                    for (std::uint32_t x = first[0]; x <= last[0]; ++x) {
                        const auto refs = grid.cell_triangles(x, y, z);
                        ASSERT_TRUE(std::is_sorted(refs.begin(), refs.end()));
                        const bool referenced = std::binary_search(refs.begin(), refs.end(), t);
                        references += referenced ? 1 : 0;
                        const std::uint32_t index[3] = {x, y, z};
                        Aabbd box;
                        for (std::size_t k = 0; k < 3; ++k) {
                            box.lower[static_cast<int>(k)] = cells[k].boundary(index[k]);
                            box.upper[static_cast<int>(k)] = cells[k].boundary(index[k] + 1);
                        }
                        if (triangle_overlaps_box(a, b, c, box)) {
                            ASSERT_TRUE(referenced) << "triangle " << t << " overlaps cell (" << x
                                                    << ' ' << y << ' ' << z << ") that misses it";
                        }
                        if (referenced) {
                            ASSERT_TRUE(triangle_overlaps_box(a, b, c, box.padded(2.0 * pad)))
                                << "triangle " << t << " is referenced by a cell it does not touch";
                        }
                    }
        }
        ASSERT_EQ(references, grid.reference_count()) << "references far from their triangles";
    }
    static std::vector<std::pair<int, float>> planes(const UniformGrid& grid)
    {
        std::vector<std::pair<int, float>> p;
        for (int k = 0; k < 3; ++k) {
            const CellMath cm = grid.axis_cells(k);
            for (std::uint32_t i = 0; i <= cm.n; ++i) p.emplace_back(k, cm.boundary(i));
        }
        return p;
    }
    static UniformGridConfig stable_planes_config()
    {
        UniformGridConfig config;
        config.resolution = {7, 9, 11};
        return config;
    }
    static std::uint32_t depth(const UniformGrid&) { return 0; }
    static std::uint32_t depth_limit(std::size_t) { return 0; }
};

INSTANTIATE_TYPED_TEST_SUITE_P(UniformGrid, BaselineOracle, ::testing::Types<UniformGrid>);

namespace {

TEST(UniformGridResolution, CubeRootRuleGivesAboutDensityTimesTrianglesCubicCells)
{
    const Aabb scene{{0, 0, 0}, {10, 20, 40}};
    for (double density : {1.0, 2.0, 8.0}) {
        UniformGridConfig config;
        config.density = density;
        const auto res = grid_resolution(scene, 5000, config);
        const double cells = double(res[0]) * res[1] * res[2];
        EXPECT_GT(cells, 0.7 * density * 5000);
        EXPECT_LT(cells, 1.3 * density * 5000);
        // Cubic cells: the same edge on every axis, up to rounding to whole cells.
        const double edge_x = 10.0 / res[0], edge_z = 40.0 / res[2];
        EXPECT_NEAR(edge_x / edge_z, 1.0, 0.2) << density;
    }
}

TEST(UniformGridResolution, FlatAndThinScenesGetOneCellAcross)
{
    UniformGridConfig config;
    config.density = 4.0;
    const auto flat = grid_resolution(Aabb{{0, 0, 5}, {30, 30, 5}}, 900, config);
    EXPECT_EQ(flat[2], 1u);
    EXPECT_EQ(flat[0], 60u);  // sqrt(4 * 900) = 60 cells per side
    EXPECT_EQ(flat[1], 60u);
    const auto thin = grid_resolution(Aabb{{0, 0, 0}, {30, 30, 0.01f}}, 900, config);
    EXPECT_EQ(thin[2], 1u);
    EXPECT_EQ(thin[0], 60u);
    const auto line = grid_resolution(Aabb{{0, 0, 0}, {0, 0, 8}}, 100, config);
    EXPECT_EQ(line[0], 1u);
    EXPECT_EQ(line[1], 1u);
    EXPECT_EQ(line[2], 400u);
}

TEST(UniformGridResolution, MaxCellsCapsTheProduct)
{
    UniformGridConfig config;
    config.max_cells = 1000;
    const auto res = grid_resolution(Aabb{{0, 0, 0}, {10, 10, 10}}, 100000, config);
    EXPECT_LE(std::uint64_t{res[0]} * res[1] * res[2], 1000u);
    EXPECT_GE(std::uint64_t{res[0]} * res[1] * res[2], 500u);
}

TEST(UniformGridBuild, FixedResolutionIsUsedAsGiven)
{
    const Mesh mesh = random_triangles(5, 500, baseline_scene_box, 1.0f);
    UniformGridConfig config;
    config.resolution = {3, 4, 5};
    const UniformGrid grid = build_checked_baseline<UniformGrid>(mesh, config);
    EXPECT_EQ(grid.resolution(), config.resolution);
    EXPECT_EQ(grid.cell_count(), 60u);
    EXPECT_EQ(grid.memory_bytes(),
              sizeof(Aabb) + 16u + 61u * 4u + grid.reference_count() * 4u);
}

TEST(UniformGridConfig, BadValuesNameTheField)
{
    UniformGridConfig c;
    EXPECT_EQ(config_error(c), "");
    c.density = 0.0;
    EXPECT_NE(config_error(c).find("UniformGridConfig.density = 0"), std::string::npos);
    c.density = std::nan("");
    EXPECT_NE(config_error(c).find("density"), std::string::npos);
    c = {};
    c.resolution = {4, 0, 4};
    EXPECT_NE(config_error(c).find("resolution"), std::string::npos);
    c = {};
    c.max_cells = 0;
    EXPECT_NE(config_error(c).find("max_cells"), std::string::npos);
    c = {};
    c.threads = 5000;
    EXPECT_NE(config_error(c).find("threads"), std::string::npos);
    c = {};
    c.density = -1.0;
    const Mesh mesh = random_triangles(1, 10, baseline_scene_box, 1.0f);
    EXPECT_THROW((void)UniformGrid::build(mesh.view(), c), ConfigError);
}

TEST(UniformGridBuild, BadMeshIsAnInputError)
{
    Mesh mesh = random_triangles(1, 10, baseline_scene_box, 1.0f);
    mesh.triangles[3].v[1] = 1000;
    EXPECT_THROW((void)UniformGrid::build(mesh.view()), InputError);
    mesh = random_triangles(1, 10, baseline_scene_box, 1.0f);
    mesh.vertices[4].y = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW((void)UniformGrid::build(mesh.view()), InputError);
}

}  // namespace
}  // namespace sg::test
