// Exact fixed-point triangle setup (Pineda 1988 edge functions; the fill rule as in
// Direct3D/OpenGL implementations such as Mesa's llvmpipe).

#include "raster/edge.hpp"

#include <algorithm>

namespace hsr::detail {

TriangleSetup setupTriangle(const ScreenTriangle& t, int first_row) {
  TriangleSetup s;
  s.x0 = t.x0;
  s.x1 = t.x1;
  s.y0 = t.y0;
  s.y1 = t.y1;
  const std::int64_t py = static_cast<std::int64_t>(first_row) * kSubpixelOne;
  for (int k = 0; k < 3; ++k) {
    const std::int64_t ax = t.x[k], ay = t.y[k];
    const std::int64_t bx = t.x[(k + 1) % 3], by = t.y[(k + 1) % 3];
    const std::int64_t dx = bx - ax, dy = by - ay;
    // The edges that own the pixel centres lying exactly on them: a left edge (the inside to
    // its right), and a horizontal edge with the inside above it in the image (in GL's y-up
    // window, the triangle's bottom edge). That is llvmpipe's rule for a window-system buffer
    // (which it rasterizes with rows reversed): a horizontal edge through pixel centres made
    // by near-plane clipping once left a whole row empty where Mesa drew it.
    const bool top_left = (dy < 0) || (dy == 0 && dx < 0);
    EdgeSetup& e = s.edge[k];
    e.step_x = -dy * kSubpixelOne;
    e.step_y = dx * kSubpixelOne;
    // E(i*256, py) = dx*(py - ay) - dy*(i*256 - ax)
    e.row = dx * (py - ay) + dy * ax + (top_left ? 0 : -1);
  }
  return s;
}

bool spanOfRow(const TriangleSetup& s, int* lo, int* hi) {
  std::int64_t l = *lo, h = *hi;
  for (const EdgeSetup& e : s.edge) {
    // Need step_x * i + row >= 0.
    if (e.step_x > 0) {
      l = std::max(l, ceilDiv(-e.row, e.step_x));
    } else if (e.step_x < 0) {
      h = std::min(h, floorDiv(e.row, -e.step_x));
    } else if (e.row < 0) {
      return false;
    }
  }
  if (l > h) return false;
  *lo = static_cast<int>(l);
  *hi = static_cast<int>(h);
  return true;
}

}  // namespace hsr::detail
