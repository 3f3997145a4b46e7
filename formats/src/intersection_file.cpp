// Hit count and hit list files (docs/FORMAT.md, sections 3.2 and 3.3): the answers of the
// queries that look at every hit along a ray, for scripts (numpy) and for comparing tracers.

#include "splitgrid/formats/intersection_file.hpp"

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "file_bytes.hpp"
#include "record_file.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/output_file.hpp"

namespace sg {
namespace {

using detail::load;
using detail::magic_bytes;

constexpr std::string_view count_magic = "SGCNT001";
constexpr std::string_view list_magic = "SGALL001";

/// Magic, ray count, hit count.
constexpr std::size_t list_header_bytes = magic_bytes + 2 * sizeof(std::uint64_t);

/// One hit of a hit list on disk (20 bytes): ray id, triangle id, then float32 t, u, v.
struct ListedHitRecord {
    std::uint32_t ray;
    std::uint32_t triangle;
    float t;
    float u;
    float v;
};
static_assert(sizeof(ListedHitRecord) == 5 * 4 && std::is_trivially_copyable_v<ListedHitRecord>,
              "ListedHitRecord must be 2 uint32 and 3 packed float32 (docs/FORMAT.md)");

[[noreturn]] void refuse(const std::filesystem::path& path, const std::string& what,
                         std::size_t offset)
{
    throw FormatError(path.string() + ": " + what + " (at byte offset " + std::to_string(offset) +
                      ")");
}

/// Whether hit a comes strictly before hit b in a ray's list: by t, then triangle id.
bool listed_before(const Hit& a, const Hit& b) noexcept
{
    return a.t < b.t || (a.t == b.t && a.triangle < b.triangle);
}

}  // namespace

void write_hit_count_file(OutputFile& output, std::span<const std::int32_t> counts)
{
    output.commit(detail::encode_records<std::int32_t>(count_magic, counts.size(),
                                                       [&](std::size_t i) { return counts[i]; }));
}

void write_hit_count_file(const std::filesystem::path& path, std::span<const std::int32_t> counts)
{
    OutputFile output(path);
    write_hit_count_file(output, counts);
}

std::vector<std::int32_t> read_hit_count_file(const std::filesystem::path& path)
{
    const detail::RecordFile file =
        detail::read_record_file(path, count_magic, "hit count", sizeof(std::int32_t));
    std::vector<std::int32_t> counts(file.count);
    for (std::size_t i = 0; i < file.count; ++i) {
        counts[i] = file.record<std::int32_t>(i);
        if (counts[i] < 0)
            refuse(path, "ray " + std::to_string(i) + " has a negative hit count " +
                             std::to_string(counts[i]),
                   detail::RecordFile::offset_of(i, sizeof(std::int32_t)));
    }
    return counts;
}

void write_hit_list_file(OutputFile& output, const IntersectionList& list)
{
    const std::size_t rays = list.ray_count();
    const std::size_t hits = list.hits.size();
    const std::size_t splits_offset = list_header_bytes;
    const std::size_t hits_offset = splits_offset + (rays + 1) * sizeof(std::uint64_t);
    std::vector<std::uint8_t> bytes(hits_offset + hits * sizeof(ListedHitRecord));
    std::memcpy(bytes.data(), list_magic.data(), magic_bytes);
    const std::uint64_t counts[2] = {rays, hits};
    std::memcpy(bytes.data() + magic_bytes, counts, sizeof counts);
    std::memcpy(bytes.data() + splits_offset, list.ray_splits.data(),
                (rays + 1) * sizeof(std::uint64_t));
    for (std::size_t i = 0; i < hits; ++i) {
        const Hit& h = list.hits[i];
        const ListedHitRecord r{list.ray_ids[i], h.triangle, h.t, h.u, h.v};
        std::memcpy(bytes.data() + hits_offset + i * sizeof r, &r, sizeof r);
    }
    output.commit(bytes);
}

void write_hit_list_file(const std::filesystem::path& path, const IntersectionList& list)
{
    OutputFile output(path);
    write_hit_list_file(output, list);
}

IntersectionList read_hit_list_file(const std::filesystem::path& path)
{
    const std::vector<std::uint8_t> bytes = detail::read_file_bytes(path);
    detail::check_magic_and_header(bytes, path, list_magic, "hit list", list_header_bytes);
    const auto rays = load<std::uint64_t>(bytes, magic_bytes);
    const auto hits = load<std::uint64_t>(bytes, magic_bytes + 8);

    // Sizes by division, so that forged counts can neither overflow nor allocate.
    const std::uint64_t payload = bytes.size() - list_header_bytes;
    const std::uint64_t split_room = payload / sizeof(std::uint64_t);
    const bool splits_fit = rays < split_room;  // R + 1 splits
    const std::uint64_t rest = splits_fit ? payload - (rays + 1) * sizeof(std::uint64_t) : 0;
    const std::uint64_t hit_room = rest / sizeof(ListedHitRecord);
    if (!splits_fit || hits != hit_room || rest % sizeof(ListedHitRecord) != 0)
        throw FormatError(path.string() + ": " +
                          (!splits_fit || hits > hit_room ? "truncated: " : "") +
                          "the header counts " + std::to_string(rays) + " rays and " +
                          std::to_string(hits) + " hits (at byte offset " +
                          std::to_string(magic_bytes) + ", expected " +
                          std::to_string(list_header_bytes) + " + 8 x (" + std::to_string(rays) +
                          " + 1) + " + std::to_string(hits) + " x " +
                          std::to_string(sizeof(ListedHitRecord)) + " bytes, found " +
                          std::to_string(bytes.size()) + " bytes)");

    IntersectionList list;
    list.ray_splits.resize(static_cast<std::size_t>(rays) + 1);
    std::memcpy(list.ray_splits.data(), bytes.data() + list_header_bytes,
                list.ray_splits.size() * sizeof(std::uint64_t));
    if (list.ray_splits.front() != 0)
        refuse(path, "ray_splits[0] is " + std::to_string(list.ray_splits.front()) +
                         ", expected 0",
               list_header_bytes);
    for (std::size_t k = 0; k < rays; ++k)
        if (list.ray_splits[k + 1] < list.ray_splits[k])
            refuse(path, "ray_splits[" + std::to_string(k + 1) + "] = " +
                             std::to_string(list.ray_splits[k + 1]) + " is below ray_splits[" +
                             std::to_string(k) + "] = " + std::to_string(list.ray_splits[k]),
                   list_header_bytes + (k + 1) * sizeof(std::uint64_t));
    if (list.ray_splits.back() != hits)
        refuse(path, "ray_splits[" + std::to_string(rays) + "] is " +
                         std::to_string(list.ray_splits.back()) + ", expected the hit count " +
                         std::to_string(hits),
               list_header_bytes + static_cast<std::size_t>(rays) * sizeof(std::uint64_t));

    const std::size_t hits_offset = list_header_bytes + list.ray_splits.size() * 8;
    list.ray_ids.resize(static_cast<std::size_t>(hits));
    list.hits.resize(static_cast<std::size_t>(hits));
    std::size_t ray = 0;
    for (std::size_t i = 0; i < hits; ++i) {
        const std::size_t offset = hits_offset + i * sizeof(ListedHitRecord);
        const auto r = load<ListedHitRecord>(bytes, offset);
        while (list.ray_splits[ray + 1] <= i) ++ray;
        if (r.ray != ray)
            refuse(path, "hit " + std::to_string(i) + " names ray " + std::to_string(r.ray) +
                             ", but ray_splits put it in ray " + std::to_string(ray),
                   offset);
        list.ray_ids[i] = r.ray;
        list.hits[i] = Hit{r.t, r.triangle, r.u, r.v};
        if (i > list.ray_splits[ray] && !listed_before(list.hits[i - 1], list.hits[i]))
            refuse(path, "hit " + std::to_string(i) + " of ray " + std::to_string(ray) +
                             " does not follow the one before it by t, then triangle id",
                   offset);
    }
    return list;
}

}  // namespace sg
