// Row 11 of docs/ROBUSTNESS.md: hostile .sg files, beyond tests/formats/sg_file_hostile_test.cpp
// (every truncation and flipped byte refused in one line, forged sizes, out-of-range indices,
// cycles and NaN planes behind valid checksums):
// - every single bit of the header and the section table flipped, with checksums on and
//   off: refused with the message of the field that bit belongs to (docs/FORMAT.md's layout);
// - 10^4 files with one to four random bits flipped anywhere: refused in one line with
//   checksums on; with them off, refused or loaded into a grid that traces safely (and like
//   brute force when it still covers its mesh);
// - huge counts behind a valid header checksum (recomputed with zlib's CRC-32);
// - the memory a refused load takes: the peak of the bytes allocated while it runs, at most
//   4 times the file's size, for every truncation, every bit flip and every forgery.
// The memory probe replaces operator new of this test binary; sanitizer builds own operator
// new, so there the probe stays off and only the refusals are checked.

#include <gtest/gtest.h>

#include <malloc.h>
#include <zlib.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <random>
#include <string>

#include "formats/file_helpers.hpp"
#include "robustness_support.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/validate.hpp"
#include "support/random_scene.hpp"

// ---------------------------------------------------------------------------------------
// Memory probe: while active, the bytes held by allocations made since it started (as
// malloc_usable_size counts them, frees of older blocks subtracted) and their peak.
namespace {
std::atomic<bool> probe_on{false};
std::atomic<long long> probe_now{0};
std::atomic<long long> probe_peak{0};
}  // namespace

#if !defined(__SANITIZE_ADDRESS__)
constexpr bool memory_probe_works = true;
namespace {
void probe_add(long long bytes)
{
    const long long now = probe_now.fetch_add(bytes, std::memory_order_relaxed) + bytes;
    long long peak = probe_peak.load(std::memory_order_relaxed);
    while (now > peak && !probe_peak.compare_exchange_weak(peak, now)) {
    }
}
}  // namespace
void* operator new(std::size_t bytes)
{
    void* p = std::malloc(bytes == 0 ? 1 : bytes);
    if (p == nullptr) throw std::bad_alloc();
    if (probe_on.load(std::memory_order_relaxed))
        probe_add(static_cast<long long>(malloc_usable_size(p)));
    return p;
}
void* operator new[](std::size_t bytes) { return ::operator new(bytes); }
// GCC 12 cannot see that these replacements pair with the malloc in operator new above.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept
{
    if (p != nullptr && probe_on.load(std::memory_order_relaxed))
        probe_add(-static_cast<long long>(malloc_usable_size(p)));
    std::free(p);
}
void operator delete[](void* p) noexcept { ::operator delete(p); }
void operator delete(void* p, std::size_t) noexcept { ::operator delete(p); }
void operator delete[](void* p, std::size_t) noexcept { ::operator delete(p); }
#pragma GCC diagnostic pop
#else
constexpr bool memory_probe_works = false;
#endif

namespace sg::test {
namespace {

/// Runs `f` and returns the peak of the bytes it held allocated.
template <class F>
long long peak_bytes(const F& f)
{
    probe_now = 0;
    probe_peak = 0;
    probe_on = true;
    f();
    probe_on = false;
    return probe_peak;
}

constexpr SgReadOptions no_checksums{.verify_checksums = false, .check_coverage = false};
constexpr std::size_t table_at = 80;
constexpr std::size_t first_section = 80 + 7 * 32;
constexpr std::array<const char*, 7> tags{"CONF", "NAME", "VERT", "TRIS", "NODE", "CELL", "TREF"};

/// The message a damaged header byte must produce, from the layout of docs/FORMAT.md.
std::string header_field_message(std::size_t byte)
{
    if (byte < 8) return "bad magic";
    if (byte < 12) return "format version";
    if (byte < 16) return "endian";
    if (byte < 20) return "header size";
    if (byte < 24) return "section table entry size";
    if (byte < 28) return "section count";
    if (byte < 32) return "header or section table checksum mismatch";
    if (byte < 40) return "than its header says";
    if (byte < 48) return "section table offset";
    static const std::array<const char*, 6> records{"vertex record size", "triangle record size",
                                                    "node record size", "cell record size",
                                                    "leaf word size",
                                                    "config record size"};
    if (byte < 72) return records[(byte - 48) / 4];
    return "reserved header field is not zero";
}

/// The message a damaged section-table byte must produce without checksums: the entry's own
/// check (its tag, or offset, size and count, all named by the section), nothing for its CRC.
std::string table_field_message(std::size_t byte)
{
    const std::size_t entry = (byte - table_at) / 32, field = (byte - table_at) % 32;
    if (field < 4) return "section " + std::to_string(entry) + " has the wrong tag";
    if (field < 8) return "";  // the section's CRC: not read without checksums
    return std::string("section ") + tags[entry];
}

struct Refusal {
    bool refused = false;
    std::string message;
    long long peak = 0;
};

Refusal try_read(const std::vector<std::uint8_t>& bytes, const SgReadOptions& options,
                 SgContents* accepted = nullptr)
{
    Refusal r;
    r.peak = peak_bytes([&] {
        try {
            SgContents c = read_sg_bytes(bytes, "damaged.sg", options);
            if (accepted != nullptr) *accepted = std::move(c);
        } catch (const FormatError& e) {
            r.refused = true;
            r.message = e.what();
        }
    });
    return r;
}

// The largest peak of a refused load relative to the file size, for the test's summary.
double largest_share = 0.0;

void expect_one_line_refusal(const Refusal& r, std::size_t file_size, const std::string& what)
{
    largest_share = std::max(largest_share, double(r.peak) / double(file_size));
    ASSERT_TRUE(r.refused) << what << ": accepted";
    EXPECT_EQ(r.message.rfind("damaged.sg: ", 0), 0u) << what << ": " << r.message;
    EXPECT_EQ(r.message.find('\n'), std::string::npos) << what << ": " << r.message;
    if (memory_probe_works) {
        EXPECT_LE(r.peak, 4 * static_cast<long long>(file_size)) << what << ": " << r.message;
    }
}

class SgDamage : public ::testing::Test {
protected:
    void SetUp() override
    {
        contents_.mesh = random_triangles(121, 60, Aabb{{0, 0, 0}, {1, 1, 1}}, 0.25f);
        BuildConfig config;
        config.leaf_size = 2;
        config.resolution_max = 8;
        contents_.grid = build_split_grid(contents_.mesh.view(), config);
        contents_.source_name = "small.obj";
        bytes_ = encode_sg(contents_);
        ASSERT_EQ(read_sg_bytes(bytes_, "ok.sg"), contents_);
        ASSERT_GT(contents_.grid.nodes.size(), 2u);
        largest_share = 0.0;
    }
    void TearDown() override
    {
        if (memory_probe_works)
            std::printf("[ sg memory] largest peak of a refused load: %.2f times the file size "
                        "of %zu bytes\n",
                        largest_share, bytes_.size());
    }
    SgContents contents_;
    std::vector<std::uint8_t> bytes_;
};

TEST_F(SgDamage, EveryTruncationSaysTruncatedWithinFourTimesTheFileSize)
{
    for (std::size_t size = 0; size < bytes_.size(); ++size) {
        const std::vector<std::uint8_t> cut(bytes_.begin(),
                                            bytes_.begin() + static_cast<std::ptrdiff_t>(size));
        for (const SgReadOptions& options : {SgReadOptions{}, no_checksums}) {
            const Refusal r = try_read(cut, options);
            const std::string what = "cut to " + std::to_string(size) + " bytes";
            expect_one_line_refusal(r, bytes_.size(), what);
            EXPECT_NE(r.message.find("truncated"), std::string::npos) << what << ": " << r.message;
        }
    }
}

TEST_F(SgDamage, EveryBitOfTheHeaderAndTableIsRefusedNamingItsField)
{
    std::size_t flips = 0;
    for (std::size_t byte = 0; byte < first_section; ++byte)
        for (int bit = 0; bit < 8; ++bit) {
            std::vector<std::uint8_t> bad = bytes_;
            bad[byte] ^= static_cast<std::uint8_t>(1u << bit);
            const std::string what = "byte " + std::to_string(byte) + " bit " + std::to_string(bit);
            ++flips;
            // Checksums on: a header field's own check first, else the header checksum.
            const Refusal on = try_read(bad, {});
            expect_one_line_refusal(on, bad.size(), what);
            const std::string expected_on = byte < table_at
                                                ? header_field_message(byte)
                                                : "header or section table checksum mismatch";
            EXPECT_NE(on.message.find(expected_on), std::string::npos)
                << what << ": " << on.message;
            // Checksums off: the structural check of that field.
            if (byte >= 28 && byte < 32) continue;  // the header CRC is not read
            const std::string expected_off =
                byte < table_at ? header_field_message(byte) : table_field_message(byte);
            SgContents accepted;
            const Refusal off = try_read(bad, no_checksums, &accepted);
            if (expected_off.empty()) {
                EXPECT_FALSE(off.refused) << what << ": " << off.message;
                EXPECT_EQ(accepted, contents_) << what;
                continue;
            }
            expect_one_line_refusal(off, bad.size(), what);
            EXPECT_NE(off.message.find(expected_off), std::string::npos)
                << what << ": " << off.message;
        }
    EXPECT_EQ(flips, 8 * first_section);
}

TEST_F(SgDamage, RandomBitFlipsAnywhereAreRefusedOrLoadSafely)
{
    std::mt19937 rng(122);
    std::uniform_int_distribution<std::size_t> where(0, bytes_.size() - 1);
    std::size_t refused_off = 0, loaded = 0, loaded_and_covering = 0;
    const std::size_t files = 10000;
    const ScratchDir dir;
    double largest_file_share = 0.0;
    for (std::size_t f = 0; f < files; ++f) {
        std::vector<std::uint8_t> bad = bytes_;
        const int bits = 1 + static_cast<int>(rng() % 4);
        for (int b = 0; b < bits; ++b)
            bad[where(rng)] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
        if (bad == bytes_) continue;  // two flips of one bit cancelled
        const std::string what = "file " + std::to_string(f);
        expect_one_line_refusal(try_read(bad, {}), bad.size(), what);
        if (f % 50 == 0) {
            // From disk too: the reader's own copy of the file counts against the bound.
            write_bytes(dir.path() / "damaged.sg", bad);
            Refusal r;
            r.peak = peak_bytes([&] {
                try {
                    (void)read_sg_file(dir.path() / "damaged.sg");
                } catch (const FormatError& e) {
                    r.refused = true;
                    r.message = e.what();
                }
            });
            ASSERT_TRUE(r.refused) << what;
            if (memory_probe_works) {
                EXPECT_LE(r.peak, 4 * static_cast<long long>(bad.size()))
                    << what << ": " << r.message;
            }
            largest_file_share = std::max(largest_file_share, double(r.peak) / double(bad.size()));
        }

        SgContents c;
        const Refusal off = try_read(bad, no_checksums, &c);
        if (off.refused) {
            ++refused_off;
            expect_one_line_refusal(off, bad.size(), what);
            continue;
        }
        // Loaded: the reader ran check_mesh and check_invariants, so tracing must be safe;
        // where the grid still covers its (possibly changed) mesh, it must be exact.
        ++loaded;
        const std::vector<Ray> rays =
            random_rays(static_cast<std::uint32_t>(f), 20, Aabb{{-1, -1, -1}, {2, 2, 2}});
        for (const Ray& r : rays) {
            (void)intersect(c.grid, c.mesh.view(), r);
            (void)occluded(c.grid, c.mesh.view(), r);
        }
        try {
            check_coverage(c.grid, c.mesh.view());
        } catch (const FormatError&) {
            continue;
        }
        ++loaded_and_covering;
        const OracleReport report = compare_with_brute_force(c.grid, c.mesh.view(), rays);
        EXPECT_EQ(report.closest_disagreements + report.any_hit_disagreements, 0u)
            << what << ": " << report.first_failure;
    }
    std::printf("[ sg flips ] %zu files, 1 to 4 random bits flipped: all refused with checksums; "
                "without them %zu refused, %zu loaded (%zu still covering their mesh); read from "
                "disk, the largest peak was %.2f times the file size\n",
                files, refused_off, loaded, loaded_and_covering, largest_file_share);
    EXPECT_GT(refused_off, files / 2);
}

// Writes the header CRC as a writer would: CRC-32 of the header with its CRC field read as
// zero, then of the section table (docs/FORMAT.md), with zlib.
void reseal_header(std::vector<std::uint8_t>& bytes)
{
    store_le<std::uint32_t>(bytes, 28, 0);
    const uLong crc = ::crc32(0L, bytes.data(), static_cast<uInt>(first_section));
    store_le<std::uint32_t>(bytes, 28, static_cast<std::uint32_t>(crc));
}

TEST_F(SgDamage, HugeCountsBehindAValidHeaderChecksumAreRefusedWithoutAllocating)
{
    const std::vector<std::uint8_t> resealed = [&] {
        std::vector<std::uint8_t> b = bytes_;
        reseal_header(b);
        return b;
    }();
    ASSERT_EQ(resealed, bytes_) << "reseal_header must reproduce the writer's checksum";
    struct Forgery {
        std::size_t section;
        std::uint64_t bytes;
        std::uint64_t count;
        const char* message;
    };
    const std::uint64_t big = std::uint64_t{1} << 40;
    for (const Forgery& f : std::vector<Forgery>{
             {2, 12 * big, big, "section VERT extends past the end of the file"},
             {3, 12, std::uint64_t{1} << 62, "section TRIS record count does not match"},
             {4, 16 * big, big, "section NODE extends past the end of the file"},
             {6, 4, ~std::uint64_t{0}, "section TREF record count does not match"},
             {0, 88, 2, "section CONF"}}) {
        std::vector<std::uint8_t> bad = bytes_;
        const std::size_t entry = table_at + 32 * f.section;
        store_le(bad, entry + 16, f.bytes);
        store_le(bad, entry + 24, f.count);
        reseal_header(bad);
        const Refusal r = try_read(bad, {});
        expect_one_line_refusal(r, bad.size(), tags[f.section]);
        EXPECT_NE(r.message.find(f.message), std::string::npos) << r.message;
        EXPECT_EQ(r.message.find("checksum"), std::string::npos) << r.message;
    }
}

TEST_F(SgDamage, ValidChecksumsWithBadIndicesCyclesAndNanPlanesStayWithinTheMemoryBound)
{
    // The forgeries of sg_file_hostile_test.cpp's SgHostileIndex, for the memory bound.
    std::vector<SgContents> forged(5, contents_);
    forged[0].mesh.triangles[3].v[1] = static_cast<std::uint32_t>(contents_.mesh.vertices.size());
    const CellRef* leaf = test::first_leaf_cell(forged[1].grid);
    ASSERT_NE(leaf, nullptr);  // its head names the triangle past the last, flags kept
    test::set_leaf_head(forged[1].grid, leaf->first_word(), contents_.grid.triangle_count);
    for (CellRef& cell : forged[2].grid.cells)
        if (cell.is_inner()) {
            cell = CellRef::make_inner(0, contents_.grid.nodes[0].resolution());  // a cycle
            break;
        }
    const GridNode& n = contents_.grid.nodes[1];
    forged[3].grid.nodes[1] = GridNode::from_raw(std::numeric_limits<float>::quiet_NaN(), n.hi,
                                                 n.cells_bits(), n.axis_res_bits());
    forged[4].grid.root =
        CellRef::make_inner(static_cast<std::uint32_t>(contents_.grid.nodes.size()), 2);
    for (std::size_t k = 0; k < forged.size(); ++k) {
        const std::vector<std::uint8_t> bytes = encode_sg(forged[k]);
        const Refusal r = try_read(bytes, {});
        expect_one_line_refusal(r, bytes.size(), "forgery " + std::to_string(k));
        EXPECT_EQ(r.message.find("checksum"), std::string::npos) << r.message;
    }
    // The probe must see a successful load's memory, or the bound proves nothing.
    const Refusal ok = try_read(bytes_, {});
    EXPECT_FALSE(ok.refused);
    if (memory_probe_works) {
        EXPECT_GT(ok.peak, static_cast<long long>(bytes_.size()) / 2);
    }
}

}  // namespace
}  // namespace sg::test
