// End-to-end tests of sg-stats: its JSON against figures counted here from the grid read
// back (an independent walk) and against compute_stats; the text form; bad files.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "app_test_support.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/formats/mesh_import.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/stats.hpp"
#include "support/leaf_triangles.hpp"
#include "support/random_scene.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// Figures of a grid counted by walking it from the root, without compute_stats.
struct Walk {
    std::size_t nodes = 0;
    std::size_t cells = 0;
    std::size_t empty = 0;
    std::size_t leaves = 0;
    std::size_t inner = 0;
    std::size_t references = 0;
    std::set<std::uint32_t> distinct;
    std::uint32_t max_depth = 0;
    std::vector<std::size_t> nodes_per_depth;
    std::vector<double> resolution_sum_per_depth;
    std::vector<std::vector<std::size_t>> resolution_histogram;
    std::size_t leaf_min = 0;
    std::size_t leaf_max = 0;
    std::vector<std::size_t> leaf_histogram;
    double leaf_depth_sum = 0.0;
};

/// Adds one to bin floor(log2(value)) of `bins`, growing it as needed.
void add_to_log2_bin(std::vector<std::size_t>& bins, std::size_t value)
{
    const auto bin = static_cast<std::size_t>(std::bit_width(value) - 1);
    if (bins.size() <= bin) bins.resize(bin + 1, 0);
    ++bins[bin];
}

void count_leaf(Walk& w, const CellRef& cell, const SplitGrid& grid, std::size_t leaf_depth)
{
    ++w.leaves;
    const std::vector<std::uint32_t> ids = leaf_triangles(grid, cell);
    const std::size_t size = ids.size();
    w.references += size;
    w.leaf_min = w.leaves == 1 ? size : std::min(w.leaf_min, size);
    w.leaf_max = std::max(w.leaf_max, size);
    add_to_log2_bin(w.leaf_histogram, size);
    w.leaf_depth_sum += static_cast<double>(leaf_depth);
    w.distinct.insert(ids.begin(), ids.end());
}

Walk walk(const SplitGrid& grid)
{
    Walk w;
    // A leaf's depth is the number of inner nodes above it: a root leaf has depth 0, a leaf
    // cell of a node at depth d has depth d + 1 (docs/STATS_JSON.md).
    if (grid.root.is_leaf()) count_leaf(w, grid.root, grid, 0);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> stack;  // (node, depth)
    if (grid.root.is_inner()) stack.emplace_back(grid.root.child(), 0);
    while (!stack.empty()) {
        const auto [index, depth] = stack.back();
        stack.pop_back();
        const GridNode& node = grid.nodes.at(index);
        ++w.nodes;
        w.max_depth = std::max(w.max_depth, depth);
        if (w.nodes_per_depth.size() <= depth) {
            w.nodes_per_depth.resize(depth + 1, 0);
            w.resolution_sum_per_depth.resize(depth + 1, 0.0);
            w.resolution_histogram.resize(depth + 1);
        }
        ++w.nodes_per_depth[depth];
        w.resolution_sum_per_depth[depth] += node.resolution();
        add_to_log2_bin(w.resolution_histogram[depth], node.resolution());
        for (std::uint32_t c = 0; c < node.resolution(); ++c) {
            const CellRef cell = node_cell(grid, node, c);
            ++w.cells;
            if (cell.is_empty()) ++w.empty;
            if (cell.is_leaf()) count_leaf(w, cell, grid, depth + 1);
            if (cell.is_inner()) {
                ++w.inner;
                stack.emplace_back(cell.child(), depth + 1);
            }
        }
    }
    return w;
}

/// Compares histograms ignoring trailing empty bins (a histogram may or may not carry them).
std::vector<std::size_t> trimmed(std::vector<std::size_t> bins)
{
    while (!bins.empty() && bins.back() == 0) bins.pop_back();
    return bins;
}

/// A scene with clustered and spread-out triangles and a plane, written by the library
/// itself (not sg-build), so these tests do not depend on sg-build being right.
fs::path write_random_scene(const ScratchDir& scratch, const BuildConfig& config)
{
    Mesh mesh = random_triangles(7, 3000, Aabb{{0, 0, 0}, {10, 10, 10}}, 0.8f);
    append(mesh, uv_sphere({5, 5, 5}, 2.0f, 24, 48));
    append(mesh, axis_plane(1, 0.0f, 12));
    SgContents contents;
    contents.grid = build_split_grid(mesh.view(), config);
    contents.mesh = std::move(mesh);
    contents.source_name = "random_scene";
    const fs::path path = scratch / "scene.sg";
    write_sg_file(path, contents);
    return path;
}

void expect_json_matches_file(const json& j, const fs::path& path)
{
    const SgContents contents = read_sg_file(path);
    const SplitGrid& grid = contents.grid;
    const std::size_t triangles = contents.mesh.triangles.size();
    const Walk w = walk(grid);
    const GridStats reference = compute_stats(grid);

    EXPECT_EQ(j.at("schema_version"), 1);
    // File header, against the header reader and the file system.
    const SgFileInfo info = read_sg_info(path);
    EXPECT_EQ(j.at("file").at("bytes"), fs::file_size(path));
    EXPECT_EQ(j.at("file").at("format_version"), sg_format_version);
    const json& sections = j.at("file").at("sections");
    ASSERT_EQ(sections.size(), info.sections.size());
    std::uint64_t section_bytes = 0;
    for (std::size_t i = 0; i < info.sections.size(); ++i) {
        EXPECT_EQ(sections[i].at("name"), info.sections[i].name);
        EXPECT_EQ(sections[i].at("bytes"), info.sections[i].bytes);
        EXPECT_EQ(sections[i].at("count"), info.sections[i].count);
        section_bytes += info.sections[i].bytes;
    }
    EXPECT_LE(section_bytes, fs::file_size(path));
    EXPECT_EQ(j.at("source_name"), contents.source_name);
    EXPECT_EQ(j.at("build_config").at("leaf_size"), grid.config.leaf_size);
    EXPECT_EQ(j.at("build_config").at("max_depth"), grid.config.max_depth);
    EXPECT_EQ(j.at("build_config").at("resolution_sigma"), grid.config.resolution_sigma);
    EXPECT_EQ(j.at("mesh").at("triangle_count"), triangles);
    EXPECT_EQ(j.at("mesh").at("vertex_count"), contents.mesh.vertices.size());

    // Totals, against the independent walk.
    const json& g = j.at("grid");
    EXPECT_EQ(g.at("triangle_count"), triangles);
    EXPECT_EQ(g.at("node_count"), w.nodes);
    EXPECT_EQ(g.at("node_count"), grid.nodes.size()) << "every node is reachable";
    EXPECT_EQ(g.at("cell_count"), w.cells);
    EXPECT_EQ(g.at("empty_cells"), w.empty);
    EXPECT_EQ(g.at("leaf_cells"), w.leaves);
    EXPECT_EQ(g.at("inner_cells"), w.inner);
    EXPECT_EQ(g.at("reference_count"), w.references);
    EXPECT_EQ(g.at("reference_count"), test::counted_references(grid));
    EXPECT_EQ(g.at("referenced_triangles"), w.distinct.size());
    EXPECT_EQ(g.at("max_depth"), w.max_depth);
    EXPECT_EQ(g.at("nodes_per_depth").get<std::vector<std::size_t>>(), w.nodes_per_depth);
    const auto mean_res = g.at("mean_resolution_per_depth").get<std::vector<double>>();
    ASSERT_EQ(mean_res.size(), w.nodes_per_depth.size());
    const auto res_hist = g.at("resolution_histogram").get<std::vector<std::vector<std::size_t>>>();
    ASSERT_EQ(res_hist.size(), w.nodes_per_depth.size());
    for (std::size_t d = 0; d < mean_res.size(); ++d) {
        EXPECT_NEAR(mean_res[d],
                    w.resolution_sum_per_depth[d] / static_cast<double>(w.nodes_per_depth[d]),
                    1e-9);
        EXPECT_EQ(trimmed(res_hist[d]), trimmed(w.resolution_histogram[d])) << "depth " << d;
    }
    EXPECT_EQ(g.at("leaf_size_min"), w.leaf_min);
    EXPECT_EQ(g.at("leaf_size_max"), w.leaf_max);
    EXPECT_NEAR(g.at("leaf_size_mean").get<double>(),
                static_cast<double>(w.references) / static_cast<double>(w.leaves), 1e-9);
    EXPECT_EQ(trimmed(g.at("leaf_size_histogram").get<std::vector<std::size_t>>()),
              trimmed(w.leaf_histogram));
    EXPECT_NEAR(g.at("mean_leaf_depth").get<double>(),
                w.leaf_depth_sum / static_cast<double>(w.leaves), 1e-9);
    EXPECT_NEAR(g.at("empty_cell_fraction").get<double>(),
                static_cast<double>(w.empty) / static_cast<double>(w.cells), 1e-12);
    EXPECT_NEAR(g.at("duplication_factor").get<double>(),
                static_cast<double>(w.references) / static_cast<double>(triangles), 1e-12);

    // Memory, against the record sizes.
    EXPECT_EQ(g.at("node_bytes"), grid.nodes.size() * sizeof(GridNode));
    EXPECT_EQ(g.at("cell_bytes"), grid.cells.size() * sizeof(CellRef));
    EXPECT_EQ(g.at("reference_bytes"), grid.leaf_words.size() * 2);
    EXPECT_EQ(g.at("structure_bytes"), grid.memory_bytes());
    const std::size_t mesh_bytes = contents.mesh.vertices.size() * sizeof(Vec3f) +
                                   triangles * sizeof(Triangle);
    EXPECT_EQ(j.at("mesh").at("bytes"), mesh_bytes);
    const json& bpt = j.at("bytes_per_triangle");
    const auto per_tri = [&](std::size_t bytes) {
        return static_cast<double>(bytes) / static_cast<double>(triangles);
    };
    EXPECT_DOUBLE_EQ(bpt.at("structure").get<double>(), per_tri(grid.memory_bytes()));
    EXPECT_DOUBLE_EQ(bpt.at("structure_and_mesh").get<double>(),
                     per_tri(grid.memory_bytes() + mesh_bytes));
    EXPECT_DOUBLE_EQ(bpt.at("file").get<double>(),
                     per_tri(static_cast<std::size_t>(fs::file_size(path))));

    // The cost model has no independent implementation here: it must equal the library's.
    EXPECT_DOUBLE_EQ(g.at("sah_cost").get<double>(), reference.sah_cost);
    EXPECT_GT(reference.sah_cost, 0.0);
    EXPECT_EQ(g.at("cost_model").at("triangle_cost"), reference.cost_model.triangle_cost);
}

TEST(SgStats, JsonMatchesIndependentCountsOnRandomScene)
{
    ScratchDir scratch;
    BuildConfig config;
    config.leaf_size = 3;
    config.resolution_max = 32;
    const fs::path file = write_random_scene(scratch, config);
    const ToolRun run = run_tool(SG_STATS_EXE, {file.string(), "--json"}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const json j = json::parse(run.out);
    EXPECT_EQ(j.at("file").at("path"), file.string());
    EXPECT_EQ(j.at("coverage_checked"), false);
    expect_json_matches_file(j, file);
    EXPECT_EQ(j.at("build_config").at("resolution_max"), 32);
}

TEST(SgStats, JsonMatchesIndependentCountsOnRealModel)
{
    const fs::path model = assimp_model("Collada/duck.dae");
    ASSERT_TRUE(fs::exists(model)) << model << ": install assimp-testmodels";
    ScratchDir scratch;
    SgContents contents;
    contents.mesh = import_mesh(model).mesh;
    contents.grid = build_split_grid(contents.mesh.view(), BuildConfig{});
    contents.source_name = "duck.dae";
    const fs::path file = scratch / "duck.sg";
    write_sg_file(file, contents);

    const ToolRun run = run_tool(SG_STATS_EXE, {file.string(), "--json", "--coverage"}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const json j = json::parse(run.out);
    EXPECT_EQ(j.at("coverage_checked"), true);
    EXPECT_EQ(j.at("source_name"), "duck.dae");
    expect_json_matches_file(j, file);
}

TEST(SgStats, TextReportShowsEveryPart)
{
    ScratchDir scratch;
    const fs::path file = write_random_scene(scratch, BuildConfig{});
    const ToolRun run = run_tool(SG_STATS_EXE, {file.string()}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const SgContents contents = read_sg_file(file);
    const GridStats stats = compute_stats(contents.grid);
    for (const std::string& text :
         {std::string("format version 5"), std::string("random_scene"),
          std::string("resolution per depth"), std::string("mean leaf depth"),
          std::string("duplication factor"), std::string("empty cell fraction"),
          std::string("triangles/leaf"), std::string("bytes/triangle"),
          std::string("expected cost"), std::to_string(stats.node_count) + " nodes",
          std::to_string(stats.reference_count), std::to_string(fs::file_size(file)) + " bytes"})
        EXPECT_NE(run.out.find(text), std::string::npos) << text << " missing in\n" << run.out;
    for (const SgSectionInfo& section : read_sg_info(file).sections)
        EXPECT_NE(run.out.find("section " + section.name), std::string::npos) << section.name;
}

TEST(SgStats, HelpStatesTheCostFormula)
{
    ScratchDir scratch;
    const ToolRun run = run_tool(SG_STATS_EXE, {"--help"}, scratch);
    ASSERT_EQ(run.exit_code, 0);
    EXPECT_NE(run.out.find("SA(X) / SA(root box)"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("STATS_JSON.md"), std::string::npos) << run.out;
}

// --- bad files: exit code 2 and a message naming the file ---

class SgStatsBadFile : public ::testing::Test {
protected:
    void expect_refused(const fs::path& file)
    {
        const ToolRun run = run_tool(SG_STATS_EXE, {file.string(), "--json"}, scratch_);
        EXPECT_EQ(run.exit_code, 2) << describe(run);
        EXPECT_NE(run.err.find(file.filename().string()), std::string::npos) << run.err;
        EXPECT_EQ(run.out, "") << "no partial JSON on stdout";
    }
    std::string good_bytes() { return read_text(write_random_scene(scratch_, BuildConfig{})); }

    ScratchDir scratch_;
};

TEST_F(SgStatsBadFile, Missing) { expect_refused(scratch_ / "missing.sg"); }

TEST_F(SgStatsBadFile, Empty)
{
    write_text(scratch_ / "empty.sg", "");
    expect_refused(scratch_ / "empty.sg");
}

TEST_F(SgStatsBadFile, TextFile)
{
    write_text(scratch_ / "text.sg", "this is a text file, not a Split Grid\n");
    expect_refused(scratch_ / "text.sg");
}

TEST_F(SgStatsBadFile, Truncated)
{
    const std::string bytes = good_bytes();
    for (const std::size_t size : {std::size_t{8}, bytes.size() / 2, bytes.size() - 1}) {
        SCOPED_TRACE(size);
        write_text(scratch_ / "truncated.sg", bytes.substr(0, size));
        expect_refused(scratch_ / "truncated.sg");
    }
}

TEST_F(SgStatsBadFile, FlippedByteInBody)
{
    std::string bytes = good_bytes();
    bytes[bytes.size() * 3 / 4] = static_cast<char>(bytes[bytes.size() * 3 / 4] ^ 0x5A);
    write_text(scratch_ / "flipped.sg", bytes);
    expect_refused(scratch_ / "flipped.sg");
}

}  // namespace
}  // namespace sg::test
