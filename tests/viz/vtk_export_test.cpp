// The VTK export read back with VTK's own XML readers, checked against an independent walk of
// the grid (expected_export.hpp) and against compute_stats, the numbers sg-stats prints.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "expected_export.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "splitgrid/stats.hpp"
#include "splitgrid/viz/vtk_export.hpp"
#include "support/oracle.hpp"
#include "support/random_scene.hpp"
#include "support/scratch_dir.hpp"
#include "support/vtk_readback.hpp"

#include <gtest/gtest.h>
#include <vtkCellType.h>

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using viz::ExportOptions;

/// Clustered and scattered triangles, a sphere and a plane: deep and shallow subtrees, empty
/// cells, leaves of many sizes.
Mesh test_scene()
{
    Mesh mesh = random_triangles(11, 1500, Aabb{{0, 0, 0}, {10, 10, 10}}, 0.7f);
    append(mesh, uv_sphere({5, 5, 5}, 2.0f, 16, 32));
    append(mesh, axis_plane(1, 0.0f, 8));
    return mesh;
}

BuildConfig test_config()
{
    BuildConfig config;
    config.leaf_size = 4;
    config.resolution_max = 16;
    return config;
}

struct Fixture {
    Mesh mesh = test_scene();
    SplitGrid grid = build_checked(mesh, test_config());
    ExpectedExport expected = expected_export(grid);
    GridStats stats = compute_stats(grid);
};

const Fixture& fixture()
{
    static const Fixture f;
    return f;
}

viz::ExportSummary export_to(const fs::path& dir, const ExportOptions& options,
                             const Fixture& f = fixture())
{
    return viz::export_vtk(f.grid, f.mesh.view(), options, {"scene.obj", "scene.sg"}, dir);
}

using CellKey = std::pair<std::int64_t, std::uint32_t>;

/// The (node_id, cell_index) of every cell of a read-back cell block.
std::vector<CellKey> cell_keys(vtkDataSet* block)
{
    const std::vector<double> node = cell_values(block, "node_id");
    const std::vector<double> index = cell_values(block, "cell_index");
    std::vector<CellKey> keys;
    for (std::size_t i = 0; i < node.size(); ++i)
        keys.emplace_back(static_cast<std::int64_t>(node[i]), static_cast<std::uint32_t>(index[i]));
    return keys;
}

/// Every cell of a read-back cell block against the expected cell of the same key: geometry
/// in VTK's hexahedron corner order, and every array.
void expect_cells_match(vtkDataSet* block, const ExpectedExport& e)
{
    ASSERT_NE(block, nullptr);
    ASSERT_NE(block->GetCellData()->GetScalars(), nullptr);
    EXPECT_STREQ(block->GetCellData()->GetScalars()->GetName(), "depth");
    const std::vector<CellKey> keys = cell_keys(block);
    const std::vector<double> depth = cell_values(block, "depth");
    const std::vector<double> axis = cell_values(block, "axis");
    const std::vector<double> kind = cell_values(block, "kind");
    const std::vector<double> triangles = cell_values(block, "triangle_count");
    const std::vector<double> share = cell_values(block, "cost_share");
    std::set<vtkIdType> point_ids;
    for (vtkIdType c = 0; c < block->GetNumberOfCells(); ++c) {
        const auto i = static_cast<std::size_t>(c);
        const auto it = e.cells.find(keys[i]);
        ASSERT_NE(it, e.cells.end()) << "cell " << c << " names a cell that does not exist";
        const ExpectedCell& x = it->second;
        SCOPED_TRACE("node " + std::to_string(keys[i].first) + " cell " +
                     std::to_string(keys[i].second));
        EXPECT_EQ(block->GetCellType(c), VTK_HEXAHEDRON);
        EXPECT_EQ(depth[i], x.depth);
        EXPECT_EQ(axis[i], x.axis);
        EXPECT_EQ(kind[i], x.kind);
        EXPECT_EQ(triangles[i], static_cast<double>(x.triangles));
        EXPECT_NEAR(share[i], x.cost / e.total_cost, 1e-12 + 1e-9 * x.cost / e.total_cost);

        // VTK_HEXAHEDRON order: lower-z face counter-clockwise from (x0, y0), then upper-z.
        const auto points = cell_points(block, c);
        ASSERT_EQ(points.size(), 8u);
        const Vec3f& l = x.box.lower;
        const Vec3f& u = x.box.upper;
        const float corners[8][3] = {{l.x, l.y, l.z}, {u.x, l.y, l.z}, {u.x, u.y, l.z},
                                     {l.x, u.y, l.z}, {l.x, l.y, u.z}, {u.x, l.y, u.z},
                                     {u.x, u.y, u.z}, {l.x, u.y, u.z}};
        for (int k = 0; k < 8; ++k)
            for (int a = 0; a < 3; ++a)
                EXPECT_EQ(static_cast<float>(points[static_cast<std::size_t>(k)][static_cast<std::size_t>(a)]),
                          corners[k][a])
                    << "corner " << k << " axis " << a;

        vtkNew<vtkIdList> ids;
        block->GetCellPoints(c, ids);
        for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) point_ids.insert(ids->GetId(k));
    }
    EXPECT_EQ(point_ids.size(), static_cast<std::size_t>(8 * block->GetNumberOfCells()))
        << "every hexahedron has its own 8 points";
}

std::size_t count_cells(const ExpectedExport& e, bool with_empty, bool leaves_only = false)
{
    return static_cast<std::size_t>(std::count_if(e.cells.begin(), e.cells.end(), [&](const auto& c) {
        if (leaves_only) return c.second.kind == 1;
        return with_empty || c.second.kind != 0;
    }));
}

TEST(VtkExport, FullExportMatchesIndependentWalkAndStats)
{
    const Fixture& f = fixture();
    ScratchDir scratch;
    ExportOptions options;
    options.empty_cells = true;
    options.name = "scene";
    const viz::ExportSummary summary = export_to(scratch / "out", options);
    EXPECT_EQ(summary.vtm_path, scratch / "out" / "scene.vtm");
    const auto blocks = read_export(summary.vtm_path);
    ASSERT_EQ(block_names(blocks), (std::vector<std::string>{"cells", "planes", "leaves", "mesh"}));

    // cells: every cell of the grid once, empty ones included.
    vtkDataSet* cells = find_block(blocks, "cells");
    expect_cells_match(cells, f.expected);
    const std::vector<CellKey> keys = cell_keys(cells);
    EXPECT_EQ(std::set<CellKey>(keys.begin(), keys.end()).size(), keys.size()) << "no duplicates";
    EXPECT_EQ(keys.size(), f.expected.cells.size());
    EXPECT_EQ(keys.size(), f.stats.cell_count);
    const std::vector<double> kind = cell_values(cells, "kind");
    EXPECT_EQ(static_cast<std::size_t>(std::count(kind.begin(), kind.end(), 0.0)), f.stats.empty_cells);
    EXPECT_EQ(static_cast<std::size_t>(std::count(kind.begin(), kind.end(), 1.0)), f.stats.leaf_cells);
    EXPECT_EQ(static_cast<std::size_t>(std::count(kind.begin(), kind.end(), 2.0)), f.stats.inner_cells);
    const std::vector<double> depth = cell_values(cells, "depth");
    EXPECT_EQ(*std::max_element(depth.begin(), depth.end()), f.stats.max_depth);
    EXPECT_EQ(*std::min_element(depth.begin(), depth.end()), 0.0);

    // leaves: the leaf cells again, with the same arrays.
    vtkDataSet* leaves = find_block(blocks, "leaves");
    expect_cells_match(leaves, f.expected);
    EXPECT_EQ(static_cast<std::size_t>(leaves->GetNumberOfCells()), f.stats.leaf_cells);
    const std::vector<double> leaf_triangles = cell_values(leaves, "triangle_count");
    double reference_sum = 0.0;
    for (double t : leaf_triangles) reference_sum += t;
    EXPECT_EQ(reference_sum, static_cast<double>(f.stats.reference_count));
    EXPECT_EQ(*std::min_element(leaf_triangles.begin(), leaf_triangles.end()), f.stats.leaf_size_min);
    EXPECT_EQ(*std::max_element(leaf_triangles.begin(), leaf_triangles.end()), f.stats.leaf_size_max);

    // Cost shares: the root node's own terms plus its cells' shares make the whole cost.
    EXPECT_NEAR(f.expected.total_cost, f.stats.sah_cost, 1e-9 * f.stats.sah_cost)
        << "the independent cost model is the one sg-stats reports";
    const std::vector<double> share = cell_values(cells, "cost_share");
    double leaf_share = 0.0;
    for (std::size_t i = 0; i < share.size(); ++i) {
        EXPECT_GE(share[i], 0.0);
        EXPECT_LE(share[i], 1.0);
        if (kind[i] == 1.0) leaf_share += share[i];
    }
    double leaf_cost = 0.0;
    for (const auto& [key, c] : f.expected.cells)
        if (c.kind == 1) leaf_cost += c.cost;
    EXPECT_NEAR(leaf_share, leaf_cost / f.stats.sah_cost, 1e-9);
    EXPECT_LT(leaf_share, 1.0) << "nodes and cell steps cost something too";

    // planes: two per node, at lo and hi, spanning the node's box.
    vtkDataSet* planes = find_block(blocks, "planes");
    ASSERT_NE(planes, nullptr);
    EXPECT_STREQ(planes->GetCellData()->GetScalars()->GetName(), "depth");
    ASSERT_EQ(static_cast<std::size_t>(planes->GetNumberOfCells()), 2 * f.stats.node_count);
    const std::vector<double> node = cell_values(planes, "node_id");
    const std::vector<double> side = cell_values(planes, "side");
    const std::vector<double> plane_axis = cell_values(planes, "axis");
    const std::vector<double> plane_depth = cell_values(planes, "depth");
    const std::vector<double> cut = cell_values(planes, "cut_fraction");
    std::set<std::pair<std::int64_t, int>> seen;
    for (vtkIdType c = 0; c < planes->GetNumberOfCells(); ++c) {
        const auto i = static_cast<std::size_t>(c);
        const std::pair<std::int64_t, int> key{static_cast<std::int64_t>(node[i]),
                                               static_cast<int>(side[i])};
        seen.insert(key);
        const auto it = f.expected.planes.find(key);
        ASSERT_NE(it, f.expected.planes.end());
        EXPECT_EQ(planes->GetCellType(c), VTK_QUAD);
        EXPECT_EQ(cell_points(planes, c).size(), 4u);
        EXPECT_EQ(cell_bounds(planes, c), it->second.quad);
        EXPECT_EQ(plane_axis[i], it->second.axis);
        EXPECT_EQ(plane_depth[i], it->second.depth);
        EXPECT_NEAR(cut[i], it->second.cut_fraction, 1e-12);
        EXPECT_GE(cut[i], 0.0);
        EXPECT_LT(cut[i], 1.0);
    }
    EXPECT_EQ(seen.size(), 2 * f.stats.node_count);

    // mesh: the triangles, with how many leaves reference each.
    vtkDataSet* mesh = find_block(blocks, "mesh");
    ASSERT_NE(mesh, nullptr);
    ASSERT_EQ(static_cast<std::size_t>(mesh->GetNumberOfCells()), f.mesh.triangles.size());
    EXPECT_STREQ(mesh->GetCellData()->GetScalars()->GetName(), "reference_count");
    const std::vector<double> refs = cell_values(mesh, "reference_count");
    double mesh_refs = 0.0;
    for (std::size_t t = 0; t < refs.size(); ++t) {
        EXPECT_EQ(refs[t], static_cast<double>(f.expected.references_per_triangle[t])) << "triangle " << t;
        mesh_refs += refs[t];
    }
    EXPECT_EQ(mesh_refs, static_cast<double>(f.stats.reference_count));
    for (vtkIdType t = 0; t < mesh->GetNumberOfCells(); t += 97) {
        const auto points = cell_points(mesh, t);
        ASSERT_EQ(points.size(), 3u);
        for (int k = 0; k < 3; ++k) {
            const Vec3f v = f.mesh.vertices[f.mesh.triangles[static_cast<std::size_t>(t)].v[static_cast<std::size_t>(k)]];
            EXPECT_EQ(static_cast<float>(points[static_cast<std::size_t>(k)][0]), v.x);
            EXPECT_EQ(static_cast<float>(points[static_cast<std::size_t>(k)][1]), v.y);
            EXPECT_EQ(static_cast<float>(points[static_cast<std::size_t>(k)][2]), v.z);
        }
    }

    // Summary: the counts and the files as they are on disk.
    EXPECT_EQ(summary.counts.cells, f.stats.cell_count);
    EXPECT_EQ(summary.counts.leaves, f.stats.leaf_cells);
    EXPECT_EQ(summary.counts.planes, 2 * f.stats.node_count);
    EXPECT_EQ(summary.counts.mesh_triangles, f.mesh.triangles.size());
    ASSERT_EQ(summary.files.size(), 5u);
    EXPECT_EQ(summary.files.front().path, summary.vtm_path);
    std::uint64_t total = 0;
    for (const viz::ExportedFile& file : summary.files) {
        EXPECT_EQ(file.bytes, fs::file_size(file.path));
        total += file.bytes;
    }
    EXPECT_EQ(summary.total_bytes, total);
}

TEST(VtkExport, FieldDataHoldsSourceBuildParametersAndTotals)
{
    const Fixture& f = fixture();
    ScratchDir scratch;
    ExportOptions options;
    options.max_depth = 2;
    options.subtree = f.grid.root.child();
    const auto blocks = read_export(export_to(scratch / "out", options).vtm_path);
    ASSERT_EQ(blocks.size(), 4u);
    for (const ReadBlock& block : blocks) {
        SCOPED_TRACE(block.name);
        EXPECT_EQ(field_string(block.data, "source_name"), "scene.obj");
        EXPECT_EQ(field_string(block.data, "structure_name"), "scene.sg");
        EXPECT_EQ(field_number(block.data, "build_leaf_size"), 4.0);
        EXPECT_EQ(field_number(block.data, "build_resolution_max"), 16.0);
        EXPECT_EQ(field_number(block.data, "build_resolution_min"), f.grid.config.resolution_min);
        EXPECT_EQ(field_number(block.data, "build_resolution_sigma"), f.grid.config.resolution_sigma);
        EXPECT_EQ(field_number(block.data, "build_max_depth"), f.grid.config.max_depth);
        EXPECT_EQ(field_number(block.data, "build_stop_by_cost"), f.grid.config.stop_by_cost ? 1 : 0);
        EXPECT_EQ(field_number(block.data, "grid_node_count"), static_cast<double>(f.stats.node_count));
        EXPECT_EQ(field_number(block.data, "grid_cell_count"), static_cast<double>(f.stats.cell_count));
        EXPECT_EQ(field_number(block.data, "grid_reference_count"),
                  static_cast<double>(f.stats.reference_count));
        EXPECT_EQ(field_number(block.data, "grid_triangle_count"),
                  static_cast<double>(f.mesh.triangles.size()));
        EXPECT_NEAR(field_number(block.data, "grid_expected_cost"), f.stats.sah_cost,
                    1e-9 * f.stats.sah_cost);
        EXPECT_EQ(field_number(block.data, "export_min_depth"), 0.0);
        EXPECT_EQ(field_number(block.data, "export_max_depth"), 2.0);
        EXPECT_EQ(field_number(block.data, "export_subtree"), f.grid.root.child());
        EXPECT_EQ(field_number(block.data, "export_empty_cells"), 0.0);
    }
}

TEST(VtkExport, FilesAreAppendedRawZlibWithUInt64Headers)
{
    ScratchDir scratch;
    ExportOptions options;
    const viz::ExportSummary summary = export_to(scratch / "out", options);
    const std::string vtm = file_head(summary.vtm_path);
    EXPECT_NE(vtm.find("type=\"vtkMultiBlockDataSet\""), std::string::npos) << vtm;
    for (const char* name : {"cells", "planes", "leaves", "mesh"})
        EXPECT_NE(vtm.find("name=\"" + std::string(name) + "\""), std::string::npos) << name;
    for (std::size_t i = 1; i < summary.files.size(); ++i) {
        const std::string head = file_head(summary.files[i].path);
        SCOPED_TRACE(summary.files[i].path.string());
        EXPECT_NE(head.find("header_type=\"UInt64\""), std::string::npos);
        EXPECT_NE(head.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
        EXPECT_EQ(head.find("format=\"binary\""), std::string::npos) << "no inline base64";
        EXPECT_EQ(head.find("format=\"ascii\""), std::string::npos);
        const std::string whole = read_text(summary.files[i].path);
        EXPECT_NE(whole.find("<AppendedData encoding=\"raw\">"), std::string::npos);
    }
}

TEST(VtkExport, DepthLimitsSelectNodesByDepth)
{
    const Fixture& f = fixture();
    ASSERT_GE(f.stats.max_depth, 3u) << "the scene must be deep enough for this test";
    ScratchDir scratch;
    ExportOptions options;
    options.min_depth = 1;
    options.max_depth = 2;
    const viz::ExportSummary summary = export_to(scratch / "out", options);
    const auto blocks = read_export(summary.vtm_path);

    std::size_t expected_cells = 0, expected_leaves = 0, expected_nodes = 0;
    double leaf_depth_min = 3.0, leaf_depth_max = 0.0;
    for (const auto& [key, c] : f.expected.cells)
        if (c.depth >= 1 && c.depth <= 2 && c.kind != 0) {
            ++expected_cells;
            expected_leaves += c.kind == 1 ? 1 : 0;
            if (c.kind == 1) {
                leaf_depth_min = std::min(leaf_depth_min, static_cast<double>(c.depth));
                leaf_depth_max = std::max(leaf_depth_max, static_cast<double>(c.depth));
            }
        }
    for (std::uint32_t d : f.expected.node_depth) expected_nodes += (d >= 1 && d <= 2) ? 1 : 0;

    vtkDataSet* cells = find_block(blocks, "cells");
    expect_cells_match(cells, f.expected);
    EXPECT_EQ(static_cast<std::size_t>(cells->GetNumberOfCells()), expected_cells);
    EXPECT_EQ(static_cast<std::size_t>(find_block(blocks, "leaves")->GetNumberOfCells()), expected_leaves);
    EXPECT_EQ(static_cast<std::size_t>(find_block(blocks, "planes")->GetNumberOfCells()), 2 * expected_nodes);
    for (const char* name : {"cells", "planes", "leaves"}) {
        const std::vector<double> depth = cell_values(find_block(blocks, name), "depth");
        ASSERT_FALSE(depth.empty()) << name;
        // Leaves lie at the depths the independent walk found them at (with bounding nodes, a
        // leaf is often one level below the cell it would otherwise be).
        const bool leaves = std::string_view(name) == "leaves";
        EXPECT_EQ(*std::min_element(depth.begin(), depth.end()), leaves ? leaf_depth_min : 1.0) << name;
        EXPECT_EQ(*std::max_element(depth.begin(), depth.end()), leaves ? leaf_depth_max : 2.0) << name;
    }
    EXPECT_EQ(static_cast<std::size_t>(find_block(blocks, "mesh")->GetNumberOfCells()),
              f.mesh.triangles.size()) << "the mesh is always whole";
    EXPECT_EQ(summary.counts.selected_nodes, expected_nodes);
}

TEST(VtkExport, SubtreeSelectsOneNodeAndItsDescendants)
{
    const Fixture& f = fixture();
    // The node at depth 1 with the most descendants.
    std::vector<std::size_t> descendants(f.grid.nodes.size(), 0);
    for (std::size_t n = 0; n < f.grid.nodes.size(); ++n)
        for (std::int64_t p = f.expected.node_parent[n]; p >= 0; p = f.expected.node_parent[static_cast<std::size_t>(p)])
            ++descendants[static_cast<std::size_t>(p)];
    std::uint32_t start = f.grid.root.child();
    for (std::uint32_t n = 0; n < f.grid.nodes.size(); ++n)
        if (f.expected.node_depth[n] == 1 &&
            (f.expected.node_depth[start] == 0 || descendants[n] > descendants[start]))
            start = n;
    ASSERT_EQ(f.expected.node_depth[start], 1u);
    ASSERT_GT(descendants[start], 2u);

    std::set<std::int64_t> in_subtree;
    for (std::size_t n = 0; n < f.grid.nodes.size(); ++n)
        for (std::int64_t p = static_cast<std::int64_t>(n); p >= 0; p = f.expected.node_parent[static_cast<std::size_t>(p)])
            if (p == start) in_subtree.insert(static_cast<std::int64_t>(n));

    ScratchDir scratch;
    ExportOptions options;
    options.subtree = start;
    options.empty_cells = true;
    const auto blocks = read_export(export_to(scratch / "out", options).vtm_path);
    vtkDataSet* cells = find_block(blocks, "cells");
    expect_cells_match(cells, f.expected);
    std::set<std::int64_t> exported_nodes;
    for (const CellKey& key : cell_keys(cells)) exported_nodes.insert(key.first);
    EXPECT_EQ(exported_nodes, in_subtree);
    std::size_t subtree_cells = 0;
    for (const std::int64_t n : in_subtree) subtree_cells += f.grid.nodes[static_cast<std::size_t>(n)].resolution();
    EXPECT_EQ(static_cast<std::size_t>(cells->GetNumberOfCells()), subtree_cells);

    const std::vector<double> plane_nodes = cell_values(find_block(blocks, "planes"), "node_id");
    EXPECT_EQ(std::set<std::int64_t>(plane_nodes.begin(), plane_nodes.end()), in_subtree);
    const std::vector<double> depth = cell_values(cells, "depth");
    EXPECT_EQ(*std::min_element(depth.begin(), depth.end()), 1.0) << "depths count from the root";
}

TEST(VtkExport, PartsChooseTheBlocks)
{
    ScratchDir scratch;
    ExportOptions options;
    options.parts = {.cells = false, .planes = true, .leaves = false, .mesh = true};
    const viz::ExportSummary summary = export_to(scratch / "a", options);
    EXPECT_EQ(block_names(read_export(summary.vtm_path)), (std::vector<std::string>{"planes", "mesh"}));
    EXPECT_EQ(summary.counts.cells, 0u);
    EXPECT_EQ(summary.counts.leaves, 0u);
    EXPECT_EQ(summary.files.size(), 3u);

    options.parts = {.cells = false, .planes = false, .leaves = true, .mesh = false};
    const auto leaves_only = read_export(export_to(scratch / "b", options).vtm_path);
    ASSERT_EQ(block_names(leaves_only), (std::vector<std::string>{"leaves"}));
    EXPECT_EQ(static_cast<std::size_t>(leaves_only[0].data->GetNumberOfCells()),
              fixture().stats.leaf_cells);
}

TEST(VtkExport, OverTheLimitWritesNothingAndSaysWhatWouldFit)
{
    const Fixture& f = fixture();
    ScratchDir scratch;
    ExportOptions options;
    const viz::ExportCounts counts = viz::count_export(f.grid, f.mesh.view(), options);
    const std::size_t nonempty = count_cells(f.expected, false);
    EXPECT_EQ(counts.cells, nonempty);
    EXPECT_EQ(counts.leaves, f.stats.leaf_cells);
    EXPECT_EQ(counts.planes, 2 * f.stats.node_count);
    EXPECT_EQ(counts.primitives(), nonempty + f.stats.leaf_cells + 2 * f.stats.node_count);

    // primitives_by_max_depth[d] is what --max-depth d would export.
    ASSERT_EQ(counts.primitives_by_max_depth.size(), f.stats.max_depth + 1);
    EXPECT_EQ(counts.primitives_by_max_depth.back(), counts.primitives());
    for (std::uint32_t d = 0; d <= f.stats.max_depth; d += 2) {
        ExportOptions limited;
        limited.max_depth = d;
        EXPECT_EQ(counts.primitives_by_max_depth[d],
                  viz::count_export(f.grid, f.mesh.view(), limited).primitives()) << "depth " << d;
    }

    options.primitive_limit = counts.primitives() - 1;
    try {
        (void)export_to(scratch / "out", options);
        FAIL() << "expected ExportLimitError";
    } catch (const viz::ExportLimitError& e) {
        EXPECT_EQ(e.limit(), counts.primitives() - 1);
        EXPECT_EQ(e.counts().primitives(), counts.primitives());
        EXPECT_NE(std::string(e.what()).find(std::to_string(counts.primitives())), std::string::npos);
    }
    EXPECT_TRUE(scratch.entries().empty()) << "nothing written, no staging folder left";

    options.primitive_limit = counts.primitives();
    EXPECT_NO_THROW((void)export_to(scratch / "out", options)) << "the limit itself is allowed";
    options.primitive_limit = 0;
    EXPECT_NO_THROW((void)export_to(scratch / "unlimited", options));
}

TEST(VtkExport, ExistingFoldersAreReplacedOnlyWhenTheyHoldAnExport)
{
    ScratchDir scratch;
    ExportOptions options;
    options.parts = {.cells = false, .planes = true, .leaves = false, .mesh = false};

    // An empty folder is used.
    fs::create_directory(scratch / "empty");
    EXPECT_NO_THROW((void)export_to(scratch / "empty", options));
    EXPECT_TRUE(fs::exists(scratch / "empty" / "splitgrid.vtm"));

    // A folder with other things in it is never touched, with or without replace_existing.
    fs::create_directory(scratch / "mine");
    write_text(scratch / "mine" / "notes.txt", "keep me");
    for (bool replace : {false, true}) {
        options.replace_existing = replace;
        EXPECT_THROW((void)export_to(scratch / "mine", options), IoError) << replace;
        EXPECT_EQ(folder_entries(scratch / "mine"), (std::vector<std::string>{"notes.txt"}));
        EXPECT_EQ(read_text(scratch / "mine" / "notes.txt"), "keep me");
    }

    // An earlier export is replaced only on request, and then completely.
    options.replace_existing = false;
    options.name = "first";
    (void)export_to(scratch / "out", options);
    options.name = "second";
    EXPECT_THROW((void)export_to(scratch / "out", options), IoError);
    EXPECT_EQ(folder_entries(scratch / "out"), (std::vector<std::string>{"first", "first.vtm"}));
    options.replace_existing = true;
    (void)export_to(scratch / "out", options);
    EXPECT_EQ(folder_entries(scratch / "out"), (std::vector<std::string>{"second", "second.vtm"}));
    EXPECT_EQ(block_names(read_export(scratch / "out" / "second.vtm")),
              (std::vector<std::string>{"planes"}));

    // A trailing separator names the same folder.
    (void)export_to(scratch.path().string() + "/out/", options);
    EXPECT_EQ(folder_entries(scratch / "out"), (std::vector<std::string>{"second", "second.vtm"}));

    // No staging folders are left beside the outputs.
    EXPECT_EQ(scratch.entries(), (std::vector<std::string>{"empty", "mine", "out"}));
}

TEST(VtkExport, RefusesImpossibleRequestsBeforeWriting)
{
    const Fixture& f = fixture();
    ScratchDir scratch;
    ExportOptions options;
    options.min_depth = 3;
    options.max_depth = 2;
    EXPECT_THROW((void)export_to(scratch / "out", options), ConfigError);
    options = {};
    options.subtree = static_cast<std::uint32_t>(f.grid.nodes.size());
    EXPECT_THROW((void)export_to(scratch / "out", options), ConfigError);
    for (const char* name : {"", ".hidden", "a/b", "two words"}) {
        options = {};
        options.name = name;
        EXPECT_THROW((void)export_to(scratch / "out", options), ConfigError) << name;
    }
    options = {};
    EXPECT_THROW((void)export_to(scratch / "missing" / "out", options), IoError);
    write_text(scratch / "file", "x");
    EXPECT_THROW((void)export_to(scratch / "file", options), IoError);
    EXPECT_EQ(scratch.entries(), (std::vector<std::string>{"file"}));
}

TEST(VtkExport, NameForFileKeepsTheStemSafe)
{
    EXPECT_EQ(viz::export_name_for("scans/dragon.sg"), "dragon");
    EXPECT_EQ(viz::export_name_for("my scene (v2).sg"), "my_scene__v2_");
    EXPECT_EQ(viz::export_name_for("..sg"), "splitgrid");
    EXPECT_EQ(viz::export_name_for(".hidden.v1.sg"), "hidden.v1");
    EXPECT_EQ(viz::export_name_for(std::string(300, 'a') + ".sg"), std::string(100, 'a'));
}

TEST(VtkExport, GridWithoutNodesExportsItsRootCell)
{
    Fixture f;
    f.mesh = axis_plane(2, 1.0f, 1);  // 2 triangles: below the leaf size, so the root is a leaf
    f.grid = build_checked(f.mesh, BuildConfig{});
    ASSERT_TRUE(f.grid.root.is_leaf());
    f.expected = expected_export(f.grid);
    f.stats = compute_stats(f.grid);

    ScratchDir scratch;
    const auto blocks = read_export(export_to(scratch / "out", ExportOptions{}, f).vtm_path);
    ASSERT_EQ(block_names(blocks), (std::vector<std::string>{"cells", "leaves", "mesh"}))
        << "the empty planes block is left out";
    for (const ReadBlock& block : blocks) ASSERT_NE(block.data, nullptr) << block.name;
    vtkDataSet* cells = find_block(blocks, "cells");
    ASSERT_EQ(cells->GetNumberOfCells(), 1);
    expect_cells_match(cells, f.expected);
    EXPECT_EQ(cell_values(cells, "node_id"), std::vector<double>{-1.0});
    EXPECT_EQ(cell_values(cells, "cost_share"), std::vector<double>{1.0});
    EXPECT_EQ(cell_bounds(cells, 0), f.grid.root_box);
    EXPECT_EQ(find_block(blocks, "leaves")->GetNumberOfCells(), 1);
    EXPECT_EQ(cell_values(find_block(blocks, "mesh"), "reference_count"), (std::vector<double>{1.0, 1.0}));
}

TEST(VtkExport, RealModelCountsMatchStats)
{
    const fs::path model = fs::path(SG_ASSIMP_MODELS_DIR) / "Collada" / "duck.dae";
    ASSERT_TRUE(fs::exists(model)) << model << ": install assimp-testmodels";
    Fixture f;
    f.mesh = import_mesh(model).mesh;
    f.grid = build_checked(f.mesh, BuildConfig{});
    f.stats = compute_stats(f.grid);
    ScratchDir scratch;
    const auto blocks = read_export(export_to(scratch / "duck", ExportOptions{}, f).vtm_path);
    EXPECT_EQ(static_cast<std::size_t>(find_block(blocks, "cells")->GetNumberOfCells()),
              f.stats.cell_count - f.stats.empty_cells);
    EXPECT_EQ(static_cast<std::size_t>(find_block(blocks, "leaves")->GetNumberOfCells()),
              f.stats.leaf_cells);
    EXPECT_EQ(static_cast<std::size_t>(find_block(blocks, "planes")->GetNumberOfCells()),
              2 * f.stats.node_count);
    double leaf_refs = 0.0, mesh_refs = 0.0;
    for (double t : cell_values(find_block(blocks, "leaves"), "triangle_count")) leaf_refs += t;
    for (double r : cell_values(find_block(blocks, "mesh"), "reference_count")) mesh_refs += r;
    EXPECT_EQ(leaf_refs, static_cast<double>(f.stats.reference_count));
    EXPECT_EQ(mesh_refs, static_cast<double>(f.stats.reference_count));
    const std::vector<double> depth = cell_values(find_block(blocks, "cells"), "depth");
    EXPECT_EQ(*std::max_element(depth.begin(), depth.end()), f.stats.max_depth);
}

}  // namespace
}  // namespace sg::test
