// Writing .sg files: the encoder and the atomic write. Reading and checking is in
// sg_file_read.cpp; the record layouts are in sg_file_layout.hpp.

#include "splitgrid/formats/sg_file.hpp"

#include <array>
#include <cstdint>
#include <cstring>
#include <span>
#include <variant>

#include "checksum.hpp"
#include "sg_file_layout.hpp"
#include "splitgrid/formats/output_file.hpp"

namespace sg {
namespace {

using detail::SgSection;

/// Stores one BuildConfig field in its CONF slot (sg_conf_slots).
void store_field(const BuildConfig& config, const BuildConfigField& field,
                 detail::SgConfigRecord& record)
{
    const detail::SgConfSlot& slot = *detail::find_conf_slot(field.name);
    auto* const at = reinterpret_cast<unsigned char*>(&record) + slot.offset;
    switch (slot.kind) {
    case detail::SgConfSlotKind::u32: {
        const std::uint32_t value = config.*std::get<BuildConfigField::CountMember>(field.member);
        std::memcpy(at, &value, sizeof value);
        break;
    }
    case detail::SgConfSlotKind::f64: {
        const double value = config.*std::get<BuildConfigField::RealMember>(field.member);
        std::memcpy(at, &value, sizeof value);
        break;
    }
    case detail::SgConfSlotKind::boolean_u32: {
        const std::uint32_t value =
            config.*std::get<BuildConfigField::SwitchMember>(field.member) ? 1u : 0u;
        std::memcpy(at, &value, sizeof value);
        break;
    }
    case detail::SgConfSlotKind::cleared_bit:
    case detail::SgConfSlotKind::set_bit: {
        std::uint32_t word = 0;
        std::memcpy(&word, at, sizeof word);
        const bool on = config.*std::get<BuildConfigField::SwitchMember>(field.member);
        if (on == (slot.kind == detail::SgConfSlotKind::set_bit)) word |= slot.bit;
        std::memcpy(at, &word, sizeof word);
        break;
    }
    }
}

detail::SgConfigRecord make_config_record(const SplitGrid& grid)
{
    detail::SgConfigRecord r{};
    for (const BuildConfigField& field : build_config_fields) store_field(grid.config, field, r);
    r.triangle_count = grid.triangle_count;
    r.root_lower = {grid.root_box.lower.x, grid.root_box.lower.y, grid.root_box.lower.z};
    r.root_upper = {grid.root_box.upper.x, grid.root_box.upper.y, grid.root_box.upper.z};
    r.root_cell = grid.root.raw_bits();
    return r;
}

/// Byte position of each section, laid out one after the other from the end of the table,
/// each starting on an 8-byte boundary.
struct Layout {
    std::array<detail::SgSectionEntry, detail::sg_section_count> table{};
    std::uint64_t file_bytes = 0;
};

Layout plan_layout(const SgContents& contents)
{
    std::array<std::uint64_t, detail::sg_section_count> counts{};
    counts[static_cast<std::size_t>(SgSection::config)] = 1;
    counts[static_cast<std::size_t>(SgSection::name)] = contents.source_name.size();
    counts[static_cast<std::size_t>(SgSection::vertices)] = contents.mesh.vertices.size();
    counts[static_cast<std::size_t>(SgSection::triangles)] = contents.mesh.triangles.size();
    counts[static_cast<std::size_t>(SgSection::nodes)] = contents.grid.nodes.size();
    counts[static_cast<std::size_t>(SgSection::cells)] = contents.grid.cells.size();
    counts[static_cast<std::size_t>(SgSection::leaf_words)] = contents.grid.leaf_words.size();

    Layout layout;
    std::uint64_t offset = detail::sg_first_section_offset;
    for (std::size_t i = 0; i < detail::sg_section_count; ++i) {
        detail::SgSectionEntry& e = layout.table[i];
        std::memcpy(e.tag.data(), detail::sg_section_specs[i].tag.data(), e.tag.size());
        e.offset = offset;
        e.count = counts[i];
        e.bytes = counts[i] * detail::sg_section_specs[i].record_bytes;
        offset = detail::align_up(offset + e.bytes);
    }
    layout.file_bytes = offset;
    return layout;
}

/// Copies `count` records of trivially copyable type T to `out`.
template <class T>
void put_records(std::uint8_t* out, std::span<const T> records)
{
    if (!records.empty()) std::memcpy(out, records.data(), records.size_bytes());
}

detail::SgHeader make_header(std::uint64_t file_bytes)
{
    detail::SgHeader h{};
    h.magic = detail::sg_magic;
    h.format_version = sg_format_version;
    h.endian_marker = detail::sg_endian_marker;
    h.header_bytes = sizeof(detail::SgHeader);
    h.section_entry_bytes = sizeof(detail::SgSectionEntry);
    h.section_count = detail::sg_section_count;
    h.file_bytes = file_bytes;
    h.table_offset = sizeof(detail::SgHeader);
    h.vertex_record_bytes = sizeof(Vec3f);
    h.triangle_record_bytes = sizeof(Triangle);
    h.node_record_bytes = sizeof(detail::SgNodeRecord);
    h.cell_record_bytes = sizeof(detail::SgCellRecord);
    h.leaf_word_bytes = sizeof(std::uint16_t);
    h.config_record_bytes = sizeof(detail::SgConfigRecord);
    return h;
}

}  // namespace

std::vector<std::uint8_t> encode_sg(const SgContents& contents)
{
    Layout layout = plan_layout(contents);
    // Value-initialised: the gaps between sections and every reserved field are zero, which
    // makes the encoding a pure function of `contents`.
    std::vector<std::uint8_t> out(layout.file_bytes);
    auto section_start = [&](SgSection s) {
        return out.data() + layout.table[static_cast<std::size_t>(s)].offset;
    };

    const detail::SgConfigRecord config = make_config_record(contents.grid);
    std::memcpy(section_start(SgSection::config), &config, sizeof config);
    put_records(section_start(SgSection::name),
                std::span<const char>(contents.source_name.data(), contents.source_name.size()));
    put_records(section_start(SgSection::vertices), std::span<const Vec3f>(contents.mesh.vertices));
    put_records(section_start(SgSection::triangles),
                std::span<const Triangle>(contents.mesh.triangles));
    // Nodes and cells go through their accessors: see SgNodeRecord for why.
    std::uint8_t* node_out = section_start(SgSection::nodes);
    for (const GridNode& node : contents.grid.nodes) {
        const detail::SgNodeRecord r{node.lo, node.hi, node.cells_bits(), node.axis_res_bits()};
        std::memcpy(node_out, &r, sizeof r);
        node_out += sizeof r;
    }
    std::uint8_t* cell_out = section_start(SgSection::cells);
    for (const CellRef& cell : contents.grid.cells) {
        const detail::SgCellRecord r{cell.raw_bits()};
        std::memcpy(cell_out, &r, sizeof r);
        cell_out += sizeof r;
    }
    put_records(section_start(SgSection::leaf_words),
                std::span<const std::uint16_t>(contents.grid.leaf_words));

    for (detail::SgSectionEntry& e : layout.table) {
        e.crc32 = detail::crc32_of(std::span<const std::uint8_t>(
            out.data() + e.offset, static_cast<std::size_t>(e.bytes)));
    }
    std::uint8_t* table_out = out.data() + sizeof(detail::SgHeader);
    std::memcpy(table_out, layout.table.data(), sizeof layout.table);

    detail::SgHeader header = make_header(layout.file_bytes);
    header.header_crc32 = detail::sg_header_crc32(
        header, std::span<const std::uint8_t>(table_out, sizeof layout.table));
    std::memcpy(out.data(), &header, sizeof header);
    return out;
}

void write_sg_file(const std::filesystem::path& path, const SgContents& contents)
{
    OutputFile output(path);
    write_sg_file(output, contents);
}

void write_sg_file(OutputFile& output, const SgContents& contents)
{
    output.commit(encode_sg(contents));
}

}  // namespace sg
