// Reading and checking .sg files (docs/FORMAT.md, "What a reader checks").
//
// The file is treated as hostile: every size, offset and count is checked against the real
// file size, with overflow-free arithmetic, before anything is allocated, so a forged count
// can neither crash the reader nor make it allocate more than the file's own size. Only then
// are the records copied out and the grid handed to the core's validators.

#include "splitgrid/formats/sg_file.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <span>
#include <string_view>
#include <variant>

#include "checksum.hpp"
#include "file_bytes.hpp"
#include "sg_file_layout.hpp"
#include "splitgrid/build_config.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/validate.hpp"

namespace sg {
namespace {

using detail::SgSection;

std::string hex32(std::uint32_t value)
{
    char text[16];
    std::snprintf(text, sizeof text, "0x%08X", value);
    return text;
}

/// Up to 8 bytes as "89 53 47 ..." for magic-number messages.
std::string hex_bytes(std::span<const std::uint8_t> bytes)
{
    std::string text;
    for (const std::uint8_t b : bytes) {
        char part[4];
        std::snprintf(part, sizeof part, "%02X", b);
        if (!text.empty()) text += ' ';
        text += part;
    }
    return text.empty() ? "nothing" : text;
}

/// A tag as text, printable ASCII kept, anything else as \xNN (the file may be hostile and
/// messages must stay on one line).
std::string quoted_tag(std::span<const char> tag)
{
    std::string text = "\"";
    for (const char c : tag) {
        const auto u = static_cast<unsigned char>(c);
        if (u >= 0x20 && u < 0x7F && c != '"' && c != '\\') {
            text += c;
        } else {
            char part[8];
            std::snprintf(part, sizeof part, "\\x%02X", u);
            text += part;
        }
    }
    return text + "\"";
}

/// Messages of the core's validators, made safe to embed in a one-line message.
std::string one_line(std::string text)
{
    for (char& c : text)
        if (c == '\n' || c == '\r') c = ' ';
    return text;
}

/// Header and section-table checks plus decoding, over a byte buffer that holds at least
/// the header and table (read_sg_info) or the whole file (read_sg_bytes).
class SgReader {
public:
    SgReader(std::span<const std::uint8_t> bytes, std::uint64_t file_bytes, std::string name)
        : bytes_(bytes), file_bytes_(file_bytes), name_(std::move(name))
    {
    }

    /// Checks everything in the header and the table. Reads only the first
    /// sg_first_section_offset bytes.
    void check_header_and_table(bool verify_header_crc);
    /// Checks the zero padding between sections and each section's CRC-32. Needs the whole
    /// file in `bytes`.
    void check_sections(bool verify_checksums) const;
    /// Copies the records out and runs the semantic checks. Needs the whole file.
    [[nodiscard]] SgContents decode(const SgReadOptions& options) const;
    [[nodiscard]] SgFileInfo info() const;

private:
    [[noreturn]] void fail(const std::string& what) const
    {
        throw FormatError(name_ + ": " + what);
    }
    [[noreturn]] void fail_at(const std::string& what, std::uint64_t offset,
                              const std::string& expected, const std::string& found) const
    {
        fail(what + " (at byte offset " + std::to_string(offset) + ", expected " + expected +
             ", found " + found + ")");
    }
    void expect_u32(const char* what, std::uint64_t offset, std::uint32_t found,
                    std::uint64_t expected) const
    {
        if (found != expected)
            fail_at(what, offset, std::to_string(expected), std::to_string(found));
    }

    void check_magic_and_version() const;
    /// Copies one BuildConfig field out of its CONF slot (sg_conf_slots), refusing a switch
    /// stored as anything but 0 or 1.
    void load_field(const detail::SgConfigRecord& record, std::uint64_t conf_at,
                    const BuildConfigField& field, BuildConfig& config) const;
    void check_table_entry(std::size_t index, std::uint64_t& previous_end) const;
    [[nodiscard]] const detail::SgSectionEntry& entry(SgSection s) const
    {
        return table_[static_cast<std::size_t>(s)];
    }
    [[nodiscard]] std::span<const std::uint8_t> section_bytes(SgSection s) const
    {
        const detail::SgSectionEntry& e = entry(s);
        return bytes_.subspan(static_cast<std::size_t>(e.offset), static_cast<std::size_t>(e.bytes));
    }
    template <class T>
    [[nodiscard]] std::vector<T> copy_records(SgSection s) const
    {
        const std::span<const std::uint8_t> raw = section_bytes(s);
        std::vector<T> out(raw.size() / sizeof(T));
        if (!raw.empty()) std::memcpy(out.data(), raw.data(), raw.size());
        return out;
    }
    [[nodiscard]] std::string section_label(SgSection s) const
    {
        return std::string(detail::sg_section_specs[static_cast<std::size_t>(s)].tag) +
               " section (at byte offset " + std::to_string(entry(s).offset) + ")";
    }

    std::span<const std::uint8_t> bytes_;
    std::uint64_t file_bytes_;
    std::string name_;
    detail::SgHeader header_{};
    std::array<detail::SgSectionEntry, detail::sg_section_count> table_{};
};

void SgReader::check_magic_and_version() const
{
    const std::size_t magic_bytes = std::min(bytes_.size(), detail::sg_magic.size());
    const std::span<const std::uint8_t> found = bytes_.first(magic_bytes);
    if (!std::equal(found.begin(), found.end(), detail::sg_magic.begin())) {
        // "\x89SGF" intact but the rest changed is the signature of a text-mode transfer.
        const bool looks_text_mangled =
            magic_bytes == detail::sg_magic.size() &&
            std::equal(found.begin(), found.begin() + 4, detail::sg_magic.begin());
        fail_at(looks_text_mangled
                    ? "bad magic: the line-ending bytes changed, the file was probably "
                      "transferred in text mode"
                    : "not a .sg file: bad magic",
                0, hex_bytes(detail::sg_magic), hex_bytes(found));
    }
    constexpr std::size_t version_end = offsetof(detail::SgHeader, format_version) + 4;
    if (bytes_.size() >= version_end) {
        std::uint32_t version = 0;
        std::memcpy(&version, bytes_.data() + offsetof(detail::SgHeader, format_version), 4);
        // The version is checked before anything else in the header: a newer version may
        // lay out the rest of the header differently.
        if (version > sg_format_version)
            fail("format version " + std::to_string(version) + " is newer than this reader's " +
                 std::to_string(sg_format_version));
        if (version == 0)
            fail_at("invalid format version", offsetof(detail::SgHeader, format_version),
                    std::to_string(sg_format_version), "0");
        if (version == 1)
            fail("format version 1 is no longer read (its cells are 8 bytes, version 5's are "
                 "4): build the file again with sg-build");
        if (version == 2)
            fail("format version 2 is no longer read (it keeps a one-cell node's cell in CELL, "
                 "version 5 in the node's record): build the file again with sg-build");
        if (version == 3)
            fail("format version 3 is no longer read (its inner cells do not say whether their "
                 "child has one cell, version 5's do): build the file again with sg-build");
        if (version == 4)
            fail("format version 4 is no longer read (its triangle references are 4 bytes each, "
                 "version 5 packs a leaf's into 16-bit words): build the file again with "
                 "sg-build");
    }
}

void SgReader::check_header_and_table(bool verify_header_crc)
{
    using detail::SgHeader;
    check_magic_and_version();
    if (bytes_.size() < sizeof(SgHeader))
        fail_at("truncated: the file is shorter than the header", bytes_.size(),
                "at least " + std::to_string(sizeof(SgHeader)) + " bytes",
                std::to_string(bytes_.size()) + " bytes");
    std::memcpy(&header_, bytes_.data(), sizeof header_);

    if (header_.endian_marker != detail::sg_endian_marker) {
        fail_at(header_.endian_marker == 0x04030201u
                    ? "written on a big-endian machine, which this reader does not support"
                    : "bad endianness marker",
                offsetof(SgHeader, endian_marker), hex32(detail::sg_endian_marker),
                hex32(header_.endian_marker));
    }
    expect_u32("header size", offsetof(SgHeader, header_bytes), header_.header_bytes,
               sizeof(SgHeader));
    expect_u32("section table entry size", offsetof(SgHeader, section_entry_bytes),
               header_.section_entry_bytes, sizeof(detail::SgSectionEntry));
    expect_u32("section count", offsetof(SgHeader, section_count), header_.section_count,
               detail::sg_section_count);
    expect_u32("vertex record size", offsetof(SgHeader, vertex_record_bytes),
               header_.vertex_record_bytes, sizeof(Vec3f));
    expect_u32("triangle record size", offsetof(SgHeader, triangle_record_bytes),
               header_.triangle_record_bytes, sizeof(Triangle));
    expect_u32("node record size", offsetof(SgHeader, node_record_bytes),
               header_.node_record_bytes, sizeof(detail::SgNodeRecord));
    expect_u32("cell record size", offsetof(SgHeader, cell_record_bytes),
               header_.cell_record_bytes, sizeof(detail::SgCellRecord));
    expect_u32("leaf word size", offsetof(SgHeader, leaf_word_bytes), header_.leaf_word_bytes,
               sizeof(std::uint16_t));
    expect_u32("config record size", offsetof(SgHeader, config_record_bytes),
               header_.config_record_bytes, sizeof(detail::SgConfigRecord));
    if (header_.table_offset != sizeof(SgHeader))
        fail_at("section table offset", offsetof(SgHeader, table_offset),
                std::to_string(sizeof(SgHeader)), std::to_string(header_.table_offset));
    if (header_.reserved != 0)
        fail_at("reserved header field is not zero", offsetof(SgHeader, reserved), "0",
                std::to_string(header_.reserved));

    if (header_.file_bytes != file_bytes_) {
        fail_at(file_bytes_ < header_.file_bytes ? "truncated: the file is shorter than its header says"
                                                 : "the file is longer than its header says",
                offsetof(SgHeader, file_bytes), std::to_string(header_.file_bytes) + " bytes",
                std::to_string(file_bytes_) + " bytes");
    }
    if (file_bytes_ < detail::sg_first_section_offset || bytes_.size() < detail::sg_first_section_offset)
        fail_at("truncated: the file is shorter than the header and section table",
                bytes_.size(), "at least " + std::to_string(detail::sg_first_section_offset) + " bytes",
                std::to_string(bytes_.size()) + " bytes");

    const std::span<const std::uint8_t> table_bytes =
        bytes_.subspan(sizeof(SgHeader), sizeof table_);
    if (verify_header_crc) {
        const std::uint32_t computed = detail::sg_header_crc32(header_, table_bytes);
        if (computed != header_.header_crc32)
            fail_at("header or section table checksum mismatch", offsetof(SgHeader, header_crc32),
                    hex32(header_.header_crc32), hex32(computed));
    }
    std::memcpy(table_.data(), table_bytes.data(), sizeof table_);

    std::uint64_t previous_end = detail::sg_first_section_offset;
    for (std::size_t i = 0; i < detail::sg_section_count; ++i) check_table_entry(i, previous_end);
    if (detail::align_up(previous_end) != file_bytes_)
        fail_at("the file does not end after the last section", offsetof(SgHeader, file_bytes),
                std::to_string(detail::align_up(previous_end)) + " bytes",
                std::to_string(file_bytes_) + " bytes");
}

void SgReader::check_table_entry(std::size_t index, std::uint64_t& previous_end) const
{
    const detail::SgSectionEntry& e = table_[index];
    const detail::SgSectionSpec& spec = detail::sg_section_specs[index];
    const std::uint64_t at = sizeof(detail::SgHeader) + index * sizeof(detail::SgSectionEntry);
    const std::string tag(spec.tag);

    if (std::string_view(e.tag.data(), e.tag.size()) != spec.tag)
        fail_at("section " + std::to_string(index) + " has the wrong tag",
                at + offsetof(detail::SgSectionEntry, tag), quoted_tag(spec.tag),
                quoted_tag(e.tag));
    const std::uint64_t offset_at = at + offsetof(detail::SgSectionEntry, offset);
    const std::uint64_t bytes_at = at + offsetof(detail::SgSectionEntry, bytes);
    const std::uint64_t count_at = at + offsetof(detail::SgSectionEntry, count);
    if (e.offset % detail::sg_section_alignment != 0)
        fail_at("section " + tag + " is not 8-byte aligned", offset_at, "a multiple of 8",
                std::to_string(e.offset));
    if (e.offset < previous_end)
        fail_at("section " + tag + " overlaps the header, table or previous section", offset_at,
                "at least " + std::to_string(previous_end), std::to_string(e.offset));
    // Written as two comparisons so that offset + bytes cannot wrap around.
    if (e.offset > file_bytes_ || e.bytes > file_bytes_ - e.offset)
        fail_at("section " + tag + " extends past the end of the file", bytes_at,
                "at most " + std::to_string(file_bytes_ - std::min(e.offset, file_bytes_)) +
                    " bytes",
                std::to_string(e.bytes) + " bytes");
    // count * record_bytes == bytes, tested by division so a forged count cannot overflow.
    if (e.bytes % spec.record_bytes != 0 || e.count != e.bytes / spec.record_bytes)
        fail_at("section " + tag + " record count does not match its size of " +
                    std::to_string(e.bytes) + " bytes at " + std::to_string(spec.record_bytes) +
                    " bytes per record",
                count_at, std::to_string(e.bytes / spec.record_bytes), std::to_string(e.count));
    if (static_cast<SgSection>(index) == SgSection::config && e.count != 1)
        fail_at("section CONF must hold exactly one record", count_at, "1",
                std::to_string(e.count));
    // Sections follow each other with only the zero padding to the next 8-byte boundary.
    if (e.offset != detail::align_up(previous_end))
        fail_at("gap before section " + tag, offset_at,
                std::to_string(detail::align_up(previous_end)), std::to_string(e.offset));
    previous_end = e.offset + e.bytes;
}

void SgReader::check_sections(bool verify_checksums) const
{
    std::uint64_t previous_end = detail::sg_first_section_offset;
    auto check_zero = [&](std::uint64_t from, std::uint64_t to) {
        for (std::uint64_t i = from; i < to; ++i) {
            if (bytes_[static_cast<std::size_t>(i)] != 0)
                fail_at("padding byte is not zero", i, "0",
                        std::to_string(bytes_[static_cast<std::size_t>(i)]));
        }
    };
    for (std::size_t i = 0; i < detail::sg_section_count; ++i) {
        const detail::SgSectionEntry& e = table_[i];
        check_zero(previous_end, e.offset);
        previous_end = e.offset + e.bytes;
        if (!verify_checksums) continue;
        const std::uint32_t computed = detail::crc32_of(section_bytes(static_cast<SgSection>(i)));
        if (computed != e.crc32)
            fail_at("section " + std::string(detail::sg_section_specs[i].tag) +
                        " checksum mismatch",
                    e.offset, hex32(e.crc32), hex32(computed));
    }
    check_zero(previous_end, file_bytes_);
}

void SgReader::load_field(const detail::SgConfigRecord& record, std::uint64_t conf_at,
                          const BuildConfigField& field, BuildConfig& config) const
{
    const detail::SgConfSlot& slot = *detail::find_conf_slot(field.name);
    const auto* const at = reinterpret_cast<const unsigned char*>(&record) + slot.offset;
    std::uint32_t word = 0;
    switch (slot.kind) {
    case detail::SgConfSlotKind::u32:
        std::memcpy(&word, at, sizeof word);
        config.*std::get<BuildConfigField::CountMember>(field.member) = word;
        return;
    case detail::SgConfSlotKind::f64: {
        double value = 0.0;
        std::memcpy(&value, at, sizeof value);
        config.*std::get<BuildConfigField::RealMember>(field.member) = value;
        return;
    }
    case detail::SgConfSlotKind::boolean_u32:
        std::memcpy(&word, at, sizeof word);
        if (word > 1)
            fail_at("CONF " + std::string(field.name) + " is not a boolean", conf_at + slot.offset,
                    "0 or 1", std::to_string(word));
        config.*std::get<BuildConfigField::SwitchMember>(field.member) = word == 1;
        return;
    case detail::SgConfSlotKind::cleared_bit:
    case detail::SgConfSlotKind::set_bit:
        std::memcpy(&word, at, sizeof word);
        config.*std::get<BuildConfigField::SwitchMember>(field.member) =
            ((word & slot.bit) != 0) == (slot.kind == detail::SgConfSlotKind::set_bit);
        return;
    }
}

SgContents SgReader::decode(const SgReadOptions& options) const
{
    SgContents contents;
    detail::SgConfigRecord config{};
    std::memcpy(&config, section_bytes(SgSection::config).data(), sizeof config);

    const std::uint64_t conf_at = entry(SgSection::config).offset;
    for (const BuildConfigField& field : build_config_fields)
        load_field(config, conf_at, field, contents.grid.config);
    if (config.reserved != 0)
        fail_at("reserved CONF field is not zero",
                conf_at + offsetof(detail::SgConfigRecord, reserved), "0",
                std::to_string(config.reserved));
    if ((config.build_flags & ~detail::sg_known_build_flags) != 0)
        fail_at("CONF build_flags has unknown bits set",
                conf_at + offsetof(detail::SgConfigRecord, build_flags), "bits 0-2 only",
                hex32(config.build_flags));
    try {
        validate(contents.grid.config);
    } catch (const Error& e) {
        fail(section_label(SgSection::config) + ": " + one_line(e.what()));
    }

    const std::uint64_t triangles = entry(SgSection::triangles).count;
    if (config.triangle_count != triangles)
        fail_at("the grid's triangle count does not match section TRIS",
                conf_at + offsetof(detail::SgConfigRecord, triangle_count),
                std::to_string(triangles), std::to_string(config.triangle_count));
    contents.grid.triangle_count = config.triangle_count;
    contents.grid.root_box.lower = {config.root_lower[0], config.root_lower[1], config.root_lower[2]};
    contents.grid.root_box.upper = {config.root_upper[0], config.root_upper[1], config.root_upper[2]};
    contents.grid.root = CellRef::from_raw(config.root_cell);

    const std::span<const std::uint8_t> name = section_bytes(SgSection::name);
    contents.source_name.assign(name.begin(), name.end());
    contents.mesh.vertices = copy_records<Vec3f>(SgSection::vertices);
    contents.mesh.triangles = copy_records<Triangle>(SgSection::triangles);
    contents.grid.leaf_words = copy_records<std::uint16_t>(SgSection::leaf_words);

    const auto node_records = section_bytes(SgSection::nodes);
    contents.grid.nodes.reserve(node_records.size() / sizeof(detail::SgNodeRecord));
    for (std::size_t at = 0; at < node_records.size(); at += sizeof(detail::SgNodeRecord)) {
        detail::SgNodeRecord r{};
        std::memcpy(&r, node_records.data() + at, sizeof r);
        contents.grid.nodes.push_back(GridNode::from_raw(r.lo, r.hi, r.cells, r.axis_res));
    }
    const auto cell_records = section_bytes(SgSection::cells);
    contents.grid.cells.reserve(cell_records.size() / sizeof(detail::SgCellRecord));
    for (std::size_t at = 0; at < cell_records.size(); at += sizeof(detail::SgCellRecord)) {
        detail::SgCellRecord r{};
        std::memcpy(&r, cell_records.data() + at, sizeof r);
        contents.grid.cells.push_back(CellRef::from_raw(r.bits));
    }

    try {
        check_mesh(contents.mesh.view());
    } catch (const Error& e) {
        fail("mesh: " + one_line(e.what()) + " (VERT section at byte offset " +
             std::to_string(entry(SgSection::vertices).offset) + ", TRIS section at byte offset " +
             std::to_string(entry(SgSection::triangles).offset) + ")");
    }
    try {
        check_invariants(contents.grid);
    } catch (const Error& e) {
        fail("grid: " + one_line(e.what()));
    }
    if (options.check_coverage) {
        try {
            check_coverage(contents.grid, contents.mesh.view());
        } catch (const Error& e) {
            fail("grid does not cover the mesh: " + one_line(e.what()));
        }
    }
    return contents;
}

SgFileInfo SgReader::info() const
{
    SgFileInfo info;
    info.format_version = header_.format_version;
    info.file_bytes = header_.file_bytes;
    for (const detail::SgSectionEntry& e : table_)
        info.sections.push_back({std::string(e.tag.data(), e.tag.size()), e.offset, e.bytes,
                                 e.count, e.crc32});
    return info;
}

}  // namespace

SgContents read_sg_bytes(const std::vector<std::uint8_t>& bytes, const std::string& name,
                         const SgReadOptions& options)
{
    SgReader reader(bytes, bytes.size(), name);
    reader.check_header_and_table(options.verify_checksums);
    reader.check_sections(options.verify_checksums);
    return reader.decode(options);
}

SgContents read_sg_file(const std::filesystem::path& path, const SgReadOptions& options)
{
    // The whole file is read first (memory: its size), then decoded (about its size again):
    // a refused load never holds more than twice the file's size.
    return read_sg_bytes(detail::read_file_bytes(path), path.string(), options);
}

SgFileInfo read_sg_info(const std::filesystem::path& path)
{
    const detail::FilePrefix prefix =
        detail::read_file_prefix(path, detail::sg_first_section_offset);
    SgReader reader(prefix.bytes, prefix.file_bytes, path.string());
    reader.check_header_and_table(true);
    return reader.info();
}

}  // namespace sg
