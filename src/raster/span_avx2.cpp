// The AVX2 sibling of fillSpanScalar (span.hpp): eight pixels per step, the same bits. Built
// for x86-64 unless HSR_NO_SIMD (the functions carry their own target, so the portable
// x86-64-v2 build has them) and chosen at run time where the processor has AVX2 (span.cpp). Depth
// is depthInRow's sum in double (two groups of four lanes), converted to float and clamped with the
// operands in depthInRow's order; the products and sums stay separate operations (no fused
// multiply-add: the target is AVX2 alone), so every lane computes the scalar float. Spans shorter
// than eight pixels, and transparent triangles, take the SSE4.1 span.

#include "raster/span.hpp"

#if defined(__x86_64__) && !defined(HSR_NO_SIMD)
#include <immintrin.h>

#define HSR_AVX2 __attribute__((target("avx2"), always_inline)) inline

namespace hsr::detail {
namespace {

template <DepthFunc F>
HSR_AVX2 __m256 depthPasses8(__m256 z, __m256 stored) {
  if constexpr (F == DepthFunc::Never) return _mm256_setzero_ps();
  if constexpr (F == DepthFunc::Less) return _mm256_cmp_ps(z, stored, _CMP_LT_OQ);
  if constexpr (F == DepthFunc::Equal) return _mm256_cmp_ps(z, stored, _CMP_EQ_OQ);
  if constexpr (F == DepthFunc::LEqual) return _mm256_cmp_ps(z, stored, _CMP_LE_OQ);
  if constexpr (F == DepthFunc::Greater) return _mm256_cmp_ps(z, stored, _CMP_GT_OQ);
  // z != stored holds when either is NaN: the unordered predicate, as SSE's cmpneq.
  if constexpr (F == DepthFunc::NotEqual) return _mm256_cmp_ps(z, stored, _CMP_NEQ_UQ);
  if constexpr (F == DepthFunc::GEqual) return _mm256_cmp_ps(z, stored, _CMP_GE_OQ);
  return _mm256_castsi256_ps(_mm256_set1_epi32(-1));  // Always
}

// depthInRow at columns x .. x + 7 of a row whose depthRowStart is in every lane of row4.
HSR_AVX2 __m256 depthInRow8(__m256d row4, __m256d dzdx4, double x) {
  const __m256d cols = _mm256_add_pd(_mm256_set1_pd(x), _mm256_setr_pd(0.0, 1.0, 2.0, 3.0));
  const __m128 lo = _mm256_cvtpd_ps(_mm256_add_pd(row4, _mm256_mul_pd(dzdx4, cols)));
  const __m128 hi = _mm256_cvtpd_ps(
      _mm256_add_pd(row4, _mm256_mul_pd(dzdx4, _mm256_add_pd(cols, _mm256_set1_pd(4.0)))));
  const __m256 z = _mm256_set_m128(hi, lo);
  return _mm256_min_ps(_mm256_set1_ps(1.0f), _mm256_max_ps(_mm256_setzero_ps(), z));
}

HSR_AVX2 void blendStore8(void* p, __m256i value, __m256i mask) {
  const __m256i old = _mm256_loadu_si256(static_cast<const __m256i*>(p));
  _mm256_storeu_si256(static_cast<__m256i*>(p), _mm256_blendv_epi8(old, value, mask));
}

// The eight columns from x at fb index idx whose lanes of `mine` are set: tested, and those
// that pass written (depth if the mask allows, id, colour, one more on the overdraw count).
template <DepthFunc F>
HSR_AVX2 void fillEight(const FrameView& fb, std::size_t idx, __m256 z, __m256 mine, __m256i id,
                        __m256i rgba, bool depth_mask, FragmentCounts& c) {
  const __m256 stored = _mm256_loadu_ps(fb.depth + idx);
  const __m256 pass = _mm256_and_ps(depthPasses8<F>(z, stored), mine);
  const int bits = _mm256_movemask_ps(pass);
  if (bits == 0) return;
  c.written += static_cast<std::uint64_t>(__builtin_popcount(static_cast<unsigned>(bits)));
  const __m256i m = _mm256_castps_si256(pass);
  if (depth_mask) _mm256_storeu_ps(fb.depth + idx, _mm256_blendv_ps(stored, z, pass));
  blendStore8(fb.ids + idx, id, m);
  blendStore8(fb.rgba + idx, rgba, m);
  const __m256i od = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(fb.overdraw + idx));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(fb.overdraw + idx), _mm256_sub_epi32(od, m));
}

template <DepthFunc F>
__attribute__((target("avx2"))) void fillSpanAvx2(const ScreenTriangle& t, const FrameView& fb,
                                                  int y, int x0, int x1, bool depth_mask,
                                                  FragmentCounts& c) {
  if (t.transparent() || x1 - x0 < 7) {
    static const SpanFn narrower = sse41SpanFunction(F);
    narrower(t, fb, y, x0, x1, depth_mask, c);
    return;
  }
  const __m256d row4 = _mm256_set1_pd(depthRowStart(t.depth, y));
  const __m256d dzdx4 = _mm256_set1_pd(t.depth.dzdx);
  const __m256i id = _mm256_set1_epi32(static_cast<int>(t.id));
  const __m256i rgba = _mm256_set1_epi32(static_cast<int>(t.rgba));
  const __m256 all = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
  std::size_t idx = fb.index(x0, y);
  int x = x0;
  for (; x + 7 <= x1; x += 8, idx += 8)
    fillEight<F>(fb, idx, depthInRow8(row4, dzdx4, x), all, id, rgba, depth_mask, c);
  c.tested += static_cast<std::uint64_t>(x1 - x0 + 1);
  if (x > x1) return;
  // The last one to seven pixels: the eight columns ending at x1 (the span has at least
  // eight), the lanes before x, written above, left out.
  const int last = x1 - 7;
  const __m256i col =
      _mm256_add_epi32(_mm256_set1_epi32(last), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  const __m256 mine = _mm256_castsi256_ps(_mm256_cmpgt_epi32(col, _mm256_set1_epi32(x - 1)));
  fillEight<F>(fb, fb.index(last, y), depthInRow8(row4, dzdx4, last), mine, id, rgba, depth_mask,
               c);
}

}  // namespace

SpanFn avx2SpanFunction(DepthFunc f) {
  if (sse41SpanFunction(f) == nullptr) return nullptr;  // its short spans need the SSE4.1 one
  return withDepthFunc(f, []<DepthFunc F>() -> SpanFn { return &fillSpanAvx2<F>; });
}

}  // namespace hsr::detail

#else

namespace hsr::detail {
SpanFn avx2SpanFunction(DepthFunc) { return nullptr; }
}  // namespace hsr::detail

#endif
