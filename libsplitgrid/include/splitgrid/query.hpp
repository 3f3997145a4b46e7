#pragma once

#include <cstdint>
#include <string_view>

/// The choices every query in splitgrid takes at run time, the Split Grid's and the comparison
/// structures' alike: which ray/triangle test it runs, whether it widens its ray intervals
/// against rounding, and which instruction set its kernels use. The defaults are the exact
/// ones and the fastest instruction set the processor has; the others exist so that sg-bench
/// can chart what exactness costs and what dropping it loses, and so that every kernel can be
/// tested on every machine.

namespace sg {

/// The ray/triangle test of a query.
enum class TriangleTest : std::uint8_t {
    /// Woop, Benthin and Wald, "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013
    /// (ray_triangle.hpp): two triangles sharing an edge decide a ray through it from the same
    /// inputs, so no ray slips between them. The one intersect_brute_force uses, so a structure
    /// finds exactly the hits brute force finds. The default.
    watertight,
    /// Moeller and Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection", JGT 2(1), 1997,
    /// in single precision without an epsilon: not watertight (a ray through a shared edge can
    /// fail both triangles). For sg-bench's speed-against-accuracy chart only.
    moller_trumbore,
    /// The watertight test as it was before its zero edge functions were decided by symbolic
    /// perturbation: a zero counts on either side, so a ray through an edge hits both of its
    /// triangles and a ray through a vertex every triangle of its fan. Watertight (no ray
    /// slips through), but a count of crossings along a ray can be wrong by one or more. For sg-bench's comparison of inside tests only (count and occupancy);
    /// closest-hit and any-hit queries given it run the watertight test.
    watertight_no_tie_break,
};

/// Whether a traversal widens its ray intervals to absorb the rounding of plane crossings
/// (conservative, the default and the only mode the tests hold to zero misses), or uses the
/// computed crossings as they are (none: it can lose hits where a ray passes within rounding
/// error of a cell or box face; sg-bench charts the difference). Build-time padding
/// (boundary_pad) is not affected.
enum class Padding : std::uint8_t { conservative, none };

/// How one query runs. Default-constructed: the exact query.
struct QueryOptions {
    TriangleTest test = TriangleTest::watertight;
    Padding padding = Padding::conservative;
    friend constexpr bool operator==(const QueryOptions&, const QueryOptions&) = default;
};

/// The instruction sets the traversal kernels are compiled for. Every query runs the kernels
/// of the active one (kernel_isa()); all of them compute bit-identical hits.
enum class Isa : std::uint8_t {
    scalar,  ///< no SIMD: one triangle, one box, one point at a time (every processor)
    sse2,    ///< x86-64 baseline: 8-lane triangle tests as two 4-wide halves
    avx2,    ///< x86-64-v3 (AVX2, FMA, BMI2): 8-wide triangle tests in 256-bit registers
    avx512,  ///< x86-64-v4 (AVX-512 F/VL/BW/DQ): 8-wide triangle tests with mask registers
};

/// "scalar", "sse2", "avx2" or "avx512".
[[nodiscard]] std::string_view isa_name(Isa isa) noexcept;

/// True if this processor can run `isa`'s kernels.
[[nodiscard]] bool isa_supported(Isa isa) noexcept;

/// The kernels queries use. At start-up: the value of the environment variable SG_ISA
/// ("scalar", "sse2", "avx2" or "avx512") if it is set and supported, else the most capable
/// supported instruction set. Cost: one atomic load.
[[nodiscard]] Isa kernel_isa() noexcept;

/// Why kernel_isa() is not what SG_ISA asked for: empty when SG_ISA is unset or was honoured,
/// else one line naming the value and the reason (unknown name, not supported by this
/// processor), for tools to print as a warning. The library itself never prints.
[[nodiscard]] std::string_view kernel_isa_note() noexcept;

/// Makes every later query use `isa`. Throws ConfigError if the processor cannot run it.
/// Meant for start-up (tools, tests, benchmarks); queries running at the same time finish on
/// the kernels they started with.
void set_kernel_isa(Isa isa);

}  // namespace sg
