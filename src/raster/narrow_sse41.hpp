#pragma once
// The narrow-triangle walk (triangle_impl.hpp) four columns at a time with SSE4.1: the same
// pixels, the same depth bits, the same counts. The three edge functions are stepped in 32-bit
// lanes, exact because the caller's bound (narrowFitsInt32) holds every value the walk can
// meet below 2^31; the depth is depthInRow's sum in double, converted and clamped in its order.

#if defined(__SSE4_1__) && !defined(HSR_NO_SIMD)
#include <smmintrin.h>

#include <algorithm>
#include <cstdlib>

#include "raster/edge.hpp"
#include "raster/fragment.hpp"

namespace hsr::detail {

template <DepthFunc F>
inline __m128 depthPasses4(__m128 z, __m128 stored) {
  if constexpr (F == DepthFunc::Never) return _mm_setzero_ps();
  if constexpr (F == DepthFunc::Less) return _mm_cmplt_ps(z, stored);
  if constexpr (F == DepthFunc::Equal) return _mm_cmpeq_ps(z, stored);
  if constexpr (F == DepthFunc::LEqual) return _mm_cmple_ps(z, stored);
  if constexpr (F == DepthFunc::Greater) return _mm_cmpgt_ps(z, stored);
  if constexpr (F == DepthFunc::NotEqual) return _mm_cmpneq_ps(z, stored);
  if constexpr (F == DepthFunc::GEqual) return _mm_cmpge_ps(z, stored);
  return _mm_castsi128_ps(_mm_set1_epi32(-1));  // Always
}

// depthInRow (raster/depth.hpp) at columns x .. x + 3 of a row whose depthRowStart is in both
// lanes of row2 (dzdx in both of dzdx2): the sum in double, converted, clamped in its order.
inline __m128 depthInRow4(__m128d row2, __m128d dzdx2, double x) {
  const __m128 lo = _mm_cvtpd_ps(_mm_add_pd(row2, _mm_mul_pd(dzdx2, _mm_setr_pd(x, x + 1.0))));
  const __m128 hi =
      _mm_cvtpd_ps(_mm_add_pd(row2, _mm_mul_pd(dzdx2, _mm_setr_pd(x + 2.0, x + 3.0))));
  return _mm_min_ps(_mm_set1_ps(1.0f), _mm_max_ps(_mm_setzero_ps(), _mm_movelh_ps(lo, hi)));
}

// Writes the four fragments at fb index idx whose lanes of `pass` are set: depth z (if the
// mask allows), the id and colour, one more on the overdraw count.
inline void writeFragments4(const FrameView& fb, std::size_t idx, __m128 z, __m128 stored,
                            __m128 pass, __m128i id, __m128i rgba, bool depth_mask) {
  const __m128i m = _mm_castps_si128(pass);
  if (depth_mask) _mm_storeu_ps(fb.depth + idx, _mm_blendv_ps(stored, z, pass));
  auto blendStore = [&](void* p, __m128i value) {
    const __m128i old = _mm_loadu_si128(static_cast<const __m128i*>(p));
    _mm_storeu_si128(static_cast<__m128i*>(p), _mm_blendv_epi8(old, value, m));
  };
  blendStore(fb.ids + idx, id);
  blendStore(fb.rgba + idx, rgba);
  const __m128i od = _mm_loadu_si128(reinterpret_cast<const __m128i*>(fb.overdraw + idx));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(fb.overdraw + idx), _mm_sub_epi32(od, m));
}

// The three edge functions of setupTriangle at pixel (x, y), and their steps per column and
// per row, in 32 bits. Straight from the vertices when the triangle spans less than 16 pixels
// each way: then every value within 16 pixels of its box is below 2^27 in magnitude, and these
// are setupTriangle's values exactly (the same integer sums, none of which overflows).
struct NarrowEdges {
  std::int32_t value[3], step_x[3], step_y[3];
};
inline bool smallTriangleEdges(const ScreenTriangle& t, int x, int y, NarrowEdges* e) {
  constexpr std::int32_t kSpan = 16 * kSubpixelOne;
  const std::int32_t lo_x = std::min({t.x[0], t.x[1], t.x[2]});
  const std::int32_t hi_x = std::max({t.x[0], t.x[1], t.x[2]});
  const std::int32_t lo_y = std::min({t.y[0], t.y[1], t.y[2]});
  const std::int32_t hi_y = std::max({t.y[0], t.y[1], t.y[2]});
  if (hi_x - lo_x >= kSpan || hi_y - lo_y >= kSpan) return false;
  const std::int32_t px = x * kSubpixelOne, py = y * kSubpixelOne;
  for (int k = 0; k < 3; ++k) {
    const int next = k == 2 ? 0 : k + 1;
    const std::int32_t dx = t.x[next] - t.x[k], dy = t.y[next] - t.y[k];
    const bool top_left = (dy < 0) || (dy == 0 && dx < 0);  // setupTriangle's fill rule
    e->step_x[k] = -dy * kSubpixelOne;
    e->step_y[k] = dx * kSubpixelOne;
    e->value[k] = dx * (py - t.y[k]) - dy * (px - t.x[k]) + (top_left ? 0 : -1);
  }
  return true;
}

// The rows y0..y1 of W windows of four columns (at xs[w], lanes `valid[w]`) whose edge values
// on row y0 are e[w][k]: the fragments inside all three edges are depth tested and written.
// Without a branch on whether a row holds a fragment or one passes: for triangles of a few
// pixels those branches went either way at random, and mispredicting them cost a third of the
// raster stage (spheres:1M, 1 thread: 35.2 -> 24.7 ms). A window with no lane passing writes
// back what it read, inside the clip box, which only this tile's thread touches.
template <DepthFunc F, int W>
inline void walkNarrowWindows(const ScreenTriangle& t, const int (&xs)[2],
                              const __m128i (&valid)[2], __m128i (&e)[2][3],
                              const __m128i (&step_y)[3], int y0, int y1, const FrameView& fb,
                              bool depth_mask, FragmentCounts& c) {
  const __m128d dzdx2 = _mm_set1_pd(t.depth.dzdx);
  const __m128i id = _mm_set1_epi32(static_cast<int>(t.id));
  const __m128i rgba = _mm_set1_epi32(static_cast<int>(t.rgba));
  for (int y = y0; y <= y1; ++y) {
    const __m128d row2 = _mm_set1_pd(depthRowStart(t.depth, y));
    for (int w = 0; w < W; ++w) {
      // Inside: no edge value negative (the sign bits of their OR clear), in a valid lane.
      const __m128i out = _mm_or_si128(_mm_or_si128(e[w][0], e[w][1]), e[w][2]);
      const __m128i in = _mm_srai_epi32(_mm_andnot_si128(out, valid[w]), 31);
      for (int k = 0; k < 3; ++k) e[w][k] = _mm_add_epi32(e[w][k], step_y[k]);
      const int in_bits = _mm_movemask_ps(_mm_castsi128_ps(in));
      c.tested += static_cast<std::uint64_t>(__builtin_popcount(static_cast<unsigned>(in_bits)));
      const __m128 z = depthInRow4(row2, dzdx2, xs[w]);
      const std::size_t idx = fb.index(xs[w], y);
      const __m128 stored = _mm_loadu_ps(fb.depth + idx);
      const __m128 pass = _mm_and_ps(depthPasses4<F>(z, stored), _mm_castsi128_ps(in));
      const int bits = _mm_movemask_ps(pass);
      c.written += static_cast<std::uint64_t>(__builtin_popcount(static_cast<unsigned>(bits)));
      writeFragments4(fb, idx, z, stored, pass, id, rgba, depth_mask);
    }
  }
}

// Walks the opaque triangle's box x0..x1 (at most 8 columns), y0..y1 in windows of four
// columns that lie inside the clip box; returns false, having drawn nothing, when the clip box
// is narrower than four columns or an edge value could leave 32 bits.
template <DepthFunc F>
inline bool rasterNarrowSse41(const ScreenTriangle& t, const PixelBox& clip, int x0, int x1, int y0,
                              int y1, const FrameView& fb, bool depth_mask, FragmentCounts& c) {
  if (clip.x1 - clip.x0 < 3) return false;
  // Window c starts at column x0 + 4c, moved left when it would cross the clip box's right
  // side; `valid` keeps the lanes of columns the window owns (its own four, within x1).
  const int windows = (x1 - x0) / 4 + 1;
  int xs[2] = {0, 0};
  __m128i valid[2];
  const __m128i lane = _mm_setr_epi32(0, 1, 2, 3);
  for (int w = 0; w < windows; ++w) {
    const int first = x0 + 4 * w;
    xs[w] = first + 3 <= clip.x1 ? first : clip.x1 - 3;
    const __m128i col = _mm_add_epi32(_mm_set1_epi32(xs[w]), lane);
    const __m128i lo = _mm_set1_epi32(first - 1), hi = _mm_set1_epi32(std::min(first + 3, x1) + 1);
    valid[w] = _mm_and_si128(_mm_cmpgt_epi32(col, lo), _mm_cmplt_epi32(col, hi));
  }
  // The edge values at (xs[0], y0): from the vertices in 32 bits for a small triangle (the
  // windows lie within 11 columns of its box), else from setupTriangle when every value met,
  // row + step_x * x + step_y * (y - y0) for x within 11 columns of xs[0], is bounded below
  // 2^31 by the sum of the absolute values.
  NarrowEdges g;
  if (!smallTriangleEdges(t, xs[0], y0, &g)) {
    const TriangleSetup s = setupTriangle(t, y0);
    for (int k = 0; k < 3; ++k) {
      const EdgeSetup& f = s.edge[k];
      const std::int64_t base = f.row + f.step_x * xs[0];
      const std::int64_t bound =
          std::llabs(base) + std::llabs(f.step_x) * 11 + std::llabs(f.step_y) * (y1 - y0);
      if (bound >= (std::int64_t{1} << 31)) return false;
      g.value[k] = static_cast<std::int32_t>(base);
      g.step_x[k] = static_cast<std::int32_t>(f.step_x);
      g.step_y[k] = static_cast<std::int32_t>(f.step_y);
    }
  }
  // Each lane's value: the window's first column's, plus step_x times the lane (by additions:
  // every value is below 2^31, as above).
  __m128i e[2][3], step_y[3];
  for (int k = 0; k < 3; ++k) {
    const std::int32_t sx = g.step_x[k];
    const __m128i steps = _mm_setr_epi32(0, sx, sx + sx, sx + sx + sx);
    for (int w = 0; w < windows; ++w)
      e[w][k] = _mm_add_epi32(_mm_set1_epi32(g.value[k] + sx * (xs[w] - xs[0])), steps);
    step_y[k] = _mm_set1_epi32(g.step_y[k]);
  }
  if (windows == 1)
    walkNarrowWindows<F, 1>(t, xs, valid, e, step_y, y0, y1, fb, depth_mask, c);
  else
    walkNarrowWindows<F, 2>(t, xs, valid, e, step_y, y0, y1, fb, depth_mask, c);
  return true;
}

}  // namespace hsr::detail
#endif
