#include "fuzz_mesh_input.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <iterator>
#include <limits>

namespace sg::fuzz {
namespace {

constexpr std::uint8_t raw_float_marker = 0xF8;
constexpr int small_value_bias = 124;
constexpr float small_value_step = 0.25f;

/// Hands out bytes in order; zero once the input is used up.
class ByteReader {
public:
    explicit ByteReader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
    [[nodiscard]] bool exhausted() const noexcept { return at_ >= bytes_.size(); }
    std::uint8_t next() noexcept { return at_ < bytes_.size() ? bytes_[at_++] : 0; }
    float coordinate() noexcept
    {
        const std::uint8_t c = next();
        if (c < raw_float_marker)
            return static_cast<float>(c - small_value_bias) * small_value_step;
        std::uint32_t bits = 0;
        for (int i = 0; i < 4; ++i) bits |= std::uint32_t{next()} << (8 * i);
        return std::bit_cast<float>(bits);
    }
    Vec3f point() noexcept
    {
        // Three statements, not one braced list: the evaluation order must be x, y, z.
        Vec3f p;
        p.x = coordinate();
        p.y = coordinate();
        p.z = coordinate();
        return p;
    }

private:
    std::span<const std::uint8_t> bytes_;
    std::size_t at_ = 0;
};

void put_coordinate(std::vector<std::uint8_t>& out, float value)
{
    const float steps = value / small_value_step + static_cast<float>(small_value_bias);
    if (std::isfinite(value) && steps >= 0.0f && steps < float{raw_float_marker} &&
        steps == std::floor(steps) && !(value == 0.0f && std::signbit(value))) {
        out.push_back(static_cast<std::uint8_t>(steps));
        return;
    }
    out.push_back(raw_float_marker);
    const auto bits = std::bit_cast<std::uint32_t>(value);
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
}

void put_point(std::vector<std::uint8_t>& out, Vec3f p)
{
    for (int k = 0; k < 3; ++k) put_coordinate(out, p[k]);
}

}  // namespace

MeshCase decode_mesh_case(std::span<const std::uint8_t> bytes)
{
    ByteReader in(bytes);
    MeshCase c;
    BuildConfig& config = c.config;
    // Each field is mapped into its valid range (build_config.hpp) so that every input
    // reaches the builder rather than stopping at validate().
    config.resolution_min = 1u + in.next() % 16u;
    config.resolution_max = std::max(2u, config.resolution_min) + in.next() % 64u;
    config.resolution_sigma = 0.25 * (1.0 + in.next());
    config.leaf_size = 1u + in.next() % 16u;
    config.max_depth = in.next() % (max_supported_depth + 1u);
    config.no_progress_fraction = (1.0 + in.next()) / 256.0;
    const std::uint8_t width_byte = in.next();
    config.stop_by_cost = (in.next() & 1u) != 0;
    // Without both the cell-width cap and the cost test, nothing but max_depth bounds how
    // finely cells are sliced, and a grid's size grows like resolution^depth: a few dozen
    // triangles can make millions of references, a size and not a bug, too slow under the
    // sanitizers (docs/FUZZING.md). So one of the two is always on here; the unit and
    // robustness tests build with both off (robustness_support.hpp, hardest_splitting).
    config.min_cell_width = (config.stop_by_cost ? width_byte : 1.0 + width_byte) / 32.0;
    config.threads = 1;

    const std::size_t vertices = in.next();
    c.mesh.vertices.reserve(vertices);
    for (std::size_t v = 0; v < vertices; ++v) c.mesh.vertices.push_back(in.point());
    const std::size_t triangles = in.next();
    c.mesh.triangles.reserve(triangles);
    for (std::size_t t = 0; t < triangles; ++t) {
        Triangle tri;
        for (std::uint32_t& index : tri.v) index = in.next();
        c.mesh.triangles.push_back(tri);
    }
    while (!in.exhausted()) {
        const std::uint8_t flags = in.next();
        Ray ray;
        ray.origin = in.point();
        ray.direction = in.point();
        if ((flags & 1u) != 0) ray.t_min = in.coordinate();
        if ((flags & 2u) != 0) ray.t_max = in.coordinate();
        c.rays.push_back(ray);
    }
    return c;
}

std::vector<std::uint8_t> encode_mesh_case(const std::uint8_t (&config)[8], const Mesh& mesh,
                                           const std::vector<Ray>& rays)
{
    std::vector<std::uint8_t> out(std::begin(config), std::end(config));
    out.push_back(static_cast<std::uint8_t>(mesh.vertices.size()));
    for (const Vec3f& p : mesh.vertices) put_point(out, p);
    out.push_back(static_cast<std::uint8_t>(mesh.triangles.size()));
    for (const Triangle& t : mesh.triangles)
        for (const std::uint32_t index : t.v) out.push_back(static_cast<std::uint8_t>(index));
    for (const Ray& ray : rays) {
        const bool has_t_min = ray.t_min != 0.0f;
        const bool has_t_max = ray.t_max != std::numeric_limits<float>::infinity();
        out.push_back(static_cast<std::uint8_t>((has_t_min ? 1u : 0u) | (has_t_max ? 2u : 0u)));
        put_point(out, ray.origin);
        put_point(out, ray.direction);
        if (has_t_min) put_coordinate(out, ray.t_min);
        if (has_t_max) put_coordinate(out, ray.t_max);
    }
    return out;
}

}  // namespace sg::fuzz
