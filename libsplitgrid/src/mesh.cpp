#include "splitgrid/mesh.hpp"

#include <algorithm>
#include <array>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <tbb/partitioner.h>

#include "splitgrid/error.hpp"
#include "splitgrid/ray.hpp"

namespace sg {
namespace {

// Whether six doubles sum to exactly zero. Two-Sum and Grow-Expansion (Shewchuk, "Adaptive
// Precision Floating-Point Arithmetic and Fast Robust Geometric Predicates", 1997) keep the
// running sum as a nonoverlapping expansion without any rounding; such an expansion is zero
// only if all its parts are. Needs round-to-nearest and no FMA contraction (sg_options).
bool sums_to_zero(const std::array<double, 6>& terms) noexcept
{
    std::array<double, 6> parts{};
    std::size_t n = 0;
    for (const double term : terms) {
        double q = term;
        for (std::size_t i = 0; i < n; ++i) {
            const double sum = q + parts[i];
            const double b_virtual = sum - q;
            parts[i] = (q - (sum - b_virtual)) + (parts[i] - b_virtual);
            q = sum;
        }
        parts[n++] = q;
    }
    return std::all_of(parts.begin(), parts.end(), [](double p) { return p == 0.0; });
}

// Whether the corners are collinear (or coincide), decided exactly: (b - a) x (c - a) equals
// a x b + b x c + c x a, whose components are sums of six products of two floats, and each
// such product is exact in double (48 significant bits, exponents within double's range).
bool is_degenerate(Vec3f a, Vec3f b, Vec3f c) noexcept
{
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        auto p = [](float x, float y) { return double(x) * double(y); };
        if (!sums_to_zero({p(a[i], b[j]), -p(a[j], b[i]), p(b[i], c[j]), -p(b[j], c[i]),
                           p(c[i], a[j]), -p(c[j], a[i])}))
            return false;
    }
    return true;
}

}  // namespace

bool is_valid(const Ray& ray) noexcept
{
    const Vec3f d = ray.direction;
    const bool nonzero = std::abs(d.x) >= std::numeric_limits<float>::min() ||
                         std::abs(d.y) >= std::numeric_limits<float>::min() ||
                         std::abs(d.z) >= std::numeric_limits<float>::min();
    return is_finite(ray.origin) && is_finite(d) && nonzero && std::isfinite(ray.t_min) &&
           !std::isnan(ray.t_max) && ray.t_min <= ray.t_max;
}

Aabb bounds(const MeshView& mesh) noexcept
{
    Aabb box;
    for (const Triangle& t : mesh.triangles)
        for (std::uint32_t i : t.v) box.extend(mesh.vertices[i]);
    return box;
}

void check_mesh(const MeshView& mesh)
{
    const std::size_t nv = mesh.vertices.size();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (std::uint32_t i : mesh.triangles[t].v) {
            if (i >= nv)
                throw InputError("triangle " + std::to_string(t) + " has vertex index " +
                                 std::to_string(i) + " but the mesh has " + std::to_string(nv) +
                                 " vertices");
            if (!is_finite(mesh.vertices[i]))
                throw InputError("vertex " + std::to_string(i) + " (of triangle " +
                                 std::to_string(t) + ") has a NaN or infinite coordinate");
        }
    }
}

Aabb checked_bounds(const MeshView& mesh)
{
    // The box of triangles [begin, end) and whether one of them fails check_mesh, without a
    // branch per triangle: an index past the vertex array reads vertex 0 instead and marks the
    // part bad, and a NaN or infinite coordinate turns `nonfinite` (a sum of coordinates times
    // zero) into NaN. The box of a bad part is not used.
    struct Part {
        Aabb box;
        float nonfinite = 0.0f;
        bool bad = false;
    };
    const std::size_t nv = mesh.vertices.size();
    if (nv == 0 && !mesh.triangles.empty()) check_mesh(mesh);  // throws: no vertex 0 to read
    const auto scan = [&](const tbb::blocked_range<std::size_t>& r, Part part) {
        for (std::size_t t = r.begin(); t != r.end(); ++t) {
            for (std::uint32_t i : mesh.triangles[t].v) {
                part.bad |= i >= nv;
                const Vec3f p = mesh.vertices[i < nv ? i : 0];
                part.nonfinite += p.x * 0.0f + p.y * 0.0f + p.z * 0.0f;
                part.box.extend(p);
            }
        }
        part.bad |= part.nonfinite != 0.0f;
        return part;
    };
    const auto join = [](Part a, const Part& b) {
        a.box.extend(b.box);
        a.bad |= b.bad;
        return a;
    };
    // Blocks joined left to right: min and max are exact, and a tie keeps the earlier
    // operand, so the box is bounds()'s bit for bit (also the sign of a zero coordinate) for
    // any thread count.
    constexpr std::size_t block = 16384;
    const std::size_t n = mesh.triangles.size();
    const tbb::blocked_range<std::size_t> all(0, n, block);
    const Part whole = n < 4 * block ? scan(all, Part{})
                                     : tbb::parallel_deterministic_reduce(
                                           all, Part{}, scan, join, tbb::simple_partitioner{});
    if (whole.bad) check_mesh(mesh);  // throws the error of the first failing triangle
    return whole.box;
}

CleanReport clean_mesh(Mesh& mesh)
{
    CleanReport report;
    const std::size_t nv = mesh.vertices.size();
    std::size_t kept = 0;
    for (const Triangle& t : mesh.triangles) {
        if (t.v[0] >= nv || t.v[1] >= nv || t.v[2] >= nv) {
            ++report.bad_index_triangles;
            continue;
        }
        const Vec3f a = mesh.vertices[t.v[0]];
        const Vec3f b = mesh.vertices[t.v[1]];
        const Vec3f c = mesh.vertices[t.v[2]];
        if (!is_finite(a) || !is_finite(b) || !is_finite(c)) {
            ++report.nonfinite_triangles;
            continue;
        }
        // Exactly, not with the edge vectors in double: their rounding made slivers between
        // corners of very different magnitudes (1e26 next to 1e-6) look collinear.
        if (is_degenerate(a, b, c)) {
            ++report.degenerate_triangles;
            continue;
        }
        mesh.triangles[kept++] = t;
    }
    mesh.triangles.resize(kept);
    return report;
}

}  // namespace sg
