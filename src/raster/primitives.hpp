#pragma once
// Screen primitives: what the pipeline hands to the image-precision algorithms, in window
// space. Coordinates are y-DOWN (row 0 is the top row of the image, the layout of every
// buffer) and measured from pixel centres: pixel (i, j) is sampled at (i, j), which is
// fixed point (i << 8, j << 8).

#include <algorithm>
#include <cstdint>
#include <utility>

#include <vector>

#include "core/check.hpp"
#include "core/default_init.hpp"
#include "core/large_pages.hpp"
#include "core/trace.hpp"
#include "hsr/scene.hpp"
#include "raster/depth.hpp"

namespace hsr::detail {

inline constexpr int kSubpixelBits = 8;  // 8 sub-pixel bits, as Mesa's llvmpipe
inline constexpr int kSubpixelOne = 1 << kSubpixelBits;

// Pixels (i, j) with x0 <= i <= x1 and y0 <= j <= y1; empty when x0 > x1 or y0 > y1.
struct PixelBox {
  int x0, y0, x1, y1;
  bool empty() const { return x0 > x1 || y0 > y1; }
};

// The outline around a box's pixels (along their edges, centres at integers), for the
// teaching view's pictures.
inline TraceOutline pixelBoxOutline(const PixelBox& b) {
  const float x0 = static_cast<float>(b.x0) - 0.5f, y0 = static_cast<float>(b.y0) - 0.5f;
  const float x1 = static_cast<float>(b.x1) + 0.5f, y1 = static_cast<float>(b.y1) + 0.5f;
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

// A triangle snapped to the sub-pixel grid. Vertices are ordered so the doubled signed area
// (y down) is positive, i.e. every edge function is > 0 inside.
struct ScreenTriangle {
  std::int32_t x[3], y[3];      // 24.8 fixed point
  std::int16_t x0, y0, x1, y1;  // inclusive pixel bounding box, clamped to the viewport
  DepthPlane depth;             // its polygon's depth plane: THE depth (raster/depth.hpp)
  PolygonId id;
  std::uint32_t rgba;  // shaded colour, R in the low byte, alpha in the high byte

  PixelBox box() const { return {x0, y0, x1, y1}; }
  // Alpha below 1: blended over what it covers, in a second pass, without depth or id.
  bool transparent() const { return (rgba >> 24) != 0xFFu; }
};
static_assert(sizeof(ScreenTriangle) == 64, "a screen triangle fills one cache line");

// The pipeline's output of triangles: resizing it before the parallel copy fills nothing, and
// a large one lies on huge pages (core/large_pages.hpp).
using ScreenTriangles =
    std::vector<ScreenTriangle,
                DefaultInitAllocator<ScreenTriangle, LargePageAllocator<ScreenTriangle>>>;

// The polygons of the pipeline's triangles, for the algorithms that reason about polygons
// (scan-line, Warnock): a polygon is a run of consecutive triangles with the same id, depth
// plane and colour (a non-planar polygon's triangles have planes of their own: each is a
// polygon). Fills polygon_of[i] with the index of the first triangle of triangle i's polygon,
// so polygon numbers increase in submission order; returns how many polygons there are.
std::uint64_t numberPolygons(const ScreenTriangles& tris, std::vector<std::uint32_t>& polygon_of);

// Whether triangle b, following a, goes on with a's polygon (the rule above).
bool samePolygon(const ScreenTriangle& a, const ScreenTriangle& b);

// The same numbering in a bit per triangle (does it start a polygon?), for an algorithm whose
// memory must stay small (scan-line): polygonOf(i) is the nearest start at or before i, found
// in O(1) words for a polygon of up to 4096 triangles, O(its length / 4096) beyond.
class PolygonStarts {
 public:
  std::uint64_t build(const ScreenTriangles& tris);  // returns how many polygons there are
  std::uint32_t polygonOf(std::uint32_t triangle) const;
  std::size_t bytes() const { return (bits_.capacity() + summary_.capacity()) * 8; }

 private:
  std::vector<std::uint64_t> bits_;     // bit i: triangle i starts a polygon
  std::vector<std::uint64_t> summary_;  // bit w: word w of bits_ holds a start
};

// A line segment or point in the same window space, float coordinates (pixel centres at
// integers), for polygon mode LINE/POINT and outline drawing; depth interpolated linearly.
struct ScreenLine {
  float x0, y0, z0, x1, y1, z1;
  PolygonId id;
  std::uint32_t rgba;
  PolygonId other = kNoPolygon;  // outline: the polygon on the other side of the edge
};

// What became of a triangle offered to makeScreenTriangle.
enum class TriangleFate {
  kMade,                // *out holds it
  kZeroArea,            // zero area on the sub-pixel grid: draws nothing, as in OpenGL
  kMissesPixelCentres,  // its bounding box holds no pixel centre of the viewport
};

// The screen triangle through three snapped vertices (24.8 fixed point, coordinates as
// above, |x|, |y| < 2^30) in a width x height viewport, with the given depth plane.
// `orientation` is windowOrientation() of the vertices as given (+1 counter-clockwise in
// GL's y-up window, -1 clockwise); the vertices are reordered to positive y-down area.
// With a `margin` (sub-pixel units), the box holds every pixel whose centre lies within that
// distance of the triangle's bounds along x and y: kSampleMargin, half a pixel, reaches every
// sub-pixel sample (raster/samples.hpp), and a triangle between pixel centres is then made too.
inline constexpr int kSampleMargin = kSubpixelOne / 2;
[[gnu::always_inline]] inline TriangleFate makeScreenTriangle(const std::int64_t fx[3],
                                                              const std::int64_t fy[3],
                                                              int orientation, int width,
                                                              int height, const DepthPlane& depth,
                                                              ScreenTriangle* out, int margin = 0) {
  if (orientation == 0) return TriangleFate::kZeroArea;
  // Order the vertices so the y-down area is positive (every edge function > 0 inside):
  // counter-clockwise in y-up is negative area in y-down.
  int o[3] = {0, 1, 2};
  if (orientation > 0) std::swap(o[1], o[2]);
  // Pixel bounding box (pixel centres are at multiples of 256), clamped to the viewport.
  auto ceilPixel = [](std::int64_t a) { return -((-a) >> kSubpixelBits); };
  const std::int64_t bx0 =
      std::max<std::int64_t>(0, ceilPixel(std::min({fx[0], fx[1], fx[2]}) - margin));
  const std::int64_t by0 =
      std::max<std::int64_t>(0, ceilPixel(std::min({fy[0], fy[1], fy[2]}) - margin));
  const std::int64_t bx1 = std::min<std::int64_t>(
      width - 1, (std::max({fx[0], fx[1], fx[2]}) + margin) >> kSubpixelBits);
  const std::int64_t by1 = std::min<std::int64_t>(
      height - 1, (std::max({fy[0], fy[1], fy[2]}) + margin) >> kSubpixelBits);
  if (bx0 > bx1 || by0 > by1) return TriangleFate::kMissesPixelCentres;
  ScreenTriangle& t = *out;
  // The box lies in the viewport and the vertices within the 2^30 the int32 fields hold.
  HSR_CHECK(bx1 < 32768 && by1 < 32768);
  for (int k = 0; k < 3; ++k) {
    t.x[k] = static_cast<std::int32_t>(fx[o[k]]);
    t.y[k] = static_cast<std::int32_t>(fy[o[k]]);
  }
  t.x0 = static_cast<std::int16_t>(bx0);
  t.y0 = static_cast<std::int16_t>(by0);
  t.x1 = static_cast<std::int16_t>(bx1);
  t.y1 = static_cast<std::int16_t>(by1);
  t.depth = depth;
  return TriangleFate::kMade;
}

// OpenGL's facing rule: the sign of a snapped triangle's area in window coordinates (y up).
// +1 counter-clockwise, -1 clockwise, 0 zero area.
inline int windowOrientation(const std::int64_t x[3], const std::int64_t y_down[3]) {
  const std::int64_t area =
      (x[1] - x[0]) * (y_down[2] - y_down[0]) - (y_down[1] - y_down[0]) * (x[2] - x[0]);
  // y-down flips the sign: negative y-down area is counter-clockwise in GL's y-up window.
  return area < 0 ? 1 : (area > 0 ? -1 : 0);
}

}  // namespace hsr::detail
