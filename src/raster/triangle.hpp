#pragma once
// Filling one screen triangle inside a clip box (a tile, or the whole viewport): the exact
// edge setup gives each row's span, the span path (span.hpp) writes its fragments. The
// renderers that reorganise the z-buffer for speed (tiles, threads, SIMD), and the routine
// that fills a frame from exact visible polygons, all fill triangles through here.

#include "raster/fragment.hpp"
#include "raster/span.hpp"

namespace hsr::detail {

// Triangles narrower than this many columns walk their bounding box testing the three edge
// functions per pixel (no divisions); wider ones compute each row's span exactly.
inline constexpr int kNarrowTriangleColumns = 8;
// Triangles with at least this many rows step each row's span from the last (RowSpans);
// shorter ones divide on every row (spanOfRow), which costs less than RowSpans' setup.
inline constexpr int kRowSpansFrom = 3;

template <DepthFunc F>
void rasterTriangle(const ScreenTriangle& t, const PixelBox& clip, const FrameView& fb,
                    bool depth_mask, const RasterPath& path, FragmentCounts& c);

// The same with the depth func and span path looked up (for callers outside a hot loop).
void rasterTriangle(const ScreenTriangle& t, const PixelBox& clip, const FrameView& fb,
                    DepthFunc func, bool depth_mask, FragmentCounts& c);

}  // namespace hsr::detail

#include "raster/triangle_impl.hpp"
