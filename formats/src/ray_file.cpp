// Ray and hit files (docs/FORMAT.md): 8 magic bytes, a little-endian uint64 count, then
// fixed-size little-endian records. Simple on purpose, so that scripts can write rays and
// read hits with a few lines of numpy.

#include "splitgrid/formats/ray_file.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "file_bytes.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/output_file.hpp"

namespace sg {
namespace {

static_assert(std::endian::native == std::endian::little,
              "ray files are little-endian records copied as bytes: add byte swapping to port "
              "to a big-endian host");

/// One ray on disk (32 bytes): origin xyz, direction xyz, t_min, t_max, all float32.
struct RayRecord {
    std::array<float, 3> origin;
    std::array<float, 3> direction;
    float t_min;
    float t_max;
};
static_assert(sizeof(RayRecord) == 8 * 4 && std::is_trivially_copyable_v<RayRecord>,
              "RayRecord must be 8 packed float32 (docs/FORMAT.md)");

/// One hit on disk (16 bytes): triangle id (0xFFFFFFFF = miss), then float32 t, u, v.
struct HitRecord {
    std::uint32_t triangle;
    float t;
    float u;
    float v;
};
static_assert(sizeof(HitRecord) == 4 * 4 && std::is_trivially_copyable_v<HitRecord>,
              "HitRecord must be a uint32 and 3 packed float32 (docs/FORMAT.md)");

constexpr std::string_view ray_magic = "SGRAY001";
constexpr std::string_view hit_magic = "SGHIT001";
constexpr std::size_t magic_bytes = 8;
constexpr std::size_t prefix_bytes = magic_bytes + sizeof(std::uint64_t);

/// Magic, count, then make_record(i) for each i, straight into the output buffer.
template <class Record, class MakeRecord>
std::vector<std::uint8_t> encode(std::string_view magic, std::size_t count,
                                 MakeRecord make_record)
{
    std::vector<std::uint8_t> out(prefix_bytes + count * sizeof(Record));
    std::memcpy(out.data(), magic.data(), magic_bytes);
    const std::uint64_t count64 = count;
    std::memcpy(out.data() + magic_bytes, &count64, sizeof count64);
    for (std::size_t i = 0; i < count; ++i) {
        const Record r = make_record(i);
        std::memcpy(out.data() + prefix_bytes + i * sizeof(Record), &r, sizeof r);
    }
    return out;
}

/// The checked bytes of a ray or hit file.
struct CheckedFile {
    std::vector<std::uint8_t> bytes;
    std::size_t count = 0;

    /// Record i, copied out of the byte buffer (records are not aligned for direct access).
    template <class Record>
    [[nodiscard]] Record record(std::size_t i) const
    {
        Record r{};
        std::memcpy(&r, bytes.data() + prefix_bytes + i * sizeof(Record), sizeof r);
        return r;
    }
};

/// Reads a file and checks magic, count and size. The count is checked against the file
/// size by division, so a forged count can neither overflow nor cause a huge allocation.
template <class Record>
CheckedFile read_checked(const std::filesystem::path& path, std::string_view magic,
                         const std::string& kind)
{
    CheckedFile file{detail::read_file_bytes(path), 0};
    const std::vector<std::uint8_t>& bytes = file.bytes;
    const std::string name = path.string();
    const std::size_t checked = std::min(bytes.size(), magic_bytes);
    // An empty vector may have a null data(), which memcmp must not see even for 0 bytes.
    if (checked > 0 && std::memcmp(bytes.data(), magic.data(), checked) != 0)
        throw FormatError(name + ": not a " + kind + " file: bad magic (at byte offset 0, expected \"" +
                          std::string(magic) + "\")");
    if (bytes.size() < prefix_bytes)
        throw FormatError(name + ": truncated: the file is shorter than its header (at byte offset " +
                          std::to_string(bytes.size()) + ", expected at least " +
                          std::to_string(prefix_bytes) + " bytes, found " +
                          std::to_string(bytes.size()) + ")");
    std::uint64_t count = 0;
    std::memcpy(&count, bytes.data() + magic_bytes, sizeof count);
    const std::uint64_t payload = bytes.size() - prefix_bytes;
    const std::uint64_t room = payload / sizeof(Record);
    if (count != room || payload % sizeof(Record) != 0) {
        // "16 + N x 32" rather than the product, which overflows for a forged count.
        throw FormatError(name + ": " + (count > room ? "truncated: " : "") + "the header counts " +
                          std::to_string(count) + " " + kind + "s, the file size fits " +
                          std::to_string(room) + " (at byte offset " +
                          std::to_string(magic_bytes) + ", expected " +
                          std::to_string(prefix_bytes) + " + " + std::to_string(count) + " x " +
                          std::to_string(sizeof(Record)) + " bytes, found " +
                          std::to_string(bytes.size()) + " bytes)");
    }
    file.count = static_cast<std::size_t>(count);
    return file;
}

}  // namespace

std::vector<Ray> read_ray_file(const std::filesystem::path& path)
{
    const CheckedFile file = read_checked<RayRecord>(path, ray_magic, "ray");
    std::vector<Ray> rays;
    rays.reserve(file.count);
    for (std::size_t i = 0; i < file.count; ++i) {
        const auto r = file.record<RayRecord>(i);
        rays.push_back(Ray{{r.origin[0], r.origin[1], r.origin[2]},
                           {r.direction[0], r.direction[1], r.direction[2]}, r.t_min, r.t_max});
    }
    return rays;
}

void write_ray_file(const std::filesystem::path& path, const std::vector<Ray>& rays)
{
    OutputFile output(path);
    write_ray_file(output, rays);
}

void write_ray_file(OutputFile& output, const std::vector<Ray>& rays)
{
    output.commit(encode<RayRecord>(ray_magic, rays.size(), [&](std::size_t i) {
        const Ray& r = rays[i];
        return RayRecord{{r.origin.x, r.origin.y, r.origin.z},
                         {r.direction.x, r.direction.y, r.direction.z}, r.t_min, r.t_max};
    }));
}

void write_hit_file(const std::filesystem::path& path, const std::vector<Hit>& hits)
{
    OutputFile output(path);
    write_hit_file(output, hits);
}

void write_hit_file(OutputFile& output, const std::vector<Hit>& hits)
{
    output.commit(encode<HitRecord>(hit_magic, hits.size(), [&](std::size_t i) {
        const Hit& h = hits[i];
        return HitRecord{h.triangle, h.t, h.u, h.v};
    }));
}

std::vector<Hit> read_hit_file(const std::filesystem::path& path)
{
    const CheckedFile file = read_checked<HitRecord>(path, hit_magic, "hit");
    std::vector<Hit> hits;
    hits.reserve(file.count);
    for (std::size_t i = 0; i < file.count; ++i) {
        const auto r = file.record<HitRecord>(i);
        hits.push_back(Hit{r.t, r.triangle, r.u, r.v});
    }
    return hits;
}

}  // namespace sg
