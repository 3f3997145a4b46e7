// Tests of formats/src/sg_file.cpp and sg_file_read.cpp on well-formed files: round trips,
// byte-identical re-encoding, and the layout of docs/FORMAT.md checked byte by byte with
// hand-written offsets (not the implementation's structs). Damaged and hostile files are in
// sg_file_hostile_test.cpp.

#include "splitgrid/formats/sg_file.hpp"

#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>
// zlib is the checksum the format names; the tests recompute CRCs with it independently.
#include <zlib.h>

#include "file_helpers.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/validate.hpp"
#include "support/changed_config.hpp"
#include "support/random_scene.hpp"

namespace sg {
namespace {

using test::load_le;

constexpr Aabb unit_box{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}};

/// A configuration away from the defaults, so that its fields are seen to survive the round
/// trip; with bounding nodes, so that the grids hold one-cell nodes too.
BuildConfig test_config()
{
    BuildConfig c = test::every_field_changed(false);
    c.bounding_nodes = true;
    return c;
}

SgContents make_contents(Mesh mesh, const BuildConfig& config, std::string name)
{
    SgContents c;
    c.grid = build_split_grid(mesh.view(), config);
    check_invariants(c.grid);
    c.mesh = std::move(mesh);
    c.source_name = std::move(name);
    return c;
}

SgContents random_contents(std::uint32_t seed, std::size_t triangles)
{
    return make_contents(test::random_triangles(seed, triangles, unit_box, 0.2f), test_config(),
                         "random_" + std::to_string(seed) + ".obj");
}

TEST(SgFile, RoundTripOfABuiltGridIsEqual)
{
    test::ScratchDir dir;
    const SgContents original = random_contents(7, 500);
    ASSERT_GT(original.grid.nodes.size(), 1u) << "the test needs a grid with several nodes";
    ASSERT_FALSE(original.grid.leaf_words.empty());

    const auto path = dir / "random.sg";
    write_sg_file(path, original);
    const SgContents read = read_sg_file(path, {.verify_checksums = true, .check_coverage = true});
    EXPECT_EQ(read.mesh, original.mesh);
    EXPECT_EQ(read.grid.config, original.grid.config);
    EXPECT_EQ(read.grid.root_box, original.grid.root_box);
    EXPECT_EQ(read.grid.root, original.grid.root);
    EXPECT_EQ(read.grid.nodes, original.grid.nodes);
    EXPECT_EQ(read.grid.cells, original.grid.cells);
    EXPECT_EQ(read.grid.leaf_words, original.grid.leaf_words);
    EXPECT_EQ(read.grid.triangle_count, 500u);
    EXPECT_EQ(read.source_name, "random_7.obj");
    EXPECT_EQ(read, original);
}

TEST(SgFile, RoundTripOfSharedVerticesAndAUtf8Name)
{
    test::ScratchDir dir;
    Mesh mesh = test::uv_sphere({0.5f, -2.0f, 3.0f}, 1.5f, 12, 24);
    test::append(mesh, test::axis_plane(1, -4.0f, 6));
    const SgContents original = make_contents(std::move(mesh), BuildConfig{},
                                              "W\xC3\xBCrfel \xE2\x9C\x93.glb");  // "Würfel ✓.glb"
    write_sg_file(dir / "sphere.sg", original);
    EXPECT_EQ(read_sg_file(dir / "sphere.sg"), original);
}

TEST(SgFile, RoundTripOfAnEmptyMeshAndAnEmptyName)
{
    // An empty mesh gives an empty root and an empty (infinite) root box: all sections but
    // CONF are empty.
    const SgContents original = make_contents(Mesh{}, BuildConfig{}, "");
    ASSERT_TRUE(original.grid.root.is_empty());
    const std::vector<std::uint8_t> bytes = encode_sg(original);
    EXPECT_EQ(bytes.size(), 80u + 7u * 32u + 88u) << "header + table + one config record";
    EXPECT_EQ(read_sg_bytes(bytes, "empty.sg"), original);
}

TEST(SgFile, RoundTripOfASingleTriangleLeafRoot)
{
    Mesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.triangles = {Triangle{{0, 1, 2}}};
    const SgContents original = make_contents(std::move(mesh), BuildConfig{}, "one.obj");
    EXPECT_EQ(read_sg_bytes(encode_sg(original), "one.sg"), original);
}

TEST(SgFile, WriteReadWriteGivesIdenticalBytes)
{
    test::ScratchDir dir;
    const SgContents original = random_contents(11, 300);
    write_sg_file(dir / "a.sg", original);
    const std::vector<std::uint8_t> first = test::read_bytes(dir / "a.sg");
    EXPECT_EQ(first, encode_sg(original)) << "encode_sg must give what write_sg_file writes";

    write_sg_file(dir / "b.sg", read_sg_file(dir / "a.sg"));
    EXPECT_EQ(test::read_bytes(dir / "b.sg"), first);
    // And the encoding does not depend on anything but the contents (no uninitialised
    // padding, no time stamps).
    EXPECT_EQ(encode_sg(random_contents(11, 300)), first);
}

TEST(SgFile, ThreadCountDoesNotChangeTheStructureBytes)
{
    // The builder promises bit-identical output for every thread count; the file stores the
    // requested count in CONF, so only that field may differ.
    BuildConfig one = test_config();
    one.threads = 1;
    BuildConfig many = test_config();
    many.threads = 4;
    const Mesh mesh = test::random_triangles(5, 400, unit_box, 0.2f);
    std::vector<std::uint8_t> a = encode_sg(make_contents(mesh, one, "m"));
    std::vector<std::uint8_t> b = encode_sg(make_contents(mesh, many, "m"));
    ASSERT_EQ(a.size(), b.size());
    std::vector<std::size_t> differing;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i] != b[i]) differing.push_back(i);
    // threads (CONF + 44), the CONF checksum in the table (80 + 4) and the header CRC (28).
    const std::size_t conf = 80 + 7 * 32;
    for (const std::size_t i : differing) {
        const bool allowed = (i >= 28 && i < 32) || (i >= 84 && i < 88) ||
                             (i >= conf + 44 && i < conf + 48);
        EXPECT_TRUE(allowed) << "byte " << i << " differs";
    }
}

/// The layout of docs/FORMAT.md, read with literal offsets.
TEST(SgFile, LayoutMatchesFormatDocument)
{
    const SgContents c = random_contents(3, 200);
    const std::vector<std::uint8_t> f = encode_sg(c);

    const std::array<std::uint8_t, 8> magic{0x89, 'S', 'G', 'F', '\r', '\n', 0x1A, '\n'};
    EXPECT_TRUE(std::equal(magic.begin(), magic.end(), f.begin()));
    EXPECT_EQ(load_le<std::uint32_t>(f, 8), 5u) << "format version";
    EXPECT_EQ((std::array<std::uint8_t, 4>{f[12], f[13], f[14], f[15]}),
              (std::array<std::uint8_t, 4>{0x04, 0x03, 0x02, 0x01}))
        << "endianness marker 0x01020304 stored little-endian";
    EXPECT_EQ(load_le<std::uint32_t>(f, 16), 80u) << "header bytes";
    EXPECT_EQ(load_le<std::uint32_t>(f, 20), 32u) << "section entry bytes";
    EXPECT_EQ(load_le<std::uint32_t>(f, 24), 7u) << "section count";
    EXPECT_EQ(load_le<std::uint64_t>(f, 32), f.size()) << "file bytes";
    EXPECT_EQ(load_le<std::uint64_t>(f, 40), 80u) << "table offset";
    EXPECT_EQ(load_le<std::uint32_t>(f, 48), 12u) << "Vec3f";
    EXPECT_EQ(load_le<std::uint32_t>(f, 52), 12u) << "Triangle";
    EXPECT_EQ(load_le<std::uint32_t>(f, 56), 16u) << "GridNode";
    EXPECT_EQ(load_le<std::uint32_t>(f, 60), 4u) << "CellRef";
    EXPECT_EQ(load_le<std::uint32_t>(f, 64), 2u) << "leaf word";
    EXPECT_EQ(load_le<std::uint32_t>(f, 68), 88u) << "config record";
    EXPECT_EQ(load_le<std::uint64_t>(f, 72), 0u) << "reserved";

    // Header CRC: the 80 header bytes with bytes 28..31 zeroed, then the 224 table bytes.
    std::vector<std::uint8_t> head(f.begin(), f.begin() + 80 + 7 * 32);
    std::fill(head.begin() + 28, head.begin() + 32, std::uint8_t{0});
    EXPECT_EQ(load_le<std::uint32_t>(f, 28),
              ::crc32(0, head.data(), static_cast<uInt>(head.size())));

    const std::array<const char*, 7> tags{"CONF", "NAME", "VERT", "TRIS", "NODE", "CELL", "TREF"};
    const std::array<std::uint64_t, 7> record_bytes{88, 1, 12, 12, 16, 4, 2};
    const std::array<std::uint64_t, 7> counts{1,
                                              c.source_name.size(),
                                              c.mesh.vertices.size(),
                                              c.mesh.triangles.size(),
                                              c.grid.nodes.size(),
                                              c.grid.cells.size(),
                                              c.grid.leaf_words.size()};
    std::uint64_t expected_offset = 80 + 7 * 32;
    for (std::size_t i = 0; i < 7; ++i) {
        SCOPED_TRACE(tags[i]);
        const std::size_t e = 80 + 32 * i;
        EXPECT_EQ(std::string(f.begin() + static_cast<std::ptrdiff_t>(e),
                              f.begin() + static_cast<std::ptrdiff_t>(e + 4)),
                  tags[i]);
        const auto offset = load_le<std::uint64_t>(f, e + 8);
        const auto bytes = load_le<std::uint64_t>(f, e + 16);
        EXPECT_EQ(offset, expected_offset);
        EXPECT_EQ(offset % 8, 0u);
        EXPECT_EQ(load_le<std::uint64_t>(f, e + 24), counts[i]);
        EXPECT_EQ(bytes, counts[i] * record_bytes[i]);
        EXPECT_EQ(load_le<std::uint32_t>(f, e + 4),
                  ::crc32(0, f.data() + offset, static_cast<uInt>(bytes)));
        for (std::uint64_t p = offset + bytes; p < (offset + bytes + 7) / 8 * 8; ++p)
            EXPECT_EQ(f[p], 0) << "padding at " << p;
        expected_offset = (offset + bytes + 7) / 8 * 8;
    }
    EXPECT_EQ(expected_offset, f.size());

    // CONF record fields at their documented offsets.
    const std::size_t conf = 80 + 7 * 32;
    const BuildConfig& cfg = c.grid.config;
    EXPECT_EQ(load_le<std::uint32_t>(f, conf + 0), cfg.resolution_min);
    EXPECT_EQ(load_le<std::uint32_t>(f, conf + 4), cfg.resolution_max);
    EXPECT_EQ(load_le<double>(f, conf + 8), cfg.resolution_sigma);
    EXPECT_EQ(load_le<std::uint32_t>(f, conf + 16), cfg.leaf_size);
    EXPECT_EQ(load_le<std::uint32_t>(f, conf + 20), cfg.max_depth);
    EXPECT_EQ(load_le<double>(f, conf + 24), cfg.no_progress_fraction);
    EXPECT_EQ(load_le<double>(f, conf + 32), cfg.min_cell_width);
    EXPECT_EQ(load_le<std::uint32_t>(f, conf + 40), cfg.stop_by_cost ? 1u : 0u);
    EXPECT_EQ(load_le<std::uint32_t>(f, conf + 44), cfg.threads);
    EXPECT_EQ(load_le<std::uint32_t>(f, conf + 48), 200u);
    EXPECT_EQ(load_le<float>(f, conf + 52), c.grid.root_box.lower.x);
    EXPECT_EQ(load_le<float>(f, conf + 60), c.grid.root_box.lower.z);
    EXPECT_EQ(load_le<float>(f, conf + 64), c.grid.root_box.upper.x);
    EXPECT_EQ(load_le<float>(f, conf + 72), c.grid.root_box.upper.z);
    EXPECT_EQ(load_le<std::uint32_t>(f, conf + 76) >> 2, c.grid.root.index());
    ASSERT_TRUE(c.grid.root.is_inner());
    EXPECT_EQ(load_le<std::uint32_t>(f, conf + 76) & 3u,
              c.grid.nodes[c.grid.root.child()].resolution() == 1 ? 3u : 2u)
        << "the root is inner, of the kind its child's resolution gives";
    EXPECT_EQ(load_le<std::uint32_t>(f, conf + 80), 0u) << "reserved";
    EXPECT_EQ(load_le<std::uint32_t>(f, conf + 84), 7u)
        << "build_flags: bounding planes and clipping off, bounding nodes on";

    // First records of the array sections, per grid_node.hpp's layouts.
    const auto section_offset = [&](std::size_t i) {
        return static_cast<std::size_t>(load_le<std::uint64_t>(f, 80 + 32 * i + 8));
    };
    EXPECT_EQ(std::string(f.begin() + static_cast<std::ptrdiff_t>(section_offset(1)),
                          f.begin() + static_cast<std::ptrdiff_t>(section_offset(1) + counts[1])),
              c.source_name);
    EXPECT_EQ(load_le<float>(f, section_offset(2) + 4), c.mesh.vertices[0].y);
    EXPECT_EQ(load_le<std::uint32_t>(f, section_offset(3) + 12 + 8), c.mesh.triangles[1].v[2]);
    const GridNode& node = c.grid.nodes.back();
    const std::size_t n = section_offset(4) + 16 * (c.grid.nodes.size() - 1);
    EXPECT_EQ(load_le<float>(f, n + 0), node.lo);
    EXPECT_EQ(load_le<float>(f, n + 4), node.hi);
    EXPECT_EQ(load_le<std::uint32_t>(f, n + 8), node.cells_bits());
    EXPECT_EQ(load_le<std::uint32_t>(f, n + 12) & 3u, static_cast<std::uint32_t>(node.axis()));
    EXPECT_EQ(load_le<std::uint32_t>(f, n + 12) >> 2, node.resolution());
    const CellRef& cell = c.grid.cells.back();
    const std::size_t k = section_offset(5) + 4 * (c.grid.cells.size() - 1);
    EXPECT_EQ(load_le<std::uint32_t>(f, k) >> 2, cell.index());
    const std::uint32_t inner_kind =
        cell.is_inner() && c.grid.nodes[cell.child()].resolution() == 1 ? 3u : 2u;
    EXPECT_EQ(load_le<std::uint32_t>(f, k) & 3u,
              cell.is_empty() ? 0u : (cell.is_leaf() ? 1u : inner_kind));
    EXPECT_EQ(load_le<std::uint16_t>(f, section_offset(6) + 2 * 5), c.grid.leaf_words[5]);
    // The array's last word ends a leaf: bit 15 is the last mark of a narrow reference, or
    // the upper half's bit 31 of a head or wide reference.
    EXPECT_NE(load_le<std::uint16_t>(f, section_offset(6) + 2 * (c.grid.leaf_words.size() - 1)) &
                  0x8000u,
              0u);
}

TEST(SgFile, InfoReadsTheHeaderAndTable)
{
    test::ScratchDir dir;
    const SgContents c = random_contents(9, 150);
    write_sg_file(dir / "x.sg", c);
    const SgFileInfo info = read_sg_info(dir / "x.sg");
    EXPECT_EQ(info.format_version, 5u);
    EXPECT_EQ(info.file_bytes, std::filesystem::file_size(dir / "x.sg"));
    ASSERT_EQ(info.sections.size(), 7u);
    EXPECT_EQ(info.sections[2].name, "VERT");
    EXPECT_EQ(info.sections[2].count, c.mesh.vertices.size());
    EXPECT_EQ(info.sections[2].bytes, 12 * c.mesh.vertices.size());
    EXPECT_EQ(info.sections[4].name, "NODE");
    EXPECT_EQ(info.sections[4].count, c.grid.nodes.size());
    EXPECT_EQ(info.sections[6].name, "TREF");
    EXPECT_EQ(info.sections[6].count, c.grid.leaf_words.size());
    EXPECT_EQ(info.sections[6].bytes, 2 * c.grid.leaf_words.size());
    const std::vector<std::uint8_t> bytes = test::read_bytes(dir / "x.sg");
    for (const SgSectionInfo& s : info.sections)
        EXPECT_EQ(s.crc32, ::crc32(0, bytes.data() + s.offset, static_cast<uInt>(s.bytes))) << s.name;
}

TEST(SgFile, InfoDoesNotReadTheSections)
{
    // A damaged section (checksum mismatch) does not matter to read_sg_info, only the header
    // and table do: it reads no further than the table.
    test::ScratchDir dir;
    std::vector<std::uint8_t> bytes = encode_sg(random_contents(9, 150));
    bytes[bytes.size() - 5] ^= 0x40;
    test::write_bytes(dir / "x.sg", bytes);
    EXPECT_THROW((void)read_sg_file(dir / "x.sg"), FormatError);
    EXPECT_EQ(read_sg_info(dir / "x.sg").sections.size(), 7u);
}

TEST(SgFile, StructureBytesPerTriangle)
{
    // docs/FORMAT.md: the structure alone is SplitGrid::memory_bytes(); the file adds the
    // mesh, the name, the header, the table, the config record and padding.
    const SgContents c = random_contents(4, 400);
    const std::size_t structure = c.grid.memory_bytes();
    EXPECT_EQ(structure, 24 + 4 + 16 * c.grid.nodes.size() + 4 * c.grid.cells.size() +
                             2 * c.grid.leaf_words.size());
    const std::size_t file = encode_sg(c).size();
    std::size_t sections = 88 + c.source_name.size() + 12 * c.mesh.vertices.size() +
                           12 * c.mesh.triangles.size() + 16 * c.grid.nodes.size() +
                           4 * c.grid.cells.size() + 2 * c.grid.leaf_words.size();
    EXPECT_GE(file, 80 + 224 + sections);
    EXPECT_LE(file, 80 + 224 + sections + 7 * 7) << "at most 7 padding bytes per section";
}

}  // namespace
}  // namespace sg
