// Tests of formats/src/point_file.cpp and point_text.cpp: point, occupancy, distance, signed
// distance and closest point files round trip with every bit, their bytes at the literal offsets of docs/FORMAT.md, text points line by
// line, the choice between a point file and text, and every refusal naming the file (and the
// line).

#include "splitgrid/formats/point_file.hpp"
#include "splitgrid/formats/point_text.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "file_helpers.hpp"
#include "splitgrid/error.hpp"

namespace sg {
namespace {

using test::error_of;
using test::load_le;
using test::store_le;

constexpr float inf = std::numeric_limits<float>::infinity();
constexpr float nan = std::numeric_limits<float>::quiet_NaN();

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }

std::vector<Vec3f> some_points()
{
    return {{1.5f, -2.0f, 3.25f}, {0.0f, -0.0f, 1e-30f}, {nan, 1.0f, 2.0f}, {inf, -inf, 7.0f}};
}

void expect_same_points(const std::vector<Vec3f>& expected, const std::vector<Vec3f>& actual)
{
    ASSERT_EQ(actual.size(), expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i)
        for (int a = 0; a < 3; ++a)
            EXPECT_EQ(bits(actual[i][a]), bits(expected[i][a])) << "point " << i << " axis " << a;
}

TEST(PointFile, RoundTripKeepsEveryBitAndMatchesTheLayout)
{
    test::ScratchDir dir;
    const std::vector<Vec3f> points = some_points();
    write_point_file(dir / "p.bin", points);
    const std::vector<std::uint8_t> f = test::read_bytes(dir / "p.bin");
    ASSERT_EQ(f.size(), 16u + 12u * points.size());
    EXPECT_EQ(std::string(f.begin(), f.begin() + 8), "SGPTS001");
    EXPECT_EQ(load_le<std::uint64_t>(f, 8), points.size());
    EXPECT_EQ(load_le<float>(f, 16), 1.5f);
    EXPECT_EQ(load_le<float>(f, 20), -2.0f);
    EXPECT_EQ(load_le<float>(f, 24), 3.25f);
    EXPECT_EQ(load_le<float>(f, 16 + 12 * 3 + 4), -inf);
    expect_same_points(points, read_point_file(dir / "p.bin"));

    const LoadedPoints loaded = read_points(dir / "p.bin");
    EXPECT_EQ(loaded.source, PointSource::binary);
    expect_same_points(points, loaded.points);
}

TEST(PointFile, MalformedFilesAreRefusedNamingTheFile)
{
    test::ScratchDir dir;
    write_point_file(dir / "ok.bin", some_points());
    const std::vector<std::uint8_t> ok = test::read_bytes(dir / "ok.bin");
    const auto path = dir / "bad.bin";

    // Every truncation, through read_point_file and through read_points, which takes a file
    // that starts like a point file for one (from one byte on: "S").
    for (std::size_t size = 1; size < ok.size(); ++size) {
        SCOPED_TRACE(size);
        test::write_bytes(path, test::prefix_of(ok, size));
        for (const std::string& m :
             {error_of<FormatError>([&] { (void)read_point_file(path); }),
              error_of<FormatError>([&] { (void)read_points(path); })}) {
            EXPECT_EQ(m.rfind(path.string() + ": ", 0), 0u) << m;
            if (size >= 8) {
                EXPECT_NE(m.find("truncated"), std::string::npos) << m;
            }
        }
    }

    std::vector<std::uint8_t> bad = ok;
    bad[7] = '2';
    test::write_bytes(path, bad);
    EXPECT_EQ(error_of<FormatError>([&] { (void)read_point_file(path); }),
              path.string() + ": not a point file: bad magic (at byte offset 0, expected "
                              "\"SGPTS001\")");
    EXPECT_EQ(error_of<FormatError>([&] { (void)read_points(path); }),
              path.string() + ": not a point file: bad magic (at byte offset 0, expected "
                              "\"SGPTS001\")")
        << "SGPTS starts a point file, whatever its version";

    bad = ok;
    store_le<std::uint64_t>(bad, 8, 5);
    test::write_bytes(path, bad);
    EXPECT_EQ(error_of<FormatError>([&] { (void)read_points(path); }),
              path.string() + ": truncated: the header counts 5 points, the file size fits 4 (at "
                              "byte offset 8, expected 16 + 5 x 12 bytes, found 64 bytes)");

    EXPECT_EQ(error_of<IoError>([&] { (void)read_points(dir / "none.bin"); }),
              (dir / "none.bin").string() + ": cannot open: No such file or directory");
}

TEST(PointFile, ReadPointsTellsTextFromBinaryByTheContent)
{
    test::ScratchDir dir;
    test::write_text(dir / "p.csv", "x,y,z\n# a comment\n1,2,3\n\n-0.5 4e2\t+7\r\nnan,inf,-inf\n");
    const LoadedPoints loaded = read_points(dir / "p.csv");
    EXPECT_EQ(loaded.source, PointSource::text);
    expect_same_points({{1, 2, 3}, {-0.5f, 400.0f, 7.0f}, {nan, inf, -inf}}, loaded.points);
    expect_same_points(loaded.points, read_point_text(dir / "p.csv"));

    // A ray file, a .sg file or anything else binary is neither.
    test::write_bytes(dir / "r.bin", {'S', 'G', 'R', 'A', 'Y', '0', '0', '1', 1, 0, 0, 0});
    EXPECT_EQ(error_of<FormatError>([&] { (void)read_points(dir / "r.bin"); }),
              (dir / "r.bin").string() + ": neither a point file (magic \"SGPTS001\") nor text: "
                                         "byte 0x01 at byte offset 8");
    test::write_bytes(dir / "s.sg", {0x89, 'S', 'G', 'F', '\r', '\n', 0x1A, '\n'});
    EXPECT_NE(error_of<FormatError>([&] { (void)read_points(dir / "s.sg"); })
                  .find("neither a point file"),
              std::string::npos);
    test::write_text(dir / "empty.csv", "");
    EXPECT_EQ(error_of<FormatError>([&] { (void)read_points(dir / "empty.csv"); }),
              (dir / "empty.csv").string() +
                  ": no points (every line is blank, a comment or a header)");
}

TEST(PointText, RefusalsNameLineAndField)
{
    const auto refusal = [](const std::string& text) {
        return error_of<FormatError>([&] { (void)parse_point_text(text, "pts.csv"); });
    };
    EXPECT_EQ(refusal("x,y,z\n1,2,3\n4,x,6\n"), "pts.csv:3: field 2 'x' is not a number");
    EXPECT_EQ(refusal("1 2 3 4\n"), "pts.csv:1: 4 fields, expected 3 (x y z)");
    EXPECT_EQ(refusal("1 2\n"), "pts.csv:1: 2 fields, expected 3 (x y z)");
    EXPECT_EQ(refusal("1,,3\n"), "pts.csv:1: field 2 is empty");
    EXPECT_EQ(refusal("1,2,1e39\n"), "pts.csv:1: field 3 '1e39' is outside the float32 range");
    EXPECT_EQ(refusal("# only\n\n"),
              "pts.csv: no points (every line is blank, a comment or a header)");
    EXPECT_EQ(refusal("1,2,3\nx,y,z\n"), "pts.csv:2: field 1 'x' is not a number")
        << "only the first line may be a header";
}

TEST(OccupancyFile, RoundTripAndLayout)
{
    test::ScratchDir dir;
    const std::vector<float> values{1.0f, 0.0f, nan, 1.0f};
    write_occupancy_file(dir / "o.bin", values);
    const std::vector<std::uint8_t> f = test::read_bytes(dir / "o.bin");
    ASSERT_EQ(f.size(), 16u + 4u * values.size());
    EXPECT_EQ(std::string(f.begin(), f.begin() + 8), "SGOCC001");
    EXPECT_EQ(load_le<std::uint64_t>(f, 8), values.size());
    EXPECT_EQ(load_le<float>(f, 16), 1.0f);
    EXPECT_EQ(load_le<float>(f, 20), 0.0f);
    EXPECT_TRUE(std::isnan(load_le<float>(f, 24)));
    const std::vector<float> read = read_occupancy_file(dir / "o.bin");
    ASSERT_EQ(read.size(), values.size());
    for (std::size_t i = 0; i < values.size(); ++i) EXPECT_EQ(bits(read[i]), bits(values[i])) << i;
}

TEST(OccupancyFile, MalformedFilesAreRefusedNamingTheFile)
{
    test::ScratchDir dir;
    write_occupancy_file(dir / "ok.bin", std::vector<float>{1.0f, 0.0f});
    const std::vector<std::uint8_t> ok = test::read_bytes(dir / "ok.bin");
    const auto path = dir / "bad.bin";
    const auto read = [&] { (void)read_occupancy_file(path); };

    std::vector<std::uint8_t> bad = ok;
    store_le<float>(bad, 20, 0.5f);
    test::write_bytes(path, bad);
    EXPECT_EQ(error_of<FormatError>(read),
              path.string() + ": point 1 has occupancy 0.500000, expected 0, 1 or NaN (at byte "
                              "offset 20)");

    test::write_bytes(path, std::vector<std::uint8_t>(ok.begin(), ok.end() - 1));
    EXPECT_NE(error_of<FormatError>(read).find("truncated"), std::string::npos);

    // A point file is not an occupancy file.
    write_point_file(dir / "p.bin", std::vector<Vec3f>{{0, 0, 0}});
    EXPECT_NE(error_of<FormatError>([&] { (void)read_occupancy_file(dir / "p.bin"); })
                  .find("not an occupancy file"),
              std::string::npos);
}

TEST(DistanceFiles, RoundTripAndLayout)
{
    test::ScratchDir dir;
    const std::vector<float> distances{0.0f, 2.5f, inf, nan, 1e-30f};
    write_distance_file(dir / "d.bin", distances);
    std::vector<std::uint8_t> f = test::read_bytes(dir / "d.bin");
    ASSERT_EQ(f.size(), 16u + 4u * distances.size());
    EXPECT_EQ(std::string(f.begin(), f.begin() + 8), "SGDST001");
    EXPECT_EQ(load_le<std::uint64_t>(f, 8), distances.size());
    EXPECT_EQ(load_le<float>(f, 20), 2.5f);
    EXPECT_EQ(load_le<float>(f, 24), inf);
    std::vector<float> read = read_distance_file(dir / "d.bin");
    ASSERT_EQ(read.size(), distances.size());
    for (std::size_t i = 0; i < read.size(); ++i) EXPECT_EQ(bits(read[i]), bits(distances[i])) << i;

    const std::vector<float> signed_distances{-1.5f, 0.0f, 3.0f, inf, nan};
    write_signed_distance_file(dir / "s.bin", signed_distances);
    f = test::read_bytes(dir / "s.bin");
    ASSERT_EQ(f.size(), 16u + 4u * signed_distances.size());
    EXPECT_EQ(std::string(f.begin(), f.begin() + 8), "SGSDF001");
    EXPECT_EQ(load_le<std::uint64_t>(f, 8), signed_distances.size());
    EXPECT_EQ(load_le<float>(f, 16), -1.5f);
    read = read_signed_distance_file(dir / "s.bin");
    ASSERT_EQ(read.size(), signed_distances.size());
    for (std::size_t i = 0; i < read.size(); ++i)
        EXPECT_EQ(bits(read[i]), bits(signed_distances[i])) << i;
}

TEST(DistanceFiles, ValuesNoQueryGivesAndOtherKindsAreRefused)
{
    test::ScratchDir dir;
    const auto path = dir / "bad.bin";
    write_distance_file(path, std::vector<float>{1.0f, -0.5f});
    EXPECT_EQ(error_of<FormatError>([&] { (void)read_distance_file(path); }),
              path.string() + ": point 1 has distance -0.500000, expected a distance >= 0, "
                              "+infinity or NaN (at byte offset 20)");
    write_signed_distance_file(path, std::vector<float>{-1.0f, -inf});
    EXPECT_EQ(error_of<FormatError>([&] { (void)read_signed_distance_file(path); }),
              path.string() + ": point 1 has signed distance -inf, expected a finite value, "
                              "+infinity or NaN (at byte offset 20)");

    // Each kind has its magic: a signed distance is never read as a distance, nor an
    // occupancy as either.
    write_signed_distance_file(dir / "s.bin", std::vector<float>{1.0f});
    write_occupancy_file(dir / "o.bin", std::vector<float>{1.0f});
    write_distance_file(dir / "d.bin", std::vector<float>{1.0f});
    EXPECT_NE(error_of<FormatError>([&] { (void)read_distance_file(dir / "s.bin"); })
                  .find("not a distance file: bad magic"),
              std::string::npos);
    EXPECT_NE(error_of<FormatError>([&] { (void)read_signed_distance_file(dir / "o.bin"); })
                  .find("not a signed distance file"),
              std::string::npos);
    EXPECT_NE(error_of<FormatError>([&] { (void)read_occupancy_file(dir / "d.bin"); })
                  .find("not an occupancy file"),
              std::string::npos);

    const std::vector<std::uint8_t> ok = test::read_bytes(dir / "d.bin");
    test::write_bytes(path, test::prefix_of(ok, ok.size() - 1));
    EXPECT_NE(error_of<FormatError>([&] { (void)read_distance_file(path); }).find("truncated"),
              std::string::npos);
}

TEST(ClosestPointFile, RoundTripAndLayout)
{
    test::ScratchDir dir;
    std::vector<ClosestPoint> closest(3);
    closest[0] = {1.25f, 7, 0.25f, 0.5f, {1.0f, -2.0f, 3.5f}};
    closest[1] = {inf, invalid_triangle, 0.0f, 0.0f, {}};  // beyond max_distance
    closest[2] = {nan, invalid_triangle, 0.0f, 0.0f, {}};  // a non-finite point
    write_closest_point_file(dir / "c.bin", closest);
    const std::vector<std::uint8_t> f = test::read_bytes(dir / "c.bin");
    ASSERT_EQ(f.size(), 16u + 28u * closest.size());
    EXPECT_EQ(std::string(f.begin(), f.begin() + 8), "SGCLP001");
    EXPECT_EQ(load_le<std::uint64_t>(f, 8), closest.size());
    EXPECT_EQ(load_le<std::uint32_t>(f, 16), 7u);
    EXPECT_EQ(load_le<float>(f, 20), 1.25f);
    EXPECT_EQ(load_le<float>(f, 24), 0.25f);
    EXPECT_EQ(load_le<float>(f, 28), 0.5f);
    EXPECT_EQ(load_le<float>(f, 32), 1.0f);
    EXPECT_EQ(load_le<float>(f, 36), -2.0f);
    EXPECT_EQ(load_le<float>(f, 40), 3.5f);
    EXPECT_EQ(load_le<std::uint32_t>(f, 44), 0xFFFFFFFFu);
    EXPECT_EQ(load_le<float>(f, 48), inf);
    EXPECT_EQ(load_le<float>(f, 52), 0.0f);
    EXPECT_TRUE(std::isnan(load_le<float>(f, 60))) << "no answer has no point: x is NaN";
    EXPECT_TRUE(std::isnan(load_le<float>(f, 44 + 28 + 4)));

    const std::vector<ClosestPoint> read = read_closest_point_file(dir / "c.bin");
    ASSERT_EQ(read.size(), closest.size());
    EXPECT_EQ(read[0].triangle, 7u);
    EXPECT_EQ(read[0].distance, 1.25f);
    EXPECT_EQ(read[0].u, 0.25f);
    EXPECT_EQ(read[0].v, 0.5f);
    EXPECT_EQ(read[0].point, (Vec3f{1.0f, -2.0f, 3.5f}));
    EXPECT_FALSE(read[1].is_hit());
    EXPECT_EQ(read[1].distance, inf);
    EXPECT_TRUE(std::isnan(read[1].point.x));
    EXPECT_FALSE(read[2].is_hit());
    EXPECT_TRUE(std::isnan(read[2].distance));
}

TEST(ClosestPointFile, RecordsWhoseTriangleAndDistanceDisagreeAreRefused)
{
    test::ScratchDir dir;
    std::vector<ClosestPoint> closest(2);
    closest[0] = {1.0f, 3, 0.0f, 0.0f, {0.0f, 0.0f, 0.0f}};
    closest[1] = {2.0f, 4, 0.0f, 0.0f, {0.0f, 0.0f, 0.0f}};
    write_closest_point_file(dir / "ok.bin", closest);
    const std::vector<std::uint8_t> ok = test::read_bytes(dir / "ok.bin");
    const auto path = dir / "bad.bin";
    const auto read = [&] { (void)read_closest_point_file(path); };

    std::vector<std::uint8_t> bad = ok;
    store_le<float>(bad, 16 + 28 + 4, inf);
    test::write_bytes(path, bad);
    EXPECT_EQ(error_of<FormatError>(read),
              path.string() + ": point 1 has triangle 4 and distance inf, expected a finite, "
                              "non-negative distance for a triangle (at byte offset 44)");
    bad = ok;
    store_le<std::uint32_t>(bad, 16, 0xFFFFFFFFu);
    test::write_bytes(path, bad);
    EXPECT_NE(error_of<FormatError>(read).find("point 0 has triangle 4294967295 and distance "
                                               "1.000000, expected +infinity or NaN without a "
                                               "triangle"),
              std::string::npos);

    test::write_bytes(path, test::prefix_of(ok, ok.size() - 4));
    EXPECT_NE(error_of<FormatError>(read).find("truncated"), std::string::npos);
    write_distance_file(path, std::vector<float>{1.0f});
    EXPECT_NE(error_of<FormatError>(read).find("not a closest point file"), std::string::npos);
}

}  // namespace
}  // namespace sg
