#pragma once

// On-disk records of the .sg format, version 5. docs/FORMAT.md describes the same layout for
// readers in other languages; keep the two in step.
//
// The file is little-endian. The writer and reader copy these records to and from the byte
// buffer with std::memcpy, so each record below is trivially copyable, has no padding (its
// sizeof equals the sum of its fields) and only fixed-width fields. Padding and reserved bytes
// are always written as zero, so writing the same contents twice gives identical bytes.

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>

#include "splitgrid/build_config.hpp"
#include "splitgrid/grid_node.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/vec3.hpp"

namespace sg::detail {

static_assert(std::endian::native == std::endian::little,
              "the .sg reader and writer copy little-endian records as bytes: porting to a "
              "big-endian host needs byte swapping in sg_file.cpp and sg_file_read.cpp");

/// First 8 bytes of every .sg file. Like PNG's signature: 0x89 (not ASCII, so a 7-bit
/// channel corrupts it), "SGF", CR LF (changed by text-mode line-ending conversion), 0x1A
/// (stops a DOS `type`), LF (changed by LF -> CRLF conversion).
inline constexpr std::array<std::uint8_t, 8> sg_magic{0x89, 'S', 'G', 'F', '\r', '\n', 0x1A, '\n'};

/// Written as the uint32 0x01020304: a file written big-endian would show 01 02 03 04.
inline constexpr std::uint32_t sg_endian_marker = 0x01020304u;

/// Sections start at multiples of this many bytes from the start of the file.
inline constexpr std::uint64_t sg_section_alignment = 8;

/// The fixed header at byte offset 0 (80 bytes).
///
///   offset  size  field
///        0     8  magic                  sg_magic
///        8     4  format_version         sg_format_version (5)
///       12     4  endian_marker          0x01020304
///       16     4  header_bytes           sizeof(SgHeader) = 80
///       20     4  section_entry_bytes    sizeof(SgSectionEntry) = 32
///       24     4  section_count          7 in version 5
///       28     4  header_crc32           CRC-32 of the header (this field read as 0)
///                                        followed by the section table
///       32     8  file_bytes             size of the whole file
///       40     8  table_offset           where the section table starts (= header_bytes)
///       48     4  vertex_record_bytes    sizeof(Vec3f) = 12
///       52     4  triangle_record_bytes  sizeof(Triangle) = 12
///       56     4  node_record_bytes      sizeof(SgNodeRecord) = 16
///       60     4  cell_record_bytes      sizeof(SgCellRecord) = 4
///       64     4  leaf_word_bytes        sizeof(std::uint16_t) = 2 (leaf_words.hpp)
///       68     4  config_record_bytes    sizeof(SgConfigRecord) = 88
///       72     8  reserved               0
struct SgHeader {
    std::array<std::uint8_t, 8> magic;
    std::uint32_t format_version;
    std::uint32_t endian_marker;
    std::uint32_t header_bytes;
    std::uint32_t section_entry_bytes;
    std::uint32_t section_count;
    std::uint32_t header_crc32;
    std::uint64_t file_bytes;
    std::uint64_t table_offset;
    std::uint32_t vertex_record_bytes;
    std::uint32_t triangle_record_bytes;
    std::uint32_t node_record_bytes;
    std::uint32_t cell_record_bytes;
    std::uint32_t leaf_word_bytes;
    std::uint32_t config_record_bytes;
    std::uint64_t reserved;
};
static_assert(sizeof(SgHeader) == 80 && std::is_trivially_copyable_v<SgHeader> &&
                  std::has_unique_object_representations_v<SgHeader>,
              "SgHeader must be 80 bytes without padding: a field was added, removed or "
              "reordered; update docs/FORMAT.md and the format version");
static_assert(offsetof(SgHeader, header_crc32) == 28 && offsetof(SgHeader, file_bytes) == 32 &&
                  offsetof(SgHeader, reserved) == 72,
              "SgHeader field offsets differ from docs/FORMAT.md");

/// One entry of the section table (32 bytes). The table follows the header.
///
///   offset  size  field
///        0     4  tag      four ASCII characters, e.g. "VERT"
///        4     4  crc32    CRC-32 (zlib) of the section's `bytes` bytes
///        8     8  offset   from the start of the file, a multiple of 8
///       16     8  bytes    length of the section (without the padding that follows it)
///       24     8  count    records in the section; count * record size == bytes
struct SgSectionEntry {
    std::array<char, 4> tag;
    std::uint32_t crc32;
    std::uint64_t offset;
    std::uint64_t bytes;
    std::uint64_t count;
};
static_assert(sizeof(SgSectionEntry) == 32 && std::is_trivially_copyable_v<SgSectionEntry> &&
                  std::has_unique_object_representations_v<SgSectionEntry>,
              "SgSectionEntry must be 32 bytes without padding: update docs/FORMAT.md");

/// The single record of the CONF section (88 bytes): every BuildConfig field, then the root
/// of the grid.
///
///   offset  size  type     field
///        0     4  uint32   resolution_min
///        4     4  uint32   resolution_max
///        8     8  float64  resolution_sigma
///       16     4  uint32   leaf_size
///       20     4  uint32   max_depth
///       24     8  float64  no_progress_fraction
///       32     8  float64  min_cell_width
///       40     4  uint32   stop_by_cost (0 = false, 1 = true; nothing else)
///       44     4  uint32   threads
///       48     4  uint32   triangle_count (SplitGrid::triangle_count)
///       52    12  3 x f32  root box lower corner x, y, z
///       64    12  3 x f32  root box upper corner x, y, z
///       76     4  uint32   root cell         (the CellRef word, see grid_node.hpp)
///       80     4  uint32   reserved, 0
///       84     4  uint32   build_flags: bit 0 set = bounding_planes off, bit 1 set =
///                          clip_triangles off (0 = both on, the defaults, so files written
///                          before these options existed read unchanged), bit 2 set =
///                          bounding_nodes on (files written before it existed were built
///                          without them, and read so); other bits 0
struct SgConfigRecord {
    std::uint32_t resolution_min;
    std::uint32_t resolution_max;
    double resolution_sigma;
    std::uint32_t leaf_size;
    std::uint32_t max_depth;
    double no_progress_fraction;
    double min_cell_width;
    std::uint32_t stop_by_cost;
    std::uint32_t threads;
    std::uint32_t triangle_count;
    std::array<float, 3> root_lower;
    std::array<float, 3> root_upper;
    std::uint32_t root_cell;
    std::uint32_t reserved;
    std::uint32_t build_flags;
};

/// Bits of SgConfigRecord::build_flags.
inline constexpr std::uint32_t sg_flag_no_bounding_planes = 1u << 0;
inline constexpr std::uint32_t sg_flag_no_clip_triangles = 1u << 1;
inline constexpr std::uint32_t sg_flag_bounding_nodes = 1u << 2;
inline constexpr std::uint32_t sg_known_build_flags =
    sg_flag_no_bounding_planes | sg_flag_no_clip_triangles | sg_flag_bounding_nodes;

/// How a BuildConfig field is stored in SgConfigRecord.
enum class SgConfSlotKind {
    u32,          ///< a count as a uint32
    f64,          ///< a real as a float64
    boolean_u32,  ///< a switch as a uint32: 0 false, 1 true, anything else is refused
    cleared_bit,  ///< a switch as one bit of a uint32 flags word: set means false
    set_bit,      ///< a switch as one bit of a uint32 flags word: set means true
};

/// Where one BuildConfig field (named as in build_config_fields) lives in the CONF record.
struct SgConfSlot {
    std::string_view field;
    std::size_t offset;
    SgConfSlotKind kind;
    std::uint32_t bit = 0;  ///< for cleared_bit and set_bit
};

/// The CONF slot of every BuildConfig field: the file reader and writer iterate
/// build_config_fields and look each field up here. The layout above is the file format and
/// does not follow the table's order.
inline constexpr std::array<SgConfSlot, 12> sg_conf_slots{{
    {"resolution_min", offsetof(SgConfigRecord, resolution_min), SgConfSlotKind::u32},
    {"resolution_max", offsetof(SgConfigRecord, resolution_max), SgConfSlotKind::u32},
    {"resolution_sigma", offsetof(SgConfigRecord, resolution_sigma), SgConfSlotKind::f64},
    {"leaf_size", offsetof(SgConfigRecord, leaf_size), SgConfSlotKind::u32},
    {"max_depth", offsetof(SgConfigRecord, max_depth), SgConfSlotKind::u32},
    {"no_progress_fraction", offsetof(SgConfigRecord, no_progress_fraction),
     SgConfSlotKind::f64},
    {"min_cell_width", offsetof(SgConfigRecord, min_cell_width), SgConfSlotKind::f64},
    {"stop_by_cost", offsetof(SgConfigRecord, stop_by_cost), SgConfSlotKind::boolean_u32},
    {"bounding_planes", offsetof(SgConfigRecord, build_flags), SgConfSlotKind::cleared_bit,
     sg_flag_no_bounding_planes},
    {"clip_triangles", offsetof(SgConfigRecord, build_flags), SgConfSlotKind::cleared_bit,
     sg_flag_no_clip_triangles},
    {"bounding_nodes", offsetof(SgConfigRecord, build_flags), SgConfSlotKind::set_bit,
     sg_flag_bounding_nodes},
    {"threads", offsetof(SgConfigRecord, threads), SgConfSlotKind::u32},
}};

/// The slot of the field called `name`, or nullptr.
[[nodiscard]] constexpr const SgConfSlot* find_conf_slot(std::string_view name)
{
    for (const SgConfSlot& slot : sg_conf_slots)
        if (slot.field == name) return &slot;
    return nullptr;
}

/// Every field of build_config_fields has exactly one slot, of a kind that fits its type.
[[nodiscard]] consteval bool every_config_field_has_a_slot()
{
    if (sg_conf_slots.size() != build_config_fields.size()) return false;
    for (const BuildConfigField& field : build_config_fields) {
        std::size_t found = 0;
        for (const SgConfSlot& slot : sg_conf_slots) {
            if (slot.field != field.name) continue;
            ++found;
            const bool fits = slot.kind == SgConfSlotKind::u32    ? field.is_count()
                              : slot.kind == SgConfSlotKind::f64 ? !field.is_count() &&
                                                                       !field.is_switch()
                                                                 : field.is_switch();
            if (!fits) return false;
        }
        if (found != 1) return false;
    }
    return true;
}
static_assert(every_config_field_has_a_slot(),
              "a BuildConfig field has no CONF slot (or one of the wrong kind): extend "
              "SgConfigRecord and sg_conf_slots, docs/FORMAT.md and the format version");
static_assert(sizeof(SgConfigRecord) == 10 * 4 + 3 * 8 + 2 * 12 && sizeof(SgConfigRecord) == 88 &&
                  std::is_trivially_copyable_v<SgConfigRecord>,
              "SgConfigRecord must be 88 bytes without padding: a BuildConfig field was added? "
              "Extend the record, docs/FORMAT.md and the format version");
static_assert(offsetof(SgConfigRecord, stop_by_cost) == 40 &&
                  offsetof(SgConfigRecord, triangle_count) == 48 &&
                  offsetof(SgConfigRecord, root_cell) == 76 &&
                  offsetof(SgConfigRecord, build_flags) == 84,
              "SgConfigRecord field offsets differ from docs/FORMAT.md");

/// One inner node (16 bytes), field for field the GridNode layout of grid_node.hpp. Written
/// through GridNode's accessors rather than as a GridNode, because GridNode mixes public and
/// private members and so is not standard-layout: its member order is not guaranteed.
struct SgNodeRecord {
    float lo;
    float hi;
    std::uint32_t cells;  ///< resolution >= 2: first cell's index in CELL; 1: the cell's word
    std::uint32_t axis_res;
};
static_assert(sizeof(SgNodeRecord) == 2 * 4 + 2 * 4 && std::is_trivially_copyable_v<SgNodeRecord>,
              "SgNodeRecord must be 16 bytes without padding (grid_node.hpp layout)");

/// One cell (4 bytes), the CellRef word of grid_node.hpp: kind in bits 0-1 (0 empty, 1 leaf,
/// 2 inner with a child of two or more cells, 3 inner with a one-cell child), index in bits
/// 2-31. Version 1 stored 8 bytes (index, count).
struct SgCellRecord {
    std::uint32_t bits;
};
static_assert(sizeof(SgCellRecord) == 4 && std::is_trivially_copyable_v<SgCellRecord> &&
                  std::has_unique_object_representations_v<SgCellRecord>,
              "SgCellRecord must be 4 bytes without padding (grid_node.hpp layout)");

// Vertices, triangles and leaf words are stored as the core's own records.
static_assert(sizeof(Vec3f) == 12 && std::is_trivially_copyable_v<Vec3f>,
              "Vec3f is stored as three float32");
static_assert(sizeof(Triangle) == 12 && std::is_trivially_copyable_v<Triangle>,
              "Triangle is stored as three uint32");
static_assert(sizeof(decltype(SplitGrid::leaf_words)::value_type) == 2,
              "leaf words are stored as uint16 (leaf_words.hpp)");

/// The sections of a version-5 file, in file order.
enum class SgSection : std::size_t {
    config,
    name,
    vertices,
    triangles,
    nodes,
    cells,
    leaf_words,
};
inline constexpr std::size_t sg_section_count = 7;

/// Tag and record size of each section, indexed by SgSection.
struct SgSectionSpec {
    std::string_view tag;
    std::uint64_t record_bytes;
};
inline constexpr std::array<SgSectionSpec, sg_section_count> sg_section_specs{{
    {"CONF", sizeof(SgConfigRecord)},
    {"NAME", 1},  // UTF-8 bytes of the source mesh name, no terminator
    {"VERT", sizeof(Vec3f)},
    {"TRIS", sizeof(Triangle)},
    {"NODE", sizeof(SgNodeRecord)},
    {"CELL", sizeof(SgCellRecord)},
    {"TREF", sizeof(std::uint16_t)},  // the leaves' words (leaf_words.hpp)
}};

/// Where the first section starts: right after the header and the table (already aligned).
inline constexpr std::uint64_t sg_first_section_offset =
    sizeof(SgHeader) + sg_section_count * sizeof(SgSectionEntry);
static_assert(sg_first_section_offset % sg_section_alignment == 0);

[[nodiscard]] constexpr std::uint64_t align_up(std::uint64_t n) noexcept
{
    return (n + sg_section_alignment - 1) / sg_section_alignment * sg_section_alignment;
}

}  // namespace sg::detail
