// End-to-end tests of sg-trace --query count and --query all: the files it writes, read back by
// the formats' readers and by the numpy lines of docs/FORMAT.md (/usr/bin/python3), against
// every hit found here by testing every triangle of the mesh (the library's watertight
// intersect_triangle, one call per ray and triangle, sorted here); the same files for 1 and 2
// threads; --any-hit the same as --query any; the two together refused.

#include <algorithm>
#include <bit>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/formats/intersection_file.hpp"
#include "splitgrid/formats/ray_file.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/ray_triangle.hpp"
#include "support/random_scene.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }

/// Every triangle `ray` hits in [t_min, t_max], by testing each, sorted by t then id.
std::vector<Hit> every_hit(const MeshView& mesh, const Ray& ray)
{
    std::vector<Hit> hits;
    if (!is_valid(ray)) return hits;
    const WatertightRay watertight(ray);
    for (std::uint32_t i = 0; i < mesh.triangle_count(); ++i) {
        Hit h;
        if (intersect_triangle(watertight, mesh.vertex(i, 0), mesh.vertex(i, 1),
                               mesh.vertex(i, 2), ray.t_min, ray.t_max, h.t, h.u, h.v)) {
            h.triangle = i;
            hits.push_back(h);
        }
    }
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
        return a.t < b.t || (a.t == b.t && a.triangle < b.triangle);
    });
    return hits;
}

/// The numpy block that follows `heading` in docs/FORMAT.md.
std::string python_block_of_format_md(const std::string& heading)
{
    const std::string doc = read_text(fs::path(SG_SOURCE_DIR) / "docs" / "FORMAT.md");
    const std::size_t at = doc.find(heading);
    if (at == std::string::npos) return {};
    const std::size_t start = doc.find("```python\n", at);
    if (start == std::string::npos) return {};
    const std::size_t end = doc.find("```\n", start + 10);
    return doc.substr(start + 10, end - start - 10);
}

class SgTraceQuery : public ::testing::Test {
protected:
    void SetUp() override
    {
        // Random triangles, two planes of unit quads (rays along their grid lines meet edges
        // and vertices shared by several triangles, at equal t) and a closed sphere (rays
        // through it hit it twice).
        Mesh mesh = random_triangles(3, 1500, Aabb{{0, 0, 0}, {8, 8, 8}}, 1.0f);
        append(mesh, axis_plane(1, 0.0f, 8));
        append(mesh, axis_plane(0, 4.0f, 8));
        append(mesh, uv_sphere({4.0f, 4.0f, 4.0f}, 2.5f, 12, 16));
        BuildConfig config;
        config.leaf_size = 4;
        contents_.grid = build_split_grid(mesh.view(), config);
        contents_.mesh = std::move(mesh);
        contents_.source_name = "random";
        write_sg_file(sg_file_, contents_);

        const MeshView view = contents_.mesh.view();
        const Aabb box{{-2, -2, -2}, {10, 10, 10}};
        rays_ = rays_at_triangles(5, 1200, box, view);
        for (const auto& more : {random_rays(6, 600, box), zero_direction_rays(7, 300, box,
                                                                                contents_.mesh),
                                 axis_rays_through_lattice(8, 300, 8, true)})
            rays_.insert(rays_.end(), more.begin(), more.end());
        std::vector<Ray> windowed(rays_.begin(), rays_.begin() + 300);
        set_random_windows(windowed, 9, 0.0f, 6.0f);
        rays_.insert(rays_.end(), windowed.begin(), windowed.end());
        const std::vector<Ray> invalid = invalid_rays();
        for (std::size_t i = 0; i < invalid.size(); ++i)
            rays_.insert(rays_.begin() + static_cast<std::ptrdiff_t>(1 + 97 * i), invalid[i]);
        write_ray_file(rays_file_, rays_);

        for (const Ray& ray : rays_) expected_.push_back(every_hit(view, ray));
    }

    ToolRun trace(const fs::path& out, std::vector<std::string> extra)
    {
        std::vector<std::string> args = {sg_file_.string(), "--rays", rays_file_.string(), "-o",
                                         out.string()};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_tool(SG_TRACE_EXE, args, scratch_);
    }

    std::size_t total_expected() const
    {
        std::size_t total = 0;
        for (const auto& hits : expected_) total += hits.size();
        return total;
    }
    std::size_t rays_hit_expected() const
    {
        return static_cast<std::size_t>(std::count_if(
            expected_.begin(), expected_.end(), [](const auto& hits) { return !hits.empty(); }));
    }

    ScratchDir scratch_;
    fs::path sg_file_ = scratch_ / "scene.sg";
    fs::path rays_file_ = scratch_ / "rays.bin";
    SgContents contents_;
    std::vector<Ray> rays_;
    std::vector<std::vector<Hit>> expected_;
};

TEST_F(SgTraceQuery, CountsEqualEveryTriangleTested)
{
    const ToolRun one = trace(scratch_ / "c1.bin", {"--query", "count", "--threads", "1"});
    ASSERT_EQ(one.exit_code, 0) << describe(one);
    const ToolRun two = trace(scratch_ / "c2.bin", {"--query", "count", "--threads", "2",
                                                    "--json"});
    ASSERT_EQ(two.exit_code, 0) << describe(two);
    EXPECT_EQ(read_text(scratch_ / "c1.bin"), read_text(scratch_ / "c2.bin"))
        << "the count file must not depend on the thread count";

    const std::vector<std::int32_t> counts = read_hit_count_file(scratch_ / "c1.bin");
    ASSERT_EQ(counts.size(), rays_.size());
    std::size_t wrong = 0;
    for (std::size_t k = 0; k < rays_.size(); ++k)
        if (counts[k] != static_cast<std::int32_t>(expected_[k].size()) && ++wrong <= 5)
            ADD_FAILURE() << "ray " << k << ": " << counts[k] << " hits, expected "
                          << expected_[k].size();
    EXPECT_EQ(wrong, 0u);
    // Premise: rays that cross several triangles, and rays that cross none.
    EXPECT_GT(total_expected(), 2 * rays_hit_expected());
    EXPECT_LT(rays_hit_expected(), rays_.size());

    const json j = json::parse(two.out);
    EXPECT_EQ(j.at("query"), "count");
    EXPECT_EQ(j.at("ray_count"), rays_.size());
    EXPECT_EQ(j.at("hit_count"), rays_hit_expected());
    EXPECT_EQ(j.at("total_hits"), total_expected());
    EXPECT_EQ(j.at("invalid_rays"), invalid_rays().size());
    EXPECT_EQ(j.at("threads"), 2);
    EXPECT_GT(j.at("rays_per_second").get<double>(), 0.0);

    EXPECT_NE(one.out.find(std::to_string(rays_hit_expected()) + " rays hit"), std::string::npos)
        << one.out;
    EXPECT_NE(one.out.find(std::to_string(total_expected()) + " hits in all"), std::string::npos)
        << one.out;
    EXPECT_NE(one.out.find("(hit count)"), std::string::npos) << one.out;
    EXPECT_NE(one.err.find("invalid (NaN"), std::string::npos) << one.err;
}

TEST_F(SgTraceQuery, ListsEqualEveryTriangleTested)
{
    const ToolRun one = trace(scratch_ / "a1.bin", {"--query", "all", "--threads", "1", "--json"});
    ASSERT_EQ(one.exit_code, 0) << describe(one);
    const ToolRun two = trace(scratch_ / "a2.bin", {"--query", "all", "--threads", "2"});
    ASSERT_EQ(two.exit_code, 0) << describe(two);
    EXPECT_EQ(read_text(scratch_ / "a1.bin"), read_text(scratch_ / "a2.bin"))
        << "the hit list file must not depend on the thread count";

    const IntersectionList list = read_hit_list_file(scratch_ / "a1.bin");
    ASSERT_EQ(list.ray_count(), rays_.size());
    std::size_t wrong = 0;
    for (std::size_t k = 0; k < rays_.size(); ++k) {
        const std::size_t first = list.ray_splits[k], last = list.ray_splits[k + 1];
        const std::vector<Hit>& expected = expected_[k];
        bool same = last - first == expected.size();
        for (std::size_t i = 0; same && i < expected.size(); ++i) {
            const Hit& got = list.hits[first + i];
            same = list.ray_ids[first + i] == k && got.triangle == expected[i].triangle &&
                   bits(got.t) == bits(expected[i].t) && bits(got.u) == bits(expected[i].u) &&
                   bits(got.v) == bits(expected[i].v);
        }
        if (!same && ++wrong <= 5) {
            std::ostringstream s;
            s << "ray " << k << ": got";
            for (std::size_t i = first; i < last; ++i)
                s << " " << list.hits[i].triangle << "@" << list.hits[i].t;
            s << "; expected";
            for (const Hit& h : expected) s << " " << h.triangle << "@" << h.t;
            ADD_FAILURE() << s.str();
        }
    }
    EXPECT_EQ(wrong, 0u);

    const json j = json::parse(one.out);
    EXPECT_EQ(j.at("query"), "all");
    EXPECT_EQ(j.at("hit_count"), rays_hit_expected());
    EXPECT_EQ(j.at("total_hits"), total_expected());
    EXPECT_EQ(j.at("hits_file"), (scratch_ / "a1.bin").string());
}

TEST_F(SgTraceQuery, NumpyLinesOfFormatMdReadBothFiles)
{
    // python3-numpy comes with python3-matplotlib, which scripts/setup.sh installs.
    const std::string code =
        python_block_of_format_md("Reading hit count and hit list files with numpy");
    ASSERT_FALSE(code.empty()) << "docs/FORMAT.md lost its numpy block";
    ASSERT_EQ(trace(scratch_ / "c.bin", {"--query", "count"}).exit_code, 0);
    ASSERT_EQ(trace(scratch_ / "a.bin", {"--query", "all"}).exit_code, 0);

    // The block, then lines that print what it read, one line per ray, floats as their bits.
    const fs::path script = scratch_ / "read_hits.py";
    write_text(script, code + R"(
t, u, v = (hits[name].copy().view('<u4') for name in ('t', 'u', 'v'))
for k in range(n_rays):
    print('ray', k, counts[k], ' '.join(
        f"{hits['ray'][i]}:{hits['tri'][i]}:{t[i]}:{u[i]}:{v[i]}"
        for i in range(splits[k], splits[k + 1])))
)");
    const ToolRun python = run_tool(
        "/usr/bin/python3", {script.string(), (scratch_ / "c.bin").string(),
                             (scratch_ / "a.bin").string()},
        scratch_);
    ASSERT_EQ(python.exit_code, 0) << describe(python);

    std::istringstream out(python.out);
    std::string line;
    std::getline(out, line);
    EXPECT_EQ(line, std::to_string(rays_.size()) + " rays, " + std::to_string(total_expected()) +
                        " hits, at most " +
                        std::to_string(std::max_element(expected_.begin(), expected_.end(),
                                                        [](const auto& a, const auto& b) {
                                                            return a.size() < b.size();
                                                        })->size()) +
                        " along one ray");
    std::size_t wrong = 0, lines = 0;
    for (std::size_t k = 0; std::getline(out, line); ++k, ++lines) {
        std::ostringstream expected;
        expected << "ray " << k << " " << expected_[k].size() << " ";
        for (std::size_t i = 0; i < expected_[k].size(); ++i) {
            const Hit& h = expected_[k][i];
            expected << (i == 0 ? "" : " ") << k << ":" << h.triangle << ":" << bits(h.t) << ":"
                     << bits(h.u) << ":" << bits(h.v);
        }
        if (line != expected.str() && ++wrong <= 3)
            ADD_FAILURE() << "numpy read\n  " << line << "\nexpected\n  " << expected.str();
    }
    EXPECT_EQ(lines, rays_.size());
    EXPECT_EQ(wrong, 0u);
}

TEST_F(SgTraceQuery, AnyHitFlagIsQueryAnyAndNotTogether)
{
    const ToolRun flag = trace(scratch_ / "flag.bin", {"--any-hit"});
    ASSERT_EQ(flag.exit_code, 0) << describe(flag);
    const ToolRun query = trace(scratch_ / "query.bin", {"--query", "any", "--json"});
    ASSERT_EQ(query.exit_code, 0) << describe(query);
    EXPECT_EQ(read_text(scratch_ / "flag.bin"), read_text(scratch_ / "query.bin"));
    // And both are what every triangle tested says: occluded exactly when some hit exists.
    const std::vector<Hit> any = read_hit_file(scratch_ / "query.bin");
    ASSERT_EQ(any.size(), rays_.size());
    for (std::size_t k = 0; k < rays_.size(); ++k)
        EXPECT_EQ(any[k].triangle, expected_[k].empty() ? invalid_triangle : 0u) << k;
    EXPECT_EQ(json::parse(query.out).at("query"), "any");
    EXPECT_EQ(json::parse(query.out).at("mode"), "any_hit");

    // The closest hit is the first of the list.
    const ToolRun closest = trace(scratch_ / "closest.bin", {"--query", "closest"});
    ASSERT_EQ(closest.exit_code, 0) << describe(closest);
    const ToolRun plain = trace(scratch_ / "plain.bin", {});
    ASSERT_EQ(plain.exit_code, 0) << describe(plain);
    EXPECT_EQ(read_text(scratch_ / "closest.bin"), read_text(scratch_ / "plain.bin"));
    const std::vector<Hit> hits = read_hit_file(scratch_ / "closest.bin");
    for (std::size_t k = 0; k < rays_.size(); ++k) {
        if (expected_[k].empty()) {
            EXPECT_FALSE(hits[k].is_hit()) << k;
            continue;
        }
        EXPECT_EQ(hits[k].triangle, expected_[k].front().triangle) << k;
        EXPECT_EQ(bits(hits[k].t), bits(expected_[k].front().t)) << k;
    }

    const fs::path both_out = scratch_ / "both.bin";
    const ToolRun both = trace(both_out, {"--any-hit", "--query", "count"});
    EXPECT_EQ(both.exit_code, 1) << describe(both);
    EXPECT_NE(both.err.find("--any-hit"), std::string::npos) << both.err;
    EXPECT_NE(both.err.find("--query"), std::string::npos) << both.err;
    EXPECT_EQ(std::count(both.err.begin(), both.err.end(), '\n'), 1) << both.err;
    EXPECT_FALSE(fs::exists(both_out));

    const ToolRun unknown = trace(both_out, {"--query", "nearest"});
    EXPECT_EQ(unknown.exit_code, 1) << describe(unknown);
    EXPECT_NE(unknown.err.find("nearest"), std::string::npos) << unknown.err;
    EXPECT_FALSE(fs::exists(both_out));
}

TEST_F(SgTraceQuery, StrictRefusesInvalidRaysForEveryQueryAndWritesNothing)
{
    for (const char* query : {"count", "all"}) {
        const fs::path out = scratch_ / (std::string(query) + ".bin");
        const ToolRun run = trace(out, {"--query", query, "--strict"});
        EXPECT_EQ(run.exit_code, 2) << describe(run);
        EXPECT_NE(run.err.find("refused by --strict"), std::string::npos) << run.err;
        EXPECT_FALSE(fs::exists(out));
        for (const auto& entry : fs::directory_iterator(scratch_.path()))
            EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos)
                << "temporary file left behind: " << entry.path();
    }
}

TEST(SgTraceQueryHelp, ExplainsEveryQuery)
{
    ScratchDir scratch;
    const ToolRun run = run_tool(SG_TRACE_EXE, {"--help"}, scratch);
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    for (const char* text : {"--query", "closest", "any", "count", "all", "SGCNT001", "SGALL001",
                             "ray_splits", "--any-hit", "Default closest."})
        EXPECT_NE(run.out.find(text), std::string::npos) << text;
}

}  // namespace
}  // namespace sg::test
