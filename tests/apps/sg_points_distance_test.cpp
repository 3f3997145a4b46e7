// End-to-end tests of sg-points --query distance, signed-distance and closest: a closed mesh of
// a sphere and a tessellated cube built by sg-build, points of every kind around it (on
// vertices, edges and faces, inside, outside, far away, non-finite), the result files read
// back and every answer held to the brute-force oracle in double; --max-distance; the JSON
// and the summary; the refusals of flags that do not apply (exit code 1, nothing written).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "sg_points_support.hpp"
#include "splitgrid/formats/point_file.hpp"
#include "splitgrid/formats/sg_file.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr float inf = std::numeric_limits<float>::infinity();
constexpr float nan = std::numeric_limits<float>::quiet_NaN();

class SgPointsDistance : public ::testing::Test {
protected:
    void SetUp() override
    {
        build_with_sg_build(sphere_and_cube(), sg_file_, scratch_);
        // The oracle runs on the mesh as the .sg file holds it (sg-build may renumber
        // triangles), read by the formats library, not by the tool under test.
        contents_ = read_sg_file(sg_file_);
        points_ = points_around_sphere_and_cube();
        points_.insert(points_.begin() + 3, Vec3f{nan, 0.0f, 0.0f});
        write_point_file(points_file_, points_);
        for (const Vec3f p : points_)
            oracle_.push_back(is_finite(p) ? point_oracle(contents_.mesh.view(), p)
                                           : PointOracle{});
    }

    ToolRun points(const std::string& query, std::vector<std::string> extra)
    {
        std::vector<std::string> args =
            {sg_file_.string(), "--points", points_file_.string(), "-o", out_.string(),
             "--query",         query};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_tool(SG_POINTS_EXE, args, scratch_);
    }

    void expect_refused(const ToolRun& run, int code, const std::string& named)
    {
        expect_refused_leaving_nothing(run, code, named, out_, scratch_.path());
    }

    ScratchDir scratch_;
    fs::path sg_file_ = scratch_ / "shapes.sg";
    fs::path points_file_ = scratch_ / "points.bin";
    fs::path out_ = scratch_ / "answers.bin";
    SgContents contents_;
    std::vector<Vec3f> points_;
    std::vector<PointOracle> oracle_;
};

TEST_F(SgPointsDistance, DistancesAgreeWithTheOracle)
{
    // Premise: points on the surface, inside and outside, and ties between triangles.
    const auto on_surface = std::count_if(oracle_.begin(), oracle_.end(),
                                          [](const PointOracle& o) { return o.distance == 0.0; });
    const auto tied = std::count_if(oracle_.begin(), oracle_.end(),
                                    [](const PointOracle& o) { return o.nearest.size() > 1; });
    ASSERT_GT(on_surface, 100);
    ASSERT_GT(tied, 300);

    std::string first_bytes;
    for (const char* threads : {"1", "2"}) {
        const ToolRun run = points("distance", {"--threads", threads, "--json"});
        ASSERT_EQ(run.exit_code, 0) << describe(run);
        const std::vector<float> got = read_distance_file(out_);
        ASSERT_EQ(got.size(), points_.size());
        double worst = 0.0;
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < points_.size(); ++i) {
            if (!is_finite(points_[i])) {
                EXPECT_TRUE(std::isnan(got[i])) << i;
                continue;
            }
            const double error = std::abs(got[i] - oracle_[i].distance);
            worst = std::max(worst, error / distance_tolerance(oracle_[i].distance, points_[i]));
            if (error > distance_tolerance(oracle_[i].distance, points_[i]) && ++wrong <= 5)
                ADD_FAILURE() << "point " << i << ": " << got[i] << ", oracle "
                              << oracle_[i].distance;
        }
        EXPECT_EQ(wrong, 0u);
        EXPECT_LE(worst, 1.0) << "worst error in units of the tolerance";
        if (first_bytes.empty())
            first_bytes = read_text(out_);
        else
            EXPECT_EQ(read_text(out_), first_bytes) << "the file depends on --threads";

        const json j = json::parse(run.out);
        EXPECT_EQ(j.at("query"), "distance");
        EXPECT_FALSE(j.contains("nsamples")) << "distance casts no rays";
        EXPECT_FALSE(j.contains("edges"));
        EXPECT_TRUE(j.at("max_distance").is_null());
        EXPECT_EQ(j.at("point_count"), points_.size());
        EXPECT_EQ(j.at("nonfinite_points"), 1);
        EXPECT_EQ(j.at("beyond_max_distance"), 0);
        EXPECT_EQ(j.at("answer_min"), 0.0);
        EXPECT_NEAR(j.at("answer_max").get<double>(), 1e4 - 1.0, 1e-3);
        EXPECT_EQ(j.at("threads"), std::stoi(threads));
        expect_documented_points_json(j);
    }
}

TEST_F(SgPointsDistance, SignedDistancesHaveTheOraclesDistanceAndSide)
{
    const ToolRun run = points("signed-distance", {"--nsamples", "3", "--json"});
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const std::vector<float> got = read_signed_distance_file(out_);
    ASSERT_EQ(got.size(), points_.size());
    std::size_t inside = 0, outside = 0, sides_checked = 0;
    for (std::size_t i = 0; i < points_.size(); ++i) {
        if (!is_finite(points_[i])) {
            EXPECT_TRUE(std::isnan(got[i])) << i;
            continue;
        }
        const PointOracle& o = oracle_[i];
        EXPECT_LE(std::abs(std::abs(got[i]) - o.distance),
                  distance_tolerance(o.distance, points_[i]))
            << "point " << i << ": " << got[i] << ", oracle " << o.distance;
        (got[i] < 0.0f ? inside : outside) += 1;
        if (o.distance <= side_band) continue;
        ++sides_checked;
        EXPECT_EQ(got[i] < 0.0f, o.inside)
            << "point " << i << " (" << points_[i].x << ", " << points_[i].y << ", " << points_[i].z
            << "): " << got[i];
    }
    ASSERT_GT(sides_checked, 1500u);
    const json j = json::parse(run.out);
    EXPECT_EQ(j.at("query"), "signed-distance");
    EXPECT_EQ(j.at("nsamples"), 3);
    EXPECT_EQ(j.at("inside"), inside);
    EXPECT_EQ(j.at("outside"), outside);
    EXPECT_EQ(j.at("edges").at("closed"), true);
    EXPECT_LT(j.at("answer_min").get<double>(), -0.9) << "the sphere's centre is inside";
    expect_documented_points_json(j);
}

TEST_F(SgPointsDistance, ClosestPointsLieOnANearestTriangle)
{
    const ToolRun run = points("closest", {});
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    EXPECT_EQ(run.err.rfind("warning: " + points_file_.string() + ": 1 of " +
                                std::to_string(points_.size()) + " points are invalid",
                            0),
              0u)
        << run.err;
    const std::vector<ClosestPoint> got = read_closest_point_file(out_);
    ASSERT_EQ(got.size(), points_.size());
    const MeshView mesh = contents_.mesh.view();
    double worst_point = 0.0;
    for (std::size_t i = 0; i < points_.size(); ++i) {
        const Vec3f p = points_[i];
        if (!is_finite(p)) {
            EXPECT_FALSE(got[i].is_hit());
            EXPECT_TRUE(std::isnan(got[i].distance));
            continue;
        }
        const PointOracle& o = oracle_[i];
        ASSERT_TRUE(got[i].is_hit()) << i;
        EXPECT_TRUE(std::binary_search(o.nearest.begin(), o.nearest.end(), got[i].triangle))
            << "point " << i << ": triangle " << got[i].triangle << " is not among the nearest";
        EXPECT_LE(std::abs(got[i].distance - o.distance), distance_tolerance(o.distance, p)) << i;
        // The point is the closest point of its triangle, and its barycentrics say so.
        const std::uint32_t t = got[i].triangle;
        const auto corner = [&](int k) {
            const Vec3f v = mesh.vertex(t, k);
            return std::array<double, 3>{v.x, v.y, v.z};
        };
        const std::array<double, 3> expected =
            closest_point_on_triangle({p.x, p.y, p.z}, corner(0), corner(1), corner(2));
        for (int a = 0; a < 3; ++a) {
            const auto k = static_cast<std::size_t>(a);
            const double from_uv = (1.0 - got[i].u - got[i].v) * corner(0)[k] +
                                   got[i].u * corner(1)[k] + got[i].v * corner(2)[k];
            worst_point = std::max(worst_point, std::abs(got[i].point[a] - expected[k]));
            EXPECT_NEAR(got[i].point[a], expected[k], 1e-6) << "point " << i << " axis " << a;
            EXPECT_NEAR(from_uv, expected[k], 1e-6) << "point " << i << " axis " << a;
        }
    }
    EXPECT_LT(worst_point, 1e-6);
}

TEST_F(SgPointsDistance, MaxDistanceAnswersFartherPointsInfinity)
{
    const float limit = 0.3f;
    std::size_t beyond = 0;
    for (std::size_t i = 0; i < points_.size(); ++i)
        beyond += is_finite(points_[i]) && oracle_[i].distance > limit ? 1 : 0;
    ASSERT_GT(beyond, 300u);

    for (const char* query : {"distance", "signed-distance", "closest"}) {
        SCOPED_TRACE(query);
        const ToolRun run = points(query, {"--max-distance", "0.3", "--json"});
        ASSERT_EQ(run.exit_code, 0) << describe(run);
        const json j = json::parse(run.out);
        EXPECT_EQ(j.at("max_distance"), 0.3f);
        EXPECT_EQ(j.at("beyond_max_distance"), beyond);
        EXPECT_LE(j.at("answer_max").get<double>(), limit);
        expect_documented_points_json(j);
        std::vector<float> distances;
        if (std::string(query) == "closest") {
            for (const ClosestPoint& c : read_closest_point_file(out_)) {
                distances.push_back(c.distance);
                EXPECT_EQ(c.is_hit(), std::isfinite(c.distance));
                if (!c.is_hit()) {
                    EXPECT_TRUE(std::isnan(c.point.x));
                }
            }
        } else {
            distances = std::string(query) == "distance" ? read_distance_file(out_)
                                                         : read_signed_distance_file(out_);
        }
        ASSERT_EQ(distances.size(), points_.size());
        for (std::size_t i = 0; i < points_.size(); ++i) {
            if (!is_finite(points_[i])) continue;
            const double d = oracle_[i].distance;
            if (d > limit * (1 + 1e-6)) {
                EXPECT_EQ(distances[i], inf) << i;
            } else if (d < limit * (1 - 1e-6)) {
                EXPECT_LE(std::abs(std::abs(distances[i]) - d), distance_tolerance(d, points_[i]))
                    << i;
            }
        }
    }

    const ToolRun summary = points("distance", {"--max-distance", "0.3"});
    ASSERT_EQ(summary.exit_code, 0) << describe(summary);
    EXPECT_NE(summary.out.find(std::to_string(beyond) +
                               " beyond --max-distance 0.3, 1 "
                               "non-finite, written to " +
                               out_.string()),
              std::string::npos)
        << summary.out;
}

TEST_F(SgPointsDistance, FlagsThatDoNotApplyAreRefused)
{
    expect_refused(points("distance", {"--max-distance", "0"}), 1, "--max-distance");
    expect_refused(points("distance", {"--max-distance", "-1"}), 1, "--max-distance");
    expect_refused(points("distance", {"--max-distance", "nan"}), 1, "--max-distance");
    expect_refused(points("distance", {"--max-distance", "1e-50"}), 1,
                   "--max-distance 1e-50 is 0 in float32");
    expect_refused(points("occupancy", {"--max-distance", "1"}), 1,
                   "--max-distance 1 applies to --query distance, signed-distance and closest, "
                   "not to --query occupancy");
    expect_refused(points("closest", {"--nsamples", "3"}), 1,
                   "--nsamples 3 applies to --query occupancy and signed-distance");
    expect_refused(points("signed-distance", {"--nsamples", "2"}), 1, "--nsamples 2 is even");
    expect_refused(points("distance", {"--padding", "0.1"}), 1,
                   "--padding 0.1 applies to "
                   "--grid only");
    const ToolRun none =
        run_tool(SG_POINTS_EXE, {sg_file_.string(), "-o", out_.string(), "--query", "distance"},
                 scratch_);
    expect_refused(none, 1, "give the points to query: --points FILE, or --grid NX,NY,NZ");

    // An output over an input is refused (exit code 2) and the input kept.
    const std::string bytes = read_text(points_file_);
    const ToolRun over = run_tool(SG_POINTS_EXE,
                                  {sg_file_.string(), "--points", points_file_.string(), "-o",
                                   points_file_.string(), "--query", "closest"},
                                  scratch_);
    EXPECT_EQ(over.exit_code, 2) << describe(over);
    EXPECT_NE(over.err.find("refusing to write the output over the input"), std::string::npos);
    EXPECT_EQ(read_text(points_file_), bytes);

    const ToolRun strict = points("signed-distance", {"--strict"});
    expect_refused(strict, 2, "refused by --strict");
}

TEST_F(SgPointsDistance, NumpyLinesOfFormatMdReadDistanceAndClosestPointFiles)
{
    const std::string doc = read_text(fs::path(SG_SOURCE_DIR) / "docs" / "FORMAT.md");
    const std::size_t heading = doc.find("Reading distance and closest point files with numpy");
    ASSERT_NE(heading, std::string::npos) << "docs/FORMAT.md lost its numpy block";
    const std::size_t start = doc.find("```python\n", heading) + 10;
    const fs::path script = scratch_ / "distances.py";
    write_text(script, doc.substr(start, doc.find("```\n", start) - start));

    const fs::path closest = scratch_ / "closest.bin";
    const fs::path sdf = scratch_ / "sdf.bin";
    ASSERT_EQ(run_tool(SG_POINTS_EXE,
                       {sg_file_.string(), "--points", points_file_.string(), "-o",
                        closest.string(), "--query", "closest"},
                       scratch_)
                  .exit_code,
              0);
    ASSERT_EQ(run_tool(SG_POINTS_EXE,
                       {sg_file_.string(), "--points", points_file_.string(), "-o", sdf.string(),
                        "--query", "signed-distance"},
                       scratch_)
                  .exit_code,
              0);
    const ToolRun python =
        run_tool("/usr/bin/python3",
                 {script.string(), points_file_.string(), closest.string(), sdf.string()},
                 scratch_);
    ASSERT_EQ(python.exit_code, 0) << describe(python);
    const std::vector<float> signed_distances = read_signed_distance_file(sdf);
    const auto inside = std::count_if(signed_distances.begin(), signed_distances.end(),
                                      [](float d) { return d < 0.0f; });
    const std::string expected = std::to_string(points_.size() - 1) + " of " +
                                 std::to_string(points_.size()) + " answered, " +
                                 std::to_string(inside) + " inside, largest gap ";
    ASSERT_EQ(python.out.rfind(expected, 0), 0u) << python.out;
    // The gap between a distance and the length to its point is rounding (the far points'
    // distances are near 1e4, whose float32 ulp is 1e-3).
    EXPECT_LE(std::stod(python.out.substr(expected.size())), 2e-3) << python.out;
}

}  // namespace
}  // namespace sg::test
