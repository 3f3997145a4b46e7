// Damaged and hostile .sg files (formats/src/sg_file_read.cpp): every truncation, every
// flipped byte, forged sizes and counts, out-of-range indices behind valid checksums. The
// reader must refuse each with a one-line FormatError naming the file, never crash, and
// never allocate much more than the file's own size.

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "file_helpers.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/validate.hpp"
#include "support/leaf_triangles.hpp"
#include "support/random_scene.hpp"

// ---------------------------------------------------------------------------------------
// Allocation probe: the global operator new of this test binary records the largest single
// request while a test asks it to, so a test can prove that a forged count did not cause a
// huge allocation (which would otherwise only show up as bad_alloc or an OOM kill).
// AddressSanitizer owns operator new and delete in sanitizer builds; there the probe stays
// off, and ASan itself aborts on any allocation beyond its limit.
namespace {
std::atomic<bool> probe_active{false};
std::atomic<std::size_t> probe_largest{0};
}  // namespace

#if !defined(__SANITIZE_ADDRESS__)
void* operator new(std::size_t bytes)
{
    if (probe_active.load(std::memory_order_relaxed)) {
        std::size_t seen = probe_largest.load(std::memory_order_relaxed);
        while (bytes > seen && !probe_largest.compare_exchange_weak(seen, bytes)) {
        }
    }
    if (void* p = std::malloc(bytes == 0 ? 1 : bytes)) return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t bytes) { return ::operator new(bytes); }
// GCC 12 cannot see that these replacements pair with the malloc in operator new above.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop
#endif

namespace sg {
namespace {

/// Largest single allocation made while running `f`.
template <class F>
std::size_t largest_allocation(F&& f)
{
    probe_largest = 0;
    probe_active = true;
    try {
        f();
    } catch (...) {
        probe_active = false;
        throw;
    }
    probe_active = false;
    return probe_largest;
}

using test::load_le;
using test::store_le;

constexpr Aabb unit_box{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}};
constexpr std::size_t table_at = 80;
constexpr std::size_t conf_at = 80 + 7 * 32;
constexpr SgReadOptions no_checksums{.verify_checksums = false, .check_coverage = false};

enum Section : std::size_t { conf, name, vert, tris, node, cell, tref };
constexpr std::array<const char*, 7> tags{"CONF", "NAME", "VERT", "TRIS", "NODE", "CELL", "TREF"};

std::size_t entry_at(Section s) { return table_at + 32 * s; }
std::size_t offset_of(const std::vector<std::uint8_t>& f, Section s)
{
    return static_cast<std::size_t>(load_le<std::uint64_t>(f, entry_at(s) + 8));
}

/// A small grid with several nodes, leaves and empty cells, so every section is non-empty.
SgContents small_contents()
{
    SgContents c;
    c.mesh = test::random_triangles(21, 40, unit_box, 0.25f);
    BuildConfig config;
    config.leaf_size = 2;
    config.resolution_max = 8;
    c.grid = build_split_grid(c.mesh.view(), config);
    c.source_name = "small.obj";
    return c;
}

/// Runs the reader and returns the FormatError message, or fails the test.
std::string refusal(const std::vector<std::uint8_t>& bytes, const std::string& name = "hostile.sg",
                    const SgReadOptions& options = {})
{
    try {
        (void)read_sg_bytes(bytes, name, options);
    } catch (const FormatError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "wrong exception type: " << e.what();
        return {};
    }
    ADD_FAILURE() << "the damaged file was accepted";
    return {};
}

/// What every refusal must look like: one line, starting with the file name.
void expect_well_formed(const std::string& message, const std::string& name)
{
    EXPECT_EQ(message.rfind(name + ": ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

class SgHostile : public ::testing::Test {
protected:
    void SetUp() override
    {
        contents_ = small_contents();
        ASSERT_GT(contents_.grid.nodes.size(), 2u);
        ASSERT_TRUE(contents_.grid.root.is_inner());
        bytes_ = encode_sg(contents_);
        ASSERT_EQ(read_sg_bytes(bytes_, "ok.sg"), contents_) << "the unmodified file must load";
    }
    SgContents contents_;
    std::vector<std::uint8_t> bytes_;
};

TEST_F(SgHostile, EveryTruncationIsRefused)
{
    for (std::size_t size = 0; size < bytes_.size(); ++size) {
        const std::vector<std::uint8_t> cut(bytes_.begin(),
                                            bytes_.begin() + static_cast<std::ptrdiff_t>(size));
        SCOPED_TRACE("truncated to " + std::to_string(size) + " bytes");
        // With and without checksums: the size checks alone must catch it.
        expect_well_formed(refusal(cut, "cut.sg"), "cut.sg");
        expect_well_formed(refusal(cut, "cut.sg", no_checksums), "cut.sg");
    }
}

TEST_F(SgHostile, TruncatedFileOnDiskNamesThePathAndSaysTruncated)
{
    test::ScratchDir dir;
    const auto path = dir / "cut.sg";
    test::write_bytes(path, std::vector<std::uint8_t>(bytes_.begin(), bytes_.end() - 100));
    try {
        (void)read_sg_file(path);
        FAIL() << "accepted";
    } catch (const FormatError& e) {
        const std::string m = e.what();
        expect_well_formed(m, path.string());
        EXPECT_NE(m.find("truncated"), std::string::npos) << m;
        EXPECT_NE(m.find("at byte offset 32"), std::string::npos) << m;
        EXPECT_NE(m.find("expected " + std::to_string(bytes_.size()) + " bytes"), std::string::npos)
            << m;
        EXPECT_NE(m.find("found " + std::to_string(bytes_.size() - 100) + " bytes"),
                  std::string::npos)
            << m;
    }
    // read_sg_info compares the header with the real size too.
    EXPECT_THROW((void)read_sg_info(path), FormatError);
}

TEST_F(SgHostile, AppendedBytesAreRefused)
{
    std::vector<std::uint8_t> longer = bytes_;
    longer.push_back(0);
    EXPECT_NE(refusal(longer, "long.sg").find("longer than its header says"), std::string::npos);
}

TEST_F(SgHostile, EveryFlippedByteIsRefusedWhenChecksumsAreOn)
{
    // Header and table are under the header CRC, sections under their own CRCs, padding
    // must be zero: no single byte can change unnoticed.
    for (std::size_t i = 0; i < bytes_.size(); ++i) {
        for (const std::uint8_t mask : {std::uint8_t{0x01}, std::uint8_t{0x80}}) {
            std::vector<std::uint8_t> bad = bytes_;
            bad[i] ^= mask;
            SCOPED_TRACE("byte " + std::to_string(i) + " ^ " + std::to_string(mask));
            expect_well_formed(refusal(bad, "flip.sg"), "flip.sg");
        }
    }
}

TEST_F(SgHostile, AFlippedByteInEachSectionNamesThatSection)
{
    for (std::size_t s = 0; s < 7; ++s) {
        SCOPED_TRACE(tags[s]);
        const std::size_t at = offset_of(bytes_, static_cast<Section>(s));
        std::vector<std::uint8_t> bad = bytes_;
        bad[at] ^= 0x10;
        const std::string m = refusal(bad);
        EXPECT_NE(m.find(std::string("section ") + tags[s] + " checksum mismatch"), std::string::npos)
            << m;
        EXPECT_NE(m.find("at byte offset " + std::to_string(at)), std::string::npos) << m;
    }
}

TEST_F(SgHostile, FlippedHeaderAndTableBytesFailTheHeaderChecksum)
{
    // A field whose change is still self-consistent (the recorded CRC of a section) is
    // caught by the header CRC.
    for (const std::size_t at : {std::size_t{28}, entry_at(vert) + 4, entry_at(tref) + 4}) {
        std::vector<std::uint8_t> bad = bytes_;
        bad[at] ^= 0x02;
        const std::string m = refusal(bad);
        EXPECT_NE(m.find("header or section table checksum mismatch (at byte offset 28"),
                  std::string::npos)
            << m;
    }
}

TEST_F(SgHostile, EveryFlippedByteWithoutChecksumsNeverCrashes)
{
    // Checksums off exposes the structural checks: every outcome must be a FormatError or a
    // grid that passes the core's invariant check (a changed vertex coordinate, say).
    std::size_t refused = 0;
    for (std::size_t i = 0; i < bytes_.size(); ++i) {
        for (const std::uint8_t mask : {std::uint8_t{0x01}, std::uint8_t{0x40}, std::uint8_t{0xFF}}) {
            std::vector<std::uint8_t> bad = bytes_;
            bad[i] ^= mask;
            try {
                const SgContents c = read_sg_bytes(bad, "fuzz.sg", no_checksums);
                check_invariants(c.grid);
                check_mesh(c.mesh.view());
            } catch (const FormatError& e) {
                ++refused;
                expect_well_formed(e.what(), "fuzz.sg");
            }
        }
    }
    EXPECT_GT(refused, 0u);
}

TEST_F(SgHostile, EveryHeaderByteChangeIsRefusedWithoutChecksums)
{
    // Every header byte but the CRC itself has exactly one valid value in version 5.
    for (std::size_t i = 0; i < 80; ++i) {
        if (i >= 28 && i < 32) continue;
        std::vector<std::uint8_t> bad = bytes_;
        bad[i] ^= 0x04;
        SCOPED_TRACE("byte " + std::to_string(i));
        expect_well_formed(refusal(bad, "h.sg", no_checksums), "h.sg");
    }
}

TEST_F(SgHostile, NewerVersionIsRefusedNamingTheVersion)
{
    std::vector<std::uint8_t> newer = bytes_;
    store_le<std::uint32_t>(newer, 8, 6);
    EXPECT_EQ(refusal(newer, "new.sg"), "new.sg: format version 6 is newer than this reader's 5");
    store_le<std::uint32_t>(newer, 8, 4000000000u);
    EXPECT_EQ(refusal(newer, "new.sg"),
              "new.sg: format version 4000000000 is newer than this reader's 5");
    // Version 1 stored 8-byte cells, version 2 a one-cell node's cell in CELL, version 3 one
    // kind of inner cell, version 4 4-byte references: refused with a way out.
    std::vector<std::uint8_t> older = bytes_;
    store_le<std::uint32_t>(older, 8, 1);
    EXPECT_EQ(refusal(older, "old.sg"),
              "old.sg: format version 1 is no longer read (its cells are 8 bytes, version 5's "
              "are 4): build the file again with sg-build");
    store_le<std::uint32_t>(older, 8, 2);
    EXPECT_EQ(refusal(older, "old.sg"),
              "old.sg: format version 2 is no longer read (it keeps a one-cell node's cell in "
              "CELL, version 5 in the node's record): build the file again with sg-build");
    store_le<std::uint32_t>(older, 8, 3);
    EXPECT_EQ(refusal(older, "old.sg"),
              "old.sg: format version 3 is no longer read (its inner cells do not say whether "
              "their child has one cell, version 5's do): build the file again with sg-build");
    store_le<std::uint32_t>(older, 8, 4);
    EXPECT_EQ(refusal(older, "old.sg"),
              "old.sg: format version 4 is no longer read (its triangle references are 4 bytes "
              "each, version 5 packs a leaf's into 16-bit words): build the file again with "
              "sg-build");

    test::ScratchDir dir;
    store_le<std::uint32_t>(newer, 8, 7);
    test::write_bytes(dir / "v7.sg", newer);
    try {
        (void)read_sg_file(dir / "v7.sg");
        FAIL() << "accepted";
    } catch (const FormatError& e) {
        EXPECT_EQ(std::string(e.what()),
                  (dir / "v7.sg").string() + ": format version 7 is newer than this reader's 5");
    }
    EXPECT_THROW((void)read_sg_info(dir / "v7.sg"), FormatError);
}

TEST_F(SgHostile, BadMagicAndTextModeDamage)
{
    const std::vector<std::uint8_t> text(64, 'x');
    EXPECT_NE(refusal(text, "t.sg").find("not a .sg file: bad magic (at byte offset 0, expected 89 53 "
                                         "47 46 0D 0A 1A 0A, found 78 78"),
              std::string::npos);
    // CR LF -> LF, as a text-mode transfer on Windows would do.
    std::vector<std::uint8_t> mangled = bytes_;
    mangled.erase(mangled.begin() + 4);
    EXPECT_NE(refusal(mangled, "m.sg").find("text mode"), std::string::npos);
    // Wrong endianness marker as a big-endian writer would leave it.
    std::vector<std::uint8_t> big = bytes_;
    store_le<std::uint32_t>(big, 12, 0x04030201u);
    EXPECT_NE(refusal(big, "b.sg").find("big-endian"), std::string::npos);
}

TEST_F(SgHostile, RecordSizeChangesAreRefusedNamingTheRecord)
{
    std::vector<std::uint8_t> bad = bytes_;
    store_le<std::uint32_t>(bad, 56, 20);
    EXPECT_EQ(refusal(bad, "r.sg", no_checksums),
              "r.sg: node record size (at byte offset 56, expected 16, found 20)");
    bad = bytes_;
    store_le<std::uint32_t>(bad, conf_at + 84, 9);
    EXPECT_EQ(refusal(bad, "r.sg", no_checksums),
              "r.sg: CONF build_flags has unknown bits set (at byte offset " +
                  std::to_string(conf_at + 84) + ", expected bits 0-2 only, found 0x00000009)");
    bad = bytes_;
    store_le<std::uint32_t>(bad, conf_at + 40, 2);
    EXPECT_EQ(refusal(bad, "r.sg", no_checksums),
              "r.sg: CONF stop_by_cost is not a boolean (at byte offset " +
                  std::to_string(conf_at + 40) + ", expected 0 or 1, found 2)");
}

TEST_F(SgHostile, HugeCountsAreRefusedWithoutAllocating)
{
    const std::size_t budget = 4 * bytes_.size();
    struct Forgery {
        Section section;
        std::uint64_t count;
        std::uint64_t bytes;
    };
    const std::uint64_t vert_bytes = load_le<std::uint64_t>(bytes_, entry_at(vert) + 16);
    const std::vector<Forgery> forgeries{
        {vert, std::uint64_t{1} << 40, std::uint64_t{12} << 40},  // consistent but huge
        {tris, std::numeric_limits<std::uint64_t>::max(), 12},
        {node, std::uint64_t{1} << 62, std::uint64_t{1} << 63},
        // count * 12 wraps around 2^64 to exactly the real size (12 * 2^62 = 3 * 2^64): a
        // reader that multiplies instead of dividing would accept it.
        {vert, vert_bytes / 12 + (std::uint64_t{1} << 62), vert_bytes},
        {cell, 5, std::numeric_limits<std::uint64_t>::max() - 7},
        {tref, 3, std::numeric_limits<std::uint64_t>::max()},
    };
    for (const Forgery& forgery : forgeries) {
        SCOPED_TRACE(std::string(tags[forgery.section]) + " count " + std::to_string(forgery.count));
        std::vector<std::uint8_t> bad = bytes_;
        store_le(bad, entry_at(forgery.section) + 16, forgery.bytes);
        store_le(bad, entry_at(forgery.section) + 24, forgery.count);
        std::string message;
        const std::size_t largest = largest_allocation([&] {
            message = refusal(bad, "huge.sg", no_checksums);
        });
        expect_well_formed(message, "huge.sg");
        EXPECT_LE(largest, budget) << message;
    }
}

TEST_F(SgHostile, HugeCountInAFileOnDiskStaysWithinFourTimesTheFileSize)
{
    test::ScratchDir dir;
    std::vector<std::uint8_t> bad = bytes_;
    store_le(bad, entry_at(tref) + 24, std::uint64_t{1} << 61);
    store_le(bad, entry_at(tref) + 16, std::uint64_t{1} << 63);
    test::write_bytes(dir / "huge.sg", bad);
    const std::size_t largest = largest_allocation([&] {
        EXPECT_THROW((void)read_sg_file(dir / "huge.sg", no_checksums), FormatError);
    });
    EXPECT_LE(largest, 4 * bad.size());
}

TEST_F(SgHostile, SectionsOutsideTheFileOrOverlappingAreRefused)
{
    {
        std::vector<std::uint8_t> bad = bytes_;
        store_le<std::uint64_t>(bad, entry_at(cell) + 8, offset_of(bytes_, node));
        EXPECT_NE(refusal(bad, "o.sg", no_checksums).find("section CELL overlaps"),
                  std::string::npos);
    }
    {
        std::vector<std::uint8_t> bad = bytes_;
        store_le<std::uint64_t>(bad, entry_at(tref) + 8, std::uint64_t{1} << 60);
        EXPECT_NE(refusal(bad, "o.sg", no_checksums).find("section TREF extends past the end"),
                  std::string::npos);
    }
    {
        std::vector<std::uint8_t> bad = bytes_;
        store_le<std::uint64_t>(bad, entry_at(vert) + 8, offset_of(bytes_, vert) + 8);
        const std::string m = refusal(bad, "o.sg", no_checksums);
        EXPECT_NE(m.find("gap before section VERT"), std::string::npos) << m;
    }
    {
        std::vector<std::uint8_t> bad = bytes_;
        store_le<std::uint64_t>(bad, entry_at(vert) + 8, offset_of(bytes_, vert) + 4);
        EXPECT_NE(refusal(bad, "o.sg", no_checksums).find("not 8-byte aligned"),
                  std::string::npos);
    }
    {
        std::vector<std::uint8_t> bad = bytes_;
        std::memcpy(bad.data() + entry_at(node), "EDON", 4);
        const std::string m = refusal(bad, "o.sg", no_checksums);
        EXPECT_NE(m.find("wrong tag (at byte offset " + std::to_string(entry_at(node)) +
                         ", expected \"NODE\", found \"EDON\")"),
                  std::string::npos)
            << m;
    }
}

/// Re-encodes a corrupted copy of the contents: the checksums are then valid, so only the
/// semantic checks stand between the reader and the bad index.
class SgHostileIndex : public SgHostile {
protected:
    template <class Corrupt>
    std::string refusal_of(Corrupt corrupt, const SgReadOptions& options = {})
    {
        SgContents bad = contents_;
        corrupt(bad);
        const std::string m = refusal(encode_sg(bad), "index.sg", options);
        expect_well_formed(m, "index.sg");
        return m;
    }
};

TEST_F(SgHostileIndex, VertexIndexOutOfRange)
{
    const std::string m = refusal_of([](SgContents& c) {
        c.mesh.triangles[3].v[1] = static_cast<std::uint32_t>(c.mesh.vertices.size());
    });
    EXPECT_NE(m.find("TRIS section"), std::string::npos) << m;
}

TEST_F(SgHostileIndex, NanVertexOfATriangle)
{
    (void)refusal_of([](SgContents& c) {
        c.mesh.vertices[c.mesh.triangles[0].v[0]].y = std::numeric_limits<float>::quiet_NaN();
    });
}

TEST_F(SgHostileIndex, TriangleReferenceOutOfRange)
{
    // The first leaf's head names the triangle one past the last (its flags kept).
    const std::string message = refusal_of([](SgContents& c) {
        const CellRef* leaf = test::first_leaf_cell(c.grid);
        ASSERT_NE(leaf, nullptr);
        test::set_leaf_head(c.grid, leaf->first_word(), c.grid.triangle_count);
    });
    EXPECT_NE(message.find("names triangle"), std::string::npos) << message;
}

TEST_F(SgHostileIndex, ChildNodeOutOfRange)
{
    (void)refusal_of([](SgContents& c) {
        for (CellRef& cell : c.grid.cells)
            if (cell.is_inner()) {
                cell = CellRef::make_inner(static_cast<std::uint32_t>(c.grid.nodes.size()), 2);
                return;
            }
        FAIL() << "no inner cell";
    });
}

TEST_F(SgHostileIndex, OneCellNodeHoldingABadCell)
{
    // A one-cell node keeps its cell in its NODE record: a child past the array (either inner
    // kind), a word of the empty kind with an index.
    for (const std::uint32_t bad : {2u, 3u, 0u}) {
        (void)refusal_of([&](SgContents& c) {
            for (GridNode& node : c.grid.nodes)
                if (node.resolution() == 1) {
                    const auto past = static_cast<std::uint32_t>(c.grid.nodes.size());
                    node.set_only_cell(CellRef::from_raw((past << 2) | bad));
                    return;
                }
            FAIL() << "no one-cell node";
        });
    }
}

TEST_F(SgHostileIndex, CellPointingBackToTheRootMakesACycle)
{
    (void)refusal_of([](SgContents& c) {
        for (CellRef& cell : c.grid.cells)
            if (cell.is_inner()) {
                cell = CellRef::make_inner(0, c.grid.nodes[0].resolution());
                return;
            }
    });
}

TEST_F(SgHostileIndex, LeafPastTheEndOfTheWordArray)
{
    (void)refusal_of([](SgContents& c) {
        for (CellRef& cell : c.grid.cells)
            if (cell.is_leaf()) {
                cell = CellRef::make_leaf(static_cast<std::uint32_t>(c.grid.leaf_words.size()));
                return;
            }
    });
}

TEST_F(SgHostileIndex, NodeCellRangePastTheCellArray)
{
    (void)refusal_of([](SgContents& c) {
        // The last node of two or more cells: its last cell one past the array's end.
        auto node = std::find_if(c.grid.nodes.rbegin(), c.grid.nodes.rend(),
                                 [](const GridNode& n) { return n.resolution() >= 2; });
        ASSERT_NE(node, c.grid.nodes.rend());
        const GridNode n = *node;
        *node = GridNode::from_raw(
            n.lo, n.hi, static_cast<std::uint32_t>(c.grid.cells.size()) - n.resolution() + 1,
            n.axis_res_bits());
    });
}

TEST_F(SgHostileIndex, NanAndInvertedPlanesAndBadAxis)
{
    const float nan = std::numeric_limits<float>::quiet_NaN();
    (void)refusal_of([&](SgContents& c) {
        const GridNode& n = c.grid.nodes[1];
        c.grid.nodes[1] = GridNode::from_raw(nan, n.hi, n.cells_bits(), n.axis_res_bits());
    });
    (void)refusal_of([&](SgContents& c) {
        const GridNode& n = c.grid.nodes[1];
        c.grid.nodes[1] = GridNode::from_raw(n.hi + 1.0f, n.hi, n.cells_bits(), n.axis_res_bits());
    });
    (void)refusal_of([&](SgContents& c) {
        const GridNode& n = c.grid.nodes[0];
        c.grid.nodes[0] = GridNode::from_raw(n.lo, n.hi, n.cells_bits(), n.axis_res_bits() | 3u);
    });
    (void)refusal_of([&](SgContents& c) {
        const GridNode& n = c.grid.nodes[0];
        c.grid.nodes[0] = GridNode::from_raw(n.lo, n.hi, n.cells_bits(), n.axis_res_bits() & 3u);
    });
    (void)refusal_of([&](SgContents& c) { c.grid.root_box.upper.x = nan; });
}

TEST_F(SgHostileIndex, RootOutOfRange)
{
    (void)refusal_of([](SgContents& c) {
        c.grid.root = CellRef::make_inner(static_cast<std::uint32_t>(c.grid.nodes.size()), 2);
    });
}

TEST_F(SgHostileIndex, TriangleCountDisagreesWithTheMesh)
{
    const std::string m = refusal_of([](SgContents& c) { c.grid.triangle_count += 1; });
    EXPECT_NE(m.find("at byte offset " + std::to_string(conf_at + 48) + ", expected 40, found 41"),
              std::string::npos)
        << m;
}

TEST_F(SgHostileIndex, InvalidBuildConfig)
{
    const std::string m = refusal_of([](SgContents& c) { c.grid.config.leaf_size = 0; });
    EXPECT_NE(m.find("CONF section"), std::string::npos) << m;
    EXPECT_NE(m.find("leaf_size"), std::string::npos) << m;
    (void)refusal_of([](SgContents& c) {
        c.grid.config.resolution_sigma = std::numeric_limits<double>::quiet_NaN();
    });
}

TEST_F(SgHostileIndex, CoverageIsCheckedOnlyWhenAsked)
{
    // Moving a triangle across the whole root box keeps every index valid but leaves it
    // unreferenced by the leaves it now crosses.
    SgContents moved = contents_;
    const Triangle t = moved.mesh.triangles[0];
    const Aabb& box = moved.grid.root_box;
    moved.mesh.vertices[t.v[0]] = box.lower;
    moved.mesh.vertices[t.v[1]] = box.upper;
    moved.mesh.vertices[t.v[2]] = {box.lower.x, box.upper.y, box.lower.z};
    const std::vector<std::uint8_t> bytes = encode_sg(moved);
    EXPECT_EQ(read_sg_bytes(bytes, "moved.sg"), moved);
    const std::string m = refusal(bytes, "moved.sg", {.verify_checksums = true, .check_coverage = true});
    EXPECT_NE(m.find("does not cover"), std::string::npos) << m;
}

}  // namespace
}  // namespace sg
