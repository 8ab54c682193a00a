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
  const __m128d row2 = _mm_set1_pd(depthRowStart(t.depth, y)), dzdx2 = _mm_set1_pd(t.depth.dzdx);
  const __m128i id = _mm_set1_epi32(static_cast<int>(t.id));
  const __m128i rgba = _mm_set1_epi32(static_cast<int>(t.rgba));
  // Four columns from x at fb index idx, those not in `mine` left out.
  auto four = [&](int x, std::size_t idx, __m128 mine) {
    const __m128 z = depthInRow4(row2, dzdx2, x);
    const __m128 stored = _mm_loadu_ps(fb.depth + idx);
    const __m128 pass = _mm_and_ps(depthPasses4<F>(z, stored), mine);
    const int bits = _mm_movemask_ps(pass);
    if (bits == 0) return;
    c.written += static_cast<std::uint64_t>(__builtin_popcount(static_cast<unsigned>(bits)));
    writeFragments4(fb, idx, z, stored, pass, id, rgba, depth_mask);
  };
  const __m128 all = _mm_castsi128_ps(_mm_set1_epi32(-1));
  std::size_t idx = fb.index(x0, y);
  int x = x0;
  for (; x + 3 <= x1; x += 4, idx += 4) four(x, idx, all);
  c.tested += static_cast<std::uint64_t>(x1 - x0 + 1);
  if (x > x1) return;
  // The last one to three pixels: the four columns ending at x1 (the span has at least four),
  // the lanes before x, written above, left out.
  const int last = x1 - 3;
  const __m128i col = _mm_add_epi32(_mm_set1_epi32(last), _mm_setr_epi32(0, 1, 2, 3));
  four(last, fb.index(last, y), _mm_castsi128_ps(_mm_cmpgt_epi32(col, _mm_set1_epi32(x - 1))));
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
