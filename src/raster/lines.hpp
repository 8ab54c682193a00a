#pragma once
// Lines and points (polygon mode LINE and POINT) and the outline pen.
//
// A line is drawn by DDA through pixel centres: one pixel per step along its major axis,
// at the nearest centre, depth interpolated linearly. A point is a line of length 0: one
// pixel. Guarantee: the pixels and depths a line writes do not depend on the clip box it is
// drawn in (a tile or the whole viewport), so tiled and untiled renderers agree bit for bit.

#include "raster/fragment.hpp"

namespace hsr::detail {

// The fragments of `l` inside `clip`, depth-tested and written like a triangle's.
void drawLine(const ScreenLine& l, const PixelBox& clip, const FrameView& fb, DepthFunc func,
              bool depth_mask, FragmentCounts& c);

// A point of polygon mode POINT with glPointSize(size): size 1 is the pixel of the nearest
// centre (a line of length 0); larger, the pixels whose centres lie in the square of side
// `size` centred on the point, half-open in OpenGL's window coordinates (x - size/2 <=
// centre < x + size/2, and likewise upwards), as OpenGL
// rasterizes points without antialiasing. One depth, the point's.
void drawPoint(const ScreenLine& p, float size, const PixelBox& clip, const FrameView& fb,
               DepthFunc func, bool depth_mask, FragmentCounts& c);

// A silhouette edge drawn with a 2x2 pen over the finished fill, colour only. A pixel shows
// the pen where nothing is drawn, where one of the edge's two polygons is the visible one, or
// where the edge is nearer than what is there (2e-4 of tolerance); edges hidden behind other
// surfaces stay hidden.
void drawOutlinePen(const ScreenLine& l, const PixelBox& clip, const FrameView& fb);

}  // namespace hsr::detail
