// Tests of formats/src/intersection_file.cpp: hit count and hit list files round trip, their
// bytes at the literal offsets of docs/FORMAT.md, and every malformed file refused with a
// FormatError naming the file.

#include "splitgrid/formats/intersection_file.hpp"

#include <bit>
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

/// Three rays: two hits, none, three hits (two at the same t, by triangle id).
IntersectionList some_list()
{
    IntersectionList list;
    list.ray_splits = {0, 2, 2, 5};
    list.ray_ids = {0, 0, 2, 2, 2};
    list.hits = {Hit{0.5f, 9, 0.25f, 0.5f}, Hit{2.0f, 3, 0.0f, 1.0f},
                 Hit{1.0f, 4, 0.125f, 0.0f}, Hit{1.0f, 7, 0.5f, 0.5f},
                 Hit{3.5f, 0, 1.0f, 0.0f}};
    return list;
}

bool same_bits(float a, float b)
{
    return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}

TEST(HitCountFile, RoundTripAndLayout)
{
    test::ScratchDir dir;
    const std::vector<std::int32_t> counts{0, 3, 1, 2147483647, 0};
    write_hit_count_file(dir / "c.bin", counts);
    const std::vector<std::uint8_t> f = test::read_bytes(dir / "c.bin");
    ASSERT_EQ(f.size(), 16u + 4u * counts.size());
    EXPECT_EQ(std::string(f.begin(), f.begin() + 8), "SGCNT001");
    EXPECT_EQ(load_le<std::uint64_t>(f, 8), counts.size());
    EXPECT_EQ(load_le<std::int32_t>(f, 16 + 4), 3);
    EXPECT_EQ(load_le<std::int32_t>(f, 16 + 12), 2147483647);
    EXPECT_EQ(read_hit_count_file(dir / "c.bin"), counts);

    write_hit_count_file(dir / "none.bin", std::vector<std::int32_t>{});
    EXPECT_EQ(std::filesystem::file_size(dir / "none.bin"), 16u);
    EXPECT_TRUE(read_hit_count_file(dir / "none.bin").empty());
}

TEST(HitCountFile, MalformedFilesAreRefusedNamingTheFile)
{
    test::ScratchDir dir;
    write_hit_count_file(dir / "ok.bin", std::vector<std::int32_t>{1, 2, 3});
    const std::vector<std::uint8_t> ok = test::read_bytes(dir / "ok.bin");
    const auto path = dir / "bad.bin";
    const auto read = [&] { (void)read_hit_count_file(path); };

    for (std::size_t size = 0; size < ok.size(); ++size) {
        SCOPED_TRACE(size);
        test::write_bytes(path, test::prefix_of(ok, size));
        const std::string m = error_of<FormatError>(read);
        EXPECT_EQ(m.rfind(path.string() + ": ", 0), 0u) << m;
        if (size >= 8) {
            EXPECT_NE(m.find("truncated"), std::string::npos) << m;
        }
    }

    std::vector<std::uint8_t> bad = ok;
    bad[2] = 'H';
    test::write_bytes(path, bad);
    EXPECT_EQ(error_of<FormatError>(read),
              path.string() + ": not a hit count file: bad magic (at byte offset 0, expected "
                              "\"SGCNT001\")");

    bad = ok;
    store_le<std::int32_t>(bad, 16 + 4, -2);
    test::write_bytes(path, bad);
    EXPECT_EQ(error_of<FormatError>(read),
              path.string() + ": ray 1 has a negative hit count -2 (at byte offset 20)");

    bad = ok;
    store_le<std::uint64_t>(bad, 8, std::numeric_limits<std::uint64_t>::max());
    test::write_bytes(path, bad);
    EXPECT_NE(error_of<FormatError>(read).find("truncated: the header counts "
                                               "18446744073709551615 hit counts"),
              std::string::npos);
}

TEST(HitListFile, RoundTripAndLayout)
{
    test::ScratchDir dir;
    const IntersectionList list = some_list();
    write_hit_list_file(dir / "a.bin", list);
    const std::vector<std::uint8_t> f = test::read_bytes(dir / "a.bin");
    // 24-byte header, R + 1 = 4 splits of 8 bytes, 5 hits of 20 bytes.
    ASSERT_EQ(f.size(), 24u + 8u * 4u + 20u * 5u);
    EXPECT_EQ(std::string(f.begin(), f.begin() + 8), "SGALL001");
    EXPECT_EQ(load_le<std::uint64_t>(f, 8), 3u) << "rays";
    EXPECT_EQ(load_le<std::uint64_t>(f, 16), 5u) << "hits";
    EXPECT_EQ(load_le<std::uint64_t>(f, 24), 0u);
    EXPECT_EQ(load_le<std::uint64_t>(f, 32), 2u);
    EXPECT_EQ(load_le<std::uint64_t>(f, 40), 2u);
    EXPECT_EQ(load_le<std::uint64_t>(f, 48), 5u);
    const std::size_t hit3 = 56 + 20 * 3;
    EXPECT_EQ(load_le<std::uint32_t>(f, hit3), 2u) << "ray id";
    EXPECT_EQ(load_le<std::uint32_t>(f, hit3 + 4), 7u) << "triangle id";
    EXPECT_EQ(load_le<float>(f, hit3 + 8), 1.0f);
    EXPECT_EQ(load_le<float>(f, hit3 + 12), 0.5f);
    EXPECT_EQ(load_le<float>(f, hit3 + 16), 0.5f);

    const IntersectionList read = read_hit_list_file(dir / "a.bin");
    EXPECT_EQ(read.ray_splits, list.ray_splits);
    EXPECT_EQ(read.ray_ids, list.ray_ids);
    ASSERT_EQ(read.hits.size(), list.hits.size());
    for (std::size_t i = 0; i < list.hits.size(); ++i) {
        EXPECT_EQ(read.hits[i].triangle, list.hits[i].triangle) << i;
        EXPECT_TRUE(same_bits(read.hits[i].t, list.hits[i].t)) << i;
        EXPECT_TRUE(same_bits(read.hits[i].u, list.hits[i].u)) << i;
        EXPECT_TRUE(same_bits(read.hits[i].v, list.hits[i].v)) << i;
    }

    write_hit_list_file(dir / "none.bin", IntersectionList{});
    EXPECT_EQ(std::filesystem::file_size(dir / "none.bin"), 32u) << "header and ray_splits {0}";
    const IntersectionList none = read_hit_list_file(dir / "none.bin");
    EXPECT_EQ(none.ray_splits, std::vector<std::uint64_t>{0});
    EXPECT_TRUE(none.ray_ids.empty());
    EXPECT_TRUE(none.hits.empty());
}

class HitListFileDamage : public ::testing::Test {
protected:
    void SetUp() override
    {
        write_hit_list_file(dir_ / "ok.bin", some_list());
        ok_ = test::read_bytes(dir_ / "ok.bin");
    }
    /// The refusal of `bytes` written to bad.bin.
    std::string refusal(const std::vector<std::uint8_t>& bytes)
    {
        test::write_bytes(path_, bytes);
        return error_of<FormatError>([&] { (void)read_hit_list_file(path_); });
    }

    test::ScratchDir dir_;
    std::filesystem::path path_ = dir_ / "bad.bin";
    std::vector<std::uint8_t> ok_;
};

TEST_F(HitListFileDamage, EveryTruncationIsRefused)
{
    for (std::size_t size = 0; size < ok_.size(); ++size) {
        SCOPED_TRACE(size);
        const std::string m = refusal(test::prefix_of(ok_, size));
        EXPECT_EQ(m.rfind(path_.string() + ": ", 0), 0u) << m;
        if (size >= 8) {
            EXPECT_NE(m.find("truncated"), std::string::npos) << m;
        }
    }
    std::vector<std::uint8_t> longer = ok_;
    longer.push_back(0);
    EXPECT_EQ(refusal(longer), path_.string() + ": the header counts 3 rays and 5 hits (at byte "
                                                "offset 8, expected 24 + 8 x (3 + 1) + 5 x 20 "
                                                "bytes, found 157 bytes)");
}

TEST_F(HitListFileDamage, ForgedCountsNeitherOverflowNorAllocate)
{
    for (const std::size_t offset : {8u, 16u}) {
        std::vector<std::uint8_t> bad = ok_;
        store_le<std::uint64_t>(bad, offset, std::numeric_limits<std::uint64_t>::max());
        EXPECT_NE(refusal(bad).find("truncated: the header counts"), std::string::npos) << offset;
        store_le<std::uint64_t>(bad, offset, std::numeric_limits<std::uint64_t>::max() / 8);
        EXPECT_NE(refusal(bad).find("truncated: the header counts"), std::string::npos) << offset;
    }
}

TEST_F(HitListFileDamage, BrokenPromisesOfTheLayoutAreRefused)
{
    std::vector<std::uint8_t> bad = ok_;
    bad[7] = '2';
    EXPECT_EQ(refusal(bad), path_.string() + ": not a hit list file: bad magic (at byte offset "
                                             "0, expected \"SGALL001\")");

    bad = ok_;
    store_le<std::uint64_t>(bad, 24, 1);
    EXPECT_EQ(refusal(bad),
              path_.string() + ": ray_splits[0] is 1, expected 0 (at byte offset 24)");

    bad = ok_;
    store_le<std::uint64_t>(bad, 40, 1);  // ray_splits[2] below ray_splits[1] = 2
    EXPECT_EQ(refusal(bad), path_.string() + ": ray_splits[2] = 1 is below ray_splits[1] = 2 (at "
                                             "byte offset 40)");

    bad = ok_;
    store_le<std::uint64_t>(bad, 48, 4);
    EXPECT_EQ(refusal(bad), path_.string() + ": ray_splits[3] is 4, expected the hit count 5 (at "
                                             "byte offset 48)");

    bad = ok_;
    store_le<std::uint32_t>(bad, 56 + 20 * 2, 1);  // hit 2 belongs to ray 2
    EXPECT_EQ(refusal(bad), path_.string() + ": hit 2 names ray 1, but ray_splits put it in ray 2 "
                                             "(at byte offset 96)");

    bad = ok_;
    store_le<std::uint32_t>(bad, 56 + 20 * 3 + 4, 4);  // same t and triangle as hit 2
    EXPECT_EQ(refusal(bad), path_.string() + ": hit 3 of ray 2 does not follow the one before it "
                                             "by t, then triangle id (at byte offset 116)");

    bad = ok_;
    store_le<float>(bad, 56 + 20 * 1 + 8, 0.25f);  // ray 0: t 0.5 then 0.25
    EXPECT_NE(refusal(bad).find("hit 1 of ray 0 does not follow"), std::string::npos);

    // Each kind of file refuses the others.
    write_hit_count_file(dir_ / "c.bin", std::vector<std::int32_t>{1});
    EXPECT_NE(error_of<FormatError>([&] { (void)read_hit_list_file(dir_ / "c.bin"); })
                  .find("not a hit list file"),
              std::string::npos);
    EXPECT_NE(error_of<FormatError>([&] { (void)read_hit_count_file(dir_ / "ok.bin"); })
                  .find("not a hit count file"),
              std::string::npos);
    EXPECT_EQ(error_of<IoError>([&] { (void)read_hit_list_file(dir_ / "none.bin"); }),
              (dir_ / "none.bin").string() + ": cannot open: No such file or directory");
}

}  // namespace
}  // namespace sg
