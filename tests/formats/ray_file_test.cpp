// Tests of formats/src/ray_file.cpp: round trips, the byte layout of docs/FORMAT.md read
// with literal offsets, and malformed files.

#include "splitgrid/formats/ray_file.hpp"

#include <bit>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "file_helpers.hpp"
#include "splitgrid/error.hpp"
#include "support/random_scene.hpp"

namespace sg {
namespace {

using test::error_of;
using test::load_le;
using test::store_le;

constexpr float inf = std::numeric_limits<float>::infinity();

/// Bitwise float comparison, so that infinities and NaN payloads must survive too.
bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }

bool same_ray(const Ray& a, const Ray& b)
{
    return same_bits(a.origin.x, b.origin.x) && same_bits(a.origin.y, b.origin.y) &&
           same_bits(a.origin.z, b.origin.z) && same_bits(a.direction.x, b.direction.x) &&
           same_bits(a.direction.y, b.direction.y) && same_bits(a.direction.z, b.direction.z) &&
           same_bits(a.t_min, b.t_min) && same_bits(a.t_max, b.t_max);
}

std::vector<Ray> some_rays()
{
    std::vector<Ray> rays = test::random_rays(17, 300, Aabb{{-1, -2, -3}, {4, 5, 6}});
    // Edge values a ray file must carry unchanged: zero and negative-zero components,
    // a finite t_max, a NaN (invalid ray, still stored as given).
    rays.push_back(Ray{{0, 0, 0}, {0.0f, -0.0f, 1.0f}, 0.5f, 2.0f});
    rays.push_back(Ray{{1, 2, 3}, {std::numeric_limits<float>::quiet_NaN(), 0, 0}, 0.0f, inf});
    return rays;
}


TEST(RayFile, RoundTripKeepsEveryBit)
{
    test::ScratchDir dir;
    const std::vector<Ray> rays = some_rays();
    write_ray_file(dir / "r.rays", rays);
    const std::vector<Ray> read = read_ray_file(dir / "r.rays");
    ASSERT_EQ(read.size(), rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) EXPECT_TRUE(same_ray(read[i], rays[i])) << i;
}

TEST(RayFile, LayoutMatchesFormatDocument)
{
    test::ScratchDir dir;
    const std::vector<Ray> rays = some_rays();
    write_ray_file(dir / "r.rays", rays);
    const std::vector<std::uint8_t> f = test::read_bytes(dir / "r.rays");
    ASSERT_EQ(f.size(), 16 + 32 * rays.size());
    EXPECT_EQ(std::string(f.begin(), f.begin() + 8), "SGRAY001");
    EXPECT_EQ(load_le<std::uint64_t>(f, 8), rays.size());
    const std::size_t last = 16 + 32 * (rays.size() - 3);
    const Ray& r = rays[rays.size() - 3];
    EXPECT_EQ(load_le<float>(f, last + 0), r.origin.x);
    EXPECT_EQ(load_le<float>(f, last + 8), r.origin.z);
    EXPECT_EQ(load_le<float>(f, last + 12), r.direction.x);
    EXPECT_EQ(load_le<float>(f, last + 20), r.direction.z);
    EXPECT_EQ(load_le<float>(f, last + 24), r.t_min);
    EXPECT_EQ(load_le<float>(f, last + 28), r.t_max);
}

TEST(RayFile, EmptyRayListRoundTrips)
{
    test::ScratchDir dir;
    write_ray_file(dir / "none.rays", {});
    EXPECT_EQ(std::filesystem::file_size(dir / "none.rays"), 16u);
    EXPECT_TRUE(read_ray_file(dir / "none.rays").empty());
}

TEST(HitFile, RoundTripAndLayout)
{
    test::ScratchDir dir;
    const std::vector<Hit> hits{Hit{1.5f, 7, 0.25f, 0.5f}, Hit{inf, invalid_triangle, 0.0f, 0.0f},
                                Hit{0.0f, 0xFFFFFFFEu, 1.0f, 0.0f}};
    write_hit_file(dir / "h.hits", hits);
    const std::vector<std::uint8_t> f = test::read_bytes(dir / "h.hits");
    ASSERT_EQ(f.size(), 16u + 16u * 3u);
    EXPECT_EQ(std::string(f.begin(), f.begin() + 8), "SGHIT001");
    EXPECT_EQ(load_le<std::uint64_t>(f, 8), 3u);
    EXPECT_EQ(load_le<std::uint32_t>(f, 16), 7u);
    EXPECT_EQ(load_le<float>(f, 20), 1.5f);
    EXPECT_EQ(load_le<float>(f, 24), 0.25f);
    EXPECT_EQ(load_le<float>(f, 28), 0.5f);
    EXPECT_EQ(load_le<std::uint32_t>(f, 32), 0xFFFFFFFFu) << "a miss";
    EXPECT_EQ(load_le<float>(f, 36), inf);

    const std::vector<Hit> read = read_hit_file(dir / "h.hits");
    ASSERT_EQ(read.size(), hits.size());
    for (std::size_t i = 0; i < hits.size(); ++i) {
        EXPECT_EQ(read[i].triangle, hits[i].triangle);
        EXPECT_TRUE(same_bits(read[i].t, hits[i].t));
        EXPECT_TRUE(same_bits(read[i].u, hits[i].u));
        EXPECT_TRUE(same_bits(read[i].v, hits[i].v));
    }
    EXPECT_FALSE(read[1].is_hit());
}

TEST(RayFile, EveryTruncationIsRefused)
{
    test::ScratchDir dir;
    std::vector<Ray> rays = some_rays();
    rays.resize(3);
    write_ray_file(dir / "r.rays", rays);
    const std::vector<std::uint8_t> full = test::read_bytes(dir / "r.rays");
    const auto path = dir / "cut.rays";
    for (std::size_t size = 0; size < full.size(); ++size) {
        SCOPED_TRACE(size);
        test::write_bytes(path, std::vector<std::uint8_t>(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(size)));
        const std::string m = error_of<FormatError>([&] { (void)read_ray_file(path); });
        EXPECT_EQ(m.rfind(path.string() + ": ", 0), 0u) << m;
        if (size >= 8) {
            EXPECT_NE(m.find("truncated"), std::string::npos) << m;
        }
    }
}

TEST(RayFile, MalformedFilesAreRefusedNamingTheFile)
{
    test::ScratchDir dir;
    write_ray_file(dir / "ok.rays", std::vector<Ray>(4));
    const std::vector<std::uint8_t> ok = test::read_bytes(dir / "ok.rays");
    const auto path = dir / "bad.rays";

    std::vector<std::uint8_t> bad = ok;
    bad[3] = 'X';
    test::write_bytes(path, bad);
    EXPECT_EQ(error_of<FormatError>([&] { (void)read_ray_file(path); }),
              path.string() + ": not a ray file: bad magic (at byte offset 0, expected \"SGRAY001\")");

    bad = ok;
    store_le<std::uint64_t>(bad, 8, 3);  // fewer than the file holds
    test::write_bytes(path, bad);
    EXPECT_EQ(error_of<FormatError>([&] { (void)read_ray_file(path); }),
              path.string() + ": the header counts 3 rays, the file size fits 4 (at byte offset 8, "
                              "expected 16 + 3 x 32 bytes, found 144 bytes)");

    bad = ok;
    bad.push_back(0);  // trailing partial record
    test::write_bytes(path, bad);
    EXPECT_NE(error_of<FormatError>([&] { (void)read_ray_file(path); }).find("counts 4 rays"),
              std::string::npos);

    bad = ok;
    store_le<std::uint64_t>(bad, 8, std::numeric_limits<std::uint64_t>::max());  // hostile
    test::write_bytes(path, bad);
    EXPECT_NE(error_of<FormatError>([&] { (void)read_ray_file(path); })
                  .find("truncated: the header counts 18446744073709551615 rays"),
              std::string::npos);

    // A hit file is not a ray file, and the other way round.
    write_hit_file(dir / "h.hits", {Hit{}});
    EXPECT_NE(error_of<FormatError>([&] { (void)read_ray_file(dir / "h.hits"); }).find("bad magic"),
              std::string::npos);
    EXPECT_NE(error_of<FormatError>([&] { (void)read_hit_file(dir / "ok.rays"); })
                  .find("not a hit file"),
              std::string::npos);
}

TEST(RayFile, MissingFileIsAnIoError)
{
    test::ScratchDir dir;
    EXPECT_EQ(error_of<IoError>([&] { (void)read_ray_file(dir / "none.rays"); }),
              (dir / "none.rays").string() + ": cannot open: No such file or directory");
    EXPECT_THROW((void)read_hit_file(dir / "none.hits"), IoError);
}

}  // namespace
}  // namespace sg
