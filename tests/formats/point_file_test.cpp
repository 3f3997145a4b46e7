// Tests of formats/src/point_file.cpp and point_text.cpp: point and occupancy files round trip
// with every bit, their bytes at the literal offsets of docs/FORMAT.md, text points line by
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

}  // namespace
}  // namespace sg
