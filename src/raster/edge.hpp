#pragma once
// The one exact triangle setup shared by everything that rasterizes: integer edge functions
// on 24.8 fixed-point vertices (Pineda 1988), the fill rule as an integer bias, and
// exact span limits per row. Guarantee: triangles that share an edge cover each pixel centre
// on it exactly once (no gaps, no double hits), independently of the order they are drawn in.

#include <cstdint>

#include "raster/primitives.hpp"

namespace hsr::detail {

// Edge function E(p) = dx*(py - ay) - dy*(px - ax) of the directed edge a->b, written as
// E + bias = step_x * i + row_value for pixel column i on the current row. A pixel is inside
// the edge when that is >= 0: E > 0, or E == 0 on an edge that owns its centres (the fill
// rule: a left edge, with the inside to its right, or a horizontal edge with the inside above
// it in the image, as llvmpipe decides on a GL window).
struct EdgeSetup {
  std::int64_t step_x;  // change of the value per pixel column: -dy * 256
  std::int64_t step_y;  // change per pixel row: dx * 256
  std::int64_t row;     // value at column 0 of the current row (bias included)
};

struct TriangleSetup {
  EdgeSetup edge[3];
  int x0, x1, y0, y1;  // inclusive pixel bounding box of the triangle, within the viewport
};

// Setup at row `first_row`. Vertices must have positive y-down area (ScreenTriangle does).
TriangleSetup setupTriangle(const ScreenTriangle& t, int first_row);

// Pixel columns [*lo, *hi] of the current row covered by the triangle, intersected with
// [lo, hi] on entry; returns false when the row is empty. Then call nextRow().
bool spanOfRow(const TriangleSetup& s, int* lo, int* hi);
inline void nextRow(TriangleSetup& s) {
  for (EdgeSetup& e : s.edge) e.row += e.step_y;
}
// Moves the setup down by `rows` rows at once.
inline void skipRows(TriangleSetup& s, int rows) {
  for (EdgeSetup& e : s.edge) e.row += e.step_y * rows;
}

// floor(a / b) and ceil(a / b) for b > 0.
inline std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}
inline std::int64_t ceilDiv(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && a > 0) ? q + 1 : q;
}

}  // namespace hsr::detail
