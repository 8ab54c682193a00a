// The SSE4.1 sibling of fillSpanScalar (span.hpp): four pixels per step, the same bits.
// Depth is depthInRow's sum in double (two pairs of lanes), converted to float and clamped
// with the operands in depthInRow's order, so every lane computes exactly the scalar float.
// Transparent triangles blend per pixel and take the scalar loop.

#include "raster/span.hpp"

#if defined(__SSE4_1__) && !defined(HSR_NO_SIMD)
#include "raster/narrow_sse41.hpp"  // depthPasses4, writeFragments4

namespace hsr::detail {
namespace {

template <DepthFunc F>
void fillSpanSse41(const ScreenTriangle& t, const FrameView& fb, int y, int x0, int x1,
                   bool depth_mask, FragmentCounts& c) {
  if (t.transparent() || x1 - x0 < 3) {
    fillSpanScalar<F>(t, fb, y, x0, x1, depth_mask, c);
    return;
  }
  const double row = depthRowStart(t.depth, y);
  const __m128d row2 = _mm_set1_pd(row), dzdx2 = _mm_set1_pd(t.depth.dzdx);
  __m128d x01 = _mm_setr_pd(x0, x0 + 1.0), x23 = _mm_setr_pd(x0 + 2.0, x0 + 3.0);
  const __m128d four = _mm_set1_pd(4.0);
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
  const __m128i id = _mm_set1_epi32(static_cast<int>(t.id));
  const __m128i rgba = _mm_set1_epi32(static_cast<int>(t.rgba));
  std::size_t idx = fb.index(x0, y);
  int x = x0;
  for (; x + 3 <= x1; x += 4, idx += 4, x01 = _mm_add_pd(x01, four), x23 = _mm_add_pd(x23, four)) {
    // depthInRow for four columns: float(row + dzdx * x), then max(0, z), min(1, z).
    const __m128 lo = _mm_cvtpd_ps(_mm_add_pd(row2, _mm_mul_pd(dzdx2, x01)));
    const __m128 hi = _mm_cvtpd_ps(_mm_add_pd(row2, _mm_mul_pd(dzdx2, x23)));
    __m128 z = _mm_movelh_ps(lo, hi);
    z = _mm_min_ps(one, _mm_max_ps(zero, z));
    c.tested += 4;
    const __m128 stored = _mm_loadu_ps(fb.depth + idx);
    const __m128 pass = depthPasses4<F>(z, stored);
    const int bits = _mm_movemask_ps(pass);
    if (bits == 0) continue;
    c.written += static_cast<std::uint64_t>(__builtin_popcount(static_cast<unsigned>(bits)));
    writeFragments4(fb, idx, z, stored, pass, id, rgba, depth_mask);
  }
  if (x > x1) return;
  // The last one to three pixels: the four columns ending at x1 (the span has at least four),
  // the lanes before x, written above, left out.
  const int last = x1 - 3;
  const __m128i col = _mm_add_epi32(_mm_set1_epi32(last), _mm_setr_epi32(0, 1, 2, 3));
  const __m128 mine = _mm_castsi128_ps(_mm_cmpgt_epi32(col, _mm_set1_epi32(x - 1)));
  const double fl = static_cast<double>(last);
  const __m128 lo = _mm_cvtpd_ps(_mm_add_pd(row2, _mm_mul_pd(dzdx2, _mm_setr_pd(fl, fl + 1.0))));
  const __m128 hi =
      _mm_cvtpd_ps(_mm_add_pd(row2, _mm_mul_pd(dzdx2, _mm_setr_pd(fl + 2.0, fl + 3.0))));
  const __m128 z = _mm_min_ps(one, _mm_max_ps(zero, _mm_movelh_ps(lo, hi)));
  const std::size_t tail = fb.index(last, y);
  c.tested += static_cast<std::uint64_t>(x1 - x + 1);
  const __m128 stored = _mm_loadu_ps(fb.depth + tail);
  const __m128 pass = _mm_and_ps(depthPasses4<F>(z, stored), mine);
  c.written +=
      static_cast<std::uint64_t>(__builtin_popcount(static_cast<unsigned>(_mm_movemask_ps(pass))));
  writeFragments4(fb, tail, z, stored, pass, id, rgba, depth_mask);
}

}  // namespace

SpanFn sse41SpanFunction(DepthFunc f) {
  return withDepthFunc(f, []<DepthFunc F>() -> SpanFn { return &fillSpanSse41<F>; });
}

}  // namespace hsr::detail

#else

namespace hsr::detail {
SpanFn sse41SpanFunction(DepthFunc) { return nullptr; }
}  // namespace hsr::detail

#endif
