// The CONF section of a .sg file as docs/FORMAT.md lays it out, byte for byte: the writer
// and reader go through BuildConfig's field table (build_config.hpp) and the slot table of
// sg_file_layout.hpp, and the bytes must stay those of the documented record.

#include <cstdint>
#include <string>
#include <vector>

#include "file_helpers.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "support/changed_config.hpp"
#include "support/random_scene.hpp"

#include <gtest/gtest.h>

namespace sg {
namespace {

/// A small grid built with every field away from its default.
SgContents unusual_contents(bool switches)
{
    SgContents c;
    c.mesh = test::random_triangles(5, 60, Aabb{{0, 0, 0}, {1, 1, 1}}, 0.2f);
    c.grid = build_split_grid(c.mesh.view(), test::every_field_changed(switches));
    c.grid.config.threads = 7;  // the builder keeps 0; the file stores whatever it is given
    c.source_name = "conf.obj";
    return c;
}

TEST(SgFileConf, FieldsLieAtTheDocumentedOffsets)
{
    for (const bool switches : {true, false}) {
        SCOPED_TRACE(switches ? "switches on" : "switches off");
        const SgContents c = unusual_contents(switches);
        const std::vector<std::uint8_t> bytes = encode_sg(c);
        // The first entry of the section table (at byte 80) is CONF; its offset at +8.
        ASSERT_EQ(std::string(bytes.begin() + 80, bytes.begin() + 84), "CONF");
        const auto at = static_cast<std::size_t>(test::load_le<std::uint64_t>(bytes, 88));
        EXPECT_EQ(test::load_le<std::uint64_t>(bytes, 96), 88u) << "CONF holds 88 bytes";
        const BuildConfig config = test::every_field_changed(switches);
        EXPECT_EQ(test::load_le<std::uint32_t>(bytes, at + 0), config.resolution_min);
        EXPECT_EQ(test::load_le<std::uint32_t>(bytes, at + 4), config.resolution_max);
        EXPECT_EQ(test::load_le<double>(bytes, at + 8), config.resolution_sigma);
        EXPECT_EQ(test::load_le<std::uint32_t>(bytes, at + 16), config.leaf_size);
        EXPECT_EQ(test::load_le<std::uint32_t>(bytes, at + 20), config.max_depth);
        EXPECT_EQ(test::load_le<double>(bytes, at + 24), config.no_progress_fraction);
        EXPECT_EQ(test::load_le<double>(bytes, at + 32), config.min_cell_width);
        EXPECT_EQ(test::load_le<std::uint32_t>(bytes, at + 40), switches ? 1u : 0u);
        EXPECT_EQ(test::load_le<std::uint32_t>(bytes, at + 44), 7u);
        EXPECT_EQ(test::load_le<std::uint32_t>(bytes, at + 48), c.mesh.triangles.size());
        EXPECT_EQ(test::load_le<float>(bytes, at + 52), c.grid.root_box.lower.x);
        EXPECT_EQ(test::load_le<float>(bytes, at + 72), c.grid.root_box.upper.z);
        EXPECT_EQ(test::load_le<std::uint32_t>(bytes, at + 76), c.grid.root.raw_bits());
        EXPECT_EQ(test::load_le<std::uint32_t>(bytes, at + 80), 0u) << "reserved";
        // build_flags: bit 0 set = bounding planes off, bit 1 set = clipping off, bit 2 set =
        // bounding nodes on.
        EXPECT_EQ(test::load_le<std::uint32_t>(bytes, at + 84), switches ? 4u : 3u);

        const SgContents back = read_sg_bytes(bytes, "conf.sg");
        EXPECT_EQ(back.grid.config, c.grid.config);
        EXPECT_EQ(back, c);
    }
}

TEST(SgFileConf, EachSwitchHasItsOwnBit)
{
    SgContents c = unusual_contents(true);
    c.grid.config.clip_triangles = false;
    std::vector<std::uint8_t> bytes = encode_sg(c);
    const auto at = static_cast<std::size_t>(test::load_le<std::uint64_t>(bytes, 88));
    EXPECT_EQ(test::load_le<std::uint32_t>(bytes, at + 84), 2u | 4u);
    c.grid.config.clip_triangles = true;
    c.grid.config.bounding_planes = false;
    bytes = encode_sg(c);
    EXPECT_EQ(test::load_le<std::uint32_t>(bytes, at + 84), 1u | 4u);
    SgContents back = read_sg_bytes(bytes, "conf.sg", {.verify_checksums = false});
    EXPECT_FALSE(back.grid.config.bounding_planes);
    EXPECT_TRUE(back.grid.config.clip_triangles);
    EXPECT_TRUE(back.grid.config.bounding_nodes);
    c.grid.config.bounding_planes = true;
    c.grid.config.bounding_nodes = false;
    bytes = encode_sg(c);
    EXPECT_EQ(test::load_le<std::uint32_t>(bytes, at + 84), 0u);
    back = read_sg_bytes(bytes, "conf.sg", {.verify_checksums = false});
    EXPECT_FALSE(back.grid.config.bounding_nodes);
}

TEST(SgFileConf, AFileWrittenBeforeBoundingNodesExistedReadsAsBuiltWithoutThem)
{
    // Files of the same format version written before the switch existed have bit 2 clear,
    // and were built by the split rule alone: they must not read as built with bounding nodes.
    BuildConfig defaults;
    ASSERT_TRUE(defaults.bounding_nodes) << "the test assumes the switch's default is on";
    SgContents c = unusual_contents(false);
    c.grid.config.bounding_planes = true;
    c.grid.config.clip_triangles = true;
    const std::vector<std::uint8_t> bytes = encode_sg(c);
    const auto at = static_cast<std::size_t>(test::load_le<std::uint64_t>(bytes, 88));
    ASSERT_EQ(test::load_le<std::uint32_t>(bytes, at + 84), 0u) << "an older file's flags word";
    const SgContents back = read_sg_bytes(bytes, "conf.sg");
    EXPECT_FALSE(back.grid.config.bounding_nodes);
    EXPECT_TRUE(back.grid.config.bounding_planes);
}

TEST(SgFileConf, ASwitchStoredAsAnythingButZeroOrOneIsRefusedWithItsOffset)
{
    std::vector<std::uint8_t> bytes = encode_sg(unusual_contents(true));
    const auto at = static_cast<std::size_t>(test::load_le<std::uint64_t>(bytes, 88));
    test::store_le<std::uint32_t>(bytes, at + 40, 2);
    try {
        (void)read_sg_bytes(bytes, "conf.sg", {.verify_checksums = false});
        FAIL() << "stop_by_cost = 2 accepted";
    } catch (const FormatError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("CONF stop_by_cost is not a boolean"), std::string::npos) << m;
        EXPECT_NE(m.find("at byte offset " + std::to_string(at + 40)), std::string::npos) << m;
    }
}

}  // namespace
}  // namespace sg
