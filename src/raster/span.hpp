#pragma once
// Filling one span (columns x0..x1 of row y, all inside the triangle): the depth test and
// writes of each of its fragments. Three siblings produce the same bits: a scalar loop (the
// reference, always built), an SSE4.1 version that handles four pixels at once and an AVX2 one
// that handles eight (both built on x86 unless HSR_NO_SIMD; AVX2 runs where the processor has
// it). Which one runs is chosen once, never inside the loop.

#include "raster/fragment.hpp"

namespace hsr::detail {

enum class SpanPath { kScalar, kSse41, kAvx2 };

using SpanFn = void (*)(const ScreenTriangle& t, const FrameView& fb, int y, int x0, int x1,
                        bool depth_mask, FragmentCounts& c);

// The scalar span: every fragment through writeFragment, depth by depthInRow.
template <DepthFunc F>
void fillSpanScalar(const ScreenTriangle& t, const FrameView& fb, int y, int x0, int x1,
                    bool depth_mask, FragmentCounts& c) {
  const double row = depthRowStart(t.depth, y);
  std::size_t idx = fb.index(x0, y);
  for (int x = x0; x <= x1; ++x, ++idx)
    writeFragment<F>(t, fb, idx, depthInRow(row, t.depth, x), depth_mask, c);
}

// The SSE4.1 sibling (span_sse41.cpp); nullptr when it is not built.
SpanFn sse41SpanFunction(DepthFunc f);
// The AVX2 sibling (span_avx2.cpp); nullptr when it is not built. Call it only where the
// processor has AVX2 (spanPathAvailable(SpanPath::kAvx2)).
SpanFn avx2SpanFunction(DepthFunc f);

// The path in use: the widest that is built and that the processor has.
SpanPath activeSpanPath();
bool spanPathAvailable(SpanPath path);
// For tests that run both paths in one binary: returns the previous path. Not thread-safe;
// call between renders.
SpanPath setSpanPath(SpanPath path);

// The span function of the active path for depth func f.
SpanFn spanFunction(DepthFunc f);

// What fills a triangle's pixels on the active path (raster/triangle.hpp): its span function,
// and whether triangles narrower than 8 columns walk their box four columns at a time
// (raster/narrow_sse41.hpp, on the SSE4.1 and AVX2 paths) instead of one.
struct RasterPath {
  SpanFn span;
  bool narrow_sse41;
};
RasterPath rasterPath(DepthFunc f);

}  // namespace hsr::detail
