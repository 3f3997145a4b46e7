#pragma once

// Traversal kernels, part 2: 8-wide float and int vectors for the batched triangle test, as
// GCC vector extensions, so that one source compiles to two SSE2 halves, one AVX2 register or
// AVX-512 mask operations by the target region it is included in. Only the gathers and the
// lane mask differ by instruction set (and the triangle test's loads from the mesh:
// load_corners in triangle_test.hpp). The scalar kernels (level 0) have no vectors at all:
// their leaves, boxes and points are taken one at a time (triangle_test.hpp, bvh_walk.hpp,
// point_lanes.hpp), so this part gives them clear_upper_lanes only.

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

/// Clears the upper halves of the 256- and 512-bit registers (vzeroupper; nothing in the
/// SSE2 and scalar kernels). The batch drivers call it after every walk: GCC does not insert
/// it on every exit of a walk whose inlined leaf test uses 256-bit registers, and the code
/// compiled without AVX that runs between two rays then stalls on the dirty registers (it cost
/// the BVH much of its speed on primary rays; docs/notebook/trace.md, "The BVH: eight boxes
/// per step").
[[gnu::always_inline]] inline void clear_upper_lanes() noexcept
{
#if SG_KERNEL_ISA_LEVEL >= 3
    _mm256_zeroupper();
#endif
}

#if SG_KERNEL_ISA_LEVEL >= 2
inline constexpr int lane_count = 8;
typedef float vfloat __attribute__((vector_size(32)));
typedef std::int32_t vint __attribute__((vector_size(32)));

/// Eight doubles and the 64-bit lane masks their comparisons give (point queries measure in
/// double: point_lanes.hpp).
typedef double vdouble __attribute__((vector_size(64)));
typedef std::int64_t vlong __attribute__((vector_size(64)));

/// x in every lane (bit for bit: -0 stays -0).
[[nodiscard]] inline vfloat splat(float x) noexcept { return vfloat{x, x, x, x, x, x, x, x}; }
[[nodiscard]] inline vint splat(std::int32_t x) noexcept { return vint{x, x, x, x, x, x, x, x}; }
[[nodiscard]] inline vdouble splat(double x) noexcept { return vdouble{x, x, x, x, x, x, x, x}; }
/// The lanes of `x` as doubles (exactly).
[[nodiscard]] inline vdouble widen(vfloat x) noexcept { return __builtin_convertvector(x, vdouble); }
/// A 32-bit lane mask as a 64-bit one, and back.
[[nodiscard]] inline vlong widen(vint mask) noexcept { return __builtin_convertvector(mask, vlong); }
[[nodiscard]] inline vint narrow(vlong mask) noexcept { return __builtin_convertvector(mask, vint); }
/// |x| lane by lane, as std::abs (the sign bit cleared).
[[nodiscard]] inline vfloat abs(vfloat x) noexcept { return (vfloat)((vint)x & 0x7FFFFFFF); }

/// Bit l set where lane l of `mask` (a comparison result: 0 or -1 per lane) is set.
[[nodiscard]] inline std::uint32_t lane_bits(vint mask) noexcept
{
#if SG_KERNEL_ISA_LEVEL >= 3
    return static_cast<std::uint32_t>(_mm256_movemask_ps(_mm256_castsi256_ps(__m256i(mask))));
#else
    __m128i lo, hi;
    std::memcpy(&lo, &mask, 16);
    std::memcpy(&hi, reinterpret_cast<const char*>(&mask) + 16, 16);
    return static_cast<std::uint32_t>(_mm_movemask_ps(_mm_castsi128_ps(lo))) |
           (static_cast<std::uint32_t>(_mm_movemask_ps(_mm_castsi128_ps(hi))) << 4);
#endif
}

/// base[index[l]] for each lane (the indices of unused lanes must still be valid).
[[nodiscard]] inline vfloat gather(const float* base, vint index) noexcept
{
#if SG_KERNEL_ISA_LEVEL >= 3
    return vfloat(_mm256_i32gather_ps(base, __m256i(index), 4));
#else
    vfloat v;
    for (int l = 0; l < lane_count; ++l) v[l] = base[index[l]];
    return v;
#endif
}
[[nodiscard]] inline vint gather(const std::int32_t* base, vint index) noexcept
{
#if SG_KERNEL_ISA_LEVEL >= 3
    return vint(_mm256_i32gather_epi32(base, __m256i(index), 4));
#else
    vint v;
    for (int l = 0; l < lane_count; ++l) v[l] = base[index[l]];
    return v;
#endif
}

/// ids[0, n) in lanes 0 .. n - 1 (as signed words; the ids are below 2^31), one vector load
/// where the array holds lane_count words from `ids` on (`end` is the array's end); the other
/// lanes are unspecified (valid words of the array, or 0).
[[nodiscard]] inline vint load_ids(const std::uint32_t* ids, std::uint32_t n,
                                   const std::uint32_t* end) noexcept
{
    vint v;
    if (end - ids >= lane_count) {
        std::memcpy(&v, ids, sizeof v);
        return v;
    }
    v = splat(std::int32_t{0});
    for (std::uint32_t l = 0; l < n; ++l) v[l] = static_cast<std::int32_t>(ids[l]);
    return v;
}

/// The 16-bit words[0, n) zero-extended into lanes 0 .. n - 1, one 16-byte load where the array
/// holds lane_count words from `words` on (`end` is the array's end); the other lanes are
/// unspecified (valid words of the array, or 0).
[[nodiscard]] inline vint load_words(const std::uint16_t* words, std::uint32_t n,
                                     const std::uint16_t* end) noexcept
{
    typedef std::uint16_t vword __attribute__((vector_size(16)));
    vword w = {};
    if (end - words >= lane_count)
        std::memcpy(&w, words, sizeof w);
    else
        for (std::uint32_t l = 0; l < n; ++l) w[l] = words[l];
    return __builtin_convertvector(w, vint);
}

/// The 32-bit values of word pairs (low half first) from `words` into lanes 0 .. n - 1, as
/// load_ids; `end` is the end of the array of 16-bit words.
[[nodiscard]] inline vint load_pairs(const std::uint16_t* words, std::uint32_t n,
                                     const std::uint16_t* end) noexcept
{
    vint v;
    if (end - words >= 2 * lane_count) {
        std::memcpy(&v, words, sizeof v);
        return v;
    }
    v = splat(std::int32_t{0});
    for (std::uint32_t l = 0; l < n; ++l)
        v[l] = static_cast<std::int32_t>(std::uint32_t{words[2 * l]} |
                                         (std::uint32_t{words[2 * l + 1]} << 16));
    return v;
}
#endif  // SG_KERNEL_ISA_LEVEL >= 2

}  // namespace sg::kernels::SG_KERNEL_ISA
