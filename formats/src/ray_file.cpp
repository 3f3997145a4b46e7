// Ray and hit files (docs/FORMAT.md): 8 magic bytes, a little-endian uint64 count, then
// fixed-size little-endian records (record_file.hpp). Simple on purpose, so that scripts can
// write rays and read hits with a few lines of numpy.

#include "splitgrid/formats/ray_file.hpp"

#include <array>
#include <cstdint>
#include <string_view>
#include <type_traits>
#include <vector>

#include "record_file.hpp"
#include "splitgrid/formats/output_file.hpp"

namespace sg {
namespace {

using detail::RecordFile;

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

}  // namespace

std::vector<Ray> read_ray_file(const std::filesystem::path& path)
{
    const RecordFile file = detail::read_record_file(path, ray_magic, "ray", sizeof(RayRecord));
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
    output.commit(detail::encode_records<RayRecord>(ray_magic, rays.size(), [&](std::size_t i) {
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
    output.commit(detail::encode_records<HitRecord>(hit_magic, hits.size(), [&](std::size_t i) {
        const Hit& h = hits[i];
        return HitRecord{h.triangle, h.t, h.u, h.v};
    }));
}

std::vector<Hit> read_hit_file(const std::filesystem::path& path)
{
    const RecordFile file = detail::read_record_file(path, hit_magic, "hit", sizeof(HitRecord));
    std::vector<Hit> hits;
    hits.reserve(file.count);
    for (std::size_t i = 0; i < file.count; ++i) {
        const auto r = file.record<HitRecord>(i);
        hits.push_back(Hit{r.t, r.triangle, r.u, r.v});
    }
    return hits;
}

}  // namespace sg
