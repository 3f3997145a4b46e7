#include "splitgrid/cell_math.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace sg {
namespace {

#if defined(__SSE2__)
// CellMath::guess, boundary, locate_lowest and locate_highest for four coordinates at once.
// Each scalar step has its lane-wise twin: the same subtraction, division, product and sum in
// float, the same clamps (min and max keep the scalar code's operand on ties and NaN), and the
// correction loops run until no lane moves, each lane stopping where the scalar loop stops.
class FourLanes {
public:
    explicit FourLanes(const CellMath& cm) noexcept
        : lo_(_mm_set1_ps(cm.lo)),
          hi_(_mm_set1_ps(cm.hi)),
          width_(_mm_set1_ps(cm.width)),
          last_cell_(_mm_set1_ps(static_cast<float>(cm.n - 1))),
          n_(_mm_set1_epi32(static_cast<int>(cm.n)))
    {
    }

    [[nodiscard]] __m128i lowest(__m128 x) const noexcept
    {
        __m128i i = guess(x);
        for (;;) {  // while (i > 0 && x <= boundary(i)) --i
            const __m128i move = _mm_and_si128(_mm_cmpgt_epi32(i, zero()),
                                               _mm_castps_si128(_mm_cmple_ps(x, boundary(i))));
            if (_mm_movemask_epi8(move) == 0) break;
            i = _mm_add_epi32(i, move);  // move is -1 where a lane steps
        }
        for (;;) {  // while (i + 1 < n && x > boundary(i + 1)) ++i
            const __m128i next = _mm_add_epi32(i, one());
            const __m128i move = _mm_and_si128(_mm_cmpgt_epi32(n_, next),
                                               _mm_castps_si128(_mm_cmpgt_ps(x, boundary(next))));
            if (_mm_movemask_epi8(move) == 0) break;
            i = _mm_sub_epi32(i, move);
        }
        return i;
    }

    [[nodiscard]] __m128i highest(__m128 x) const noexcept
    {
        __m128i i = guess(x);
        for (;;) {  // while (i + 1 < n && x >= boundary(i + 1)) ++i
            const __m128i next = _mm_add_epi32(i, one());
            const __m128i move = _mm_and_si128(_mm_cmpgt_epi32(n_, next),
                                               _mm_castps_si128(_mm_cmpge_ps(x, boundary(next))));
            if (_mm_movemask_epi8(move) == 0) break;
            i = _mm_sub_epi32(i, move);
        }
        for (;;) {  // while (i > 0 && x < boundary(i)) --i
            const __m128i move = _mm_and_si128(_mm_cmpgt_epi32(i, zero()),
                                               _mm_castps_si128(_mm_cmplt_ps(x, boundary(i))));
            if (_mm_movemask_epi8(move) == 0) break;
            i = _mm_add_epi32(i, move);
        }
        return i;
    }

private:
    static __m128i zero() noexcept { return _mm_setzero_si128(); }
    static __m128i one() noexcept { return _mm_set1_epi32(1); }

    // guess(): (x - lo) / width, 0 where not above 0 (NaN included: max keeps its second
    // operand), n - 1 from n - 1 up, truncated. Requires width > 0.
    [[nodiscard]] __m128i guess(__m128 x) const noexcept
    {
        const __m128 f = _mm_div_ps(_mm_sub_ps(x, lo_), width_);
        return _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), last_cell_));
    }

    // boundary(i): lo at 0, hi from n up, else min(hi, lo + i * width) (min keeps hi on ties,
    // as std::min(hi, v) does).
    [[nodiscard]] __m128 boundary(__m128i i) const noexcept
    {
        const __m128 inner =
            _mm_min_ps(_mm_add_ps(lo_, _mm_mul_ps(_mm_cvtepi32_ps(i), width_)), hi_);
        const __m128 at_zero = _mm_castsi128_ps(_mm_cmpeq_epi32(i, zero()));
        const __m128 past_end = _mm_castsi128_ps(_mm_cmpgt_epi32(i, _mm_sub_epi32(n_, one())));
        const __m128 b = _mm_or_ps(_mm_and_ps(past_end, hi_), _mm_andnot_ps(past_end, inner));
        return _mm_or_ps(_mm_and_ps(at_zero, lo_), _mm_andnot_ps(at_zero, b));
    }

    __m128 lo_;
    __m128 hi_;
    __m128 width_;
    __m128 last_cell_;
    __m128i n_;
};
#endif

}  // namespace

void locate_cells(const CellMath& cm, const float* lower, const float* upper, std::size_t count,
                  std::uint32_t* first, std::uint32_t* last) noexcept
{
    std::size_t i = 0;
#if defined(__SSE2__)
    // The lanes need width > 0 (guess() divides by it; the scalar guess() returns 0 there) and
    // signed 32-bit cell indices (a resolution is at most 2^20).
    if (cm.width > 0.0f) {
        const FourLanes lanes(cm);
        for (; i + 4 <= count; i += 4) {
            _mm_storeu_si128(reinterpret_cast<__m128i*>(first + i),
                             lanes.lowest(_mm_loadu_ps(lower + i)));
            _mm_storeu_si128(reinterpret_cast<__m128i*>(last + i),
                             lanes.highest(_mm_loadu_ps(upper + i)));
        }
    }
#endif
    for (; i < count; ++i) {
        first[i] = cm.locate_lowest(lower[i]);
        last[i] = cm.locate_highest(upper[i]);
    }
}

}  // namespace sg
