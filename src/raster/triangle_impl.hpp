#pragma once
// rasterTriangle<F> (triangle.hpp), in a header so that callers' loops inline it.

#include <algorithm>

#include "raster/edge.hpp"
#include "raster/narrow_sse41.hpp"

namespace hsr::detail {

template <DepthFunc F>
void rasterTriangle(const ScreenTriangle& t, const PixelBox& clip, const FrameView& fb,
                    bool depth_mask, const RasterPath& path, FragmentCounts& c) {
  const int y0 = std::max(clip.y0, static_cast<int>(t.y0));
  const int y1 = std::min(clip.y1, static_cast<int>(t.y1));
  const int x0 = std::max(clip.x0, static_cast<int>(t.x0));
  const int x1 = std::min(clip.x1, static_cast<int>(t.x1));
  if (y0 > y1 || x0 > x1) return;
  if (x1 - x0 < kNarrowTriangleColumns) {
#if defined(__SSE4_1__) && !defined(HSR_NO_SIMD)
    if (path.narrow_sse41 && !t.transparent() &&
        rasterNarrowSse41<F>(t, clip, x0, x1, y0, y1, fb, depth_mask, c))
      return;
#endif
    TriangleSetup s = setupTriangle(t, y0);
    // Few columns (most triangles of a dense mesh): walk the box, stepping the three edge
    // functions by additions; a pixel is inside when none of them is negative.
    for (int y = y0; y <= y1; ++y, nextRow(s)) {
      std::int64_t e0 = s.edge[0].row + s.edge[0].step_x * x0;
      std::int64_t e1 = s.edge[1].row + s.edge[1].step_x * x0;
      std::int64_t e2 = s.edge[2].row + s.edge[2].step_x * x0;
      const double row = depthRowStart(t.depth, y);
      std::size_t idx = fb.index(x0, y);
      for (int x = x0; x <= x1;
           ++x, ++idx, e0 += s.edge[0].step_x, e1 += s.edge[1].step_x, e2 += s.edge[2].step_x) {
        if ((e0 | e1 | e2) < 0) continue;  // outside some edge (sign bit set)
        writeFragment<F>(t, fb, idx, depthInRow(row, t.depth, x), depth_mask, c);
      }
    }
    return;
  }
  TriangleSetup s = setupTriangle(t, y0);
  if (y1 - y0 < kRowSpansFrom) {
    for (int y = y0; y <= y1; ++y, nextRow(s)) {
      int lo = x0, hi = x1;
      if (spanOfRow(s, &lo, &hi)) path.span(t, fb, y, lo, hi, depth_mask, c);
    }
    return;
  }
  RowSpans spans(s);
  for (int y = y0; y <= y1; ++y, spans.next()) {
    int lo = x0, hi = x1;
    if (spans.span(&lo, &hi)) path.span(t, fb, y, lo, hi, depth_mask, c);
  }
}

}  // namespace hsr::detail
