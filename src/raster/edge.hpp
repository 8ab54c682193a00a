#pragma once
// The one exact triangle setup shared by everything that rasterizes: integer edge functions
// on 24.8 fixed-point vertices (Pineda 1988), the fill rule as an integer bias, and
// exact span limits per row. Guarantee: triangles that share an edge cover each pixel centre
// on it exactly once (no gaps, no double hits), independently of the order they are drawn in.

#include <climits>
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
inline std::int64_t floorDiv(std::int64_t a, std::int64_t b);
inline std::int64_t ceilDiv(std::int64_t a, std::int64_t b);

// Row after row, the spans spanOfRow gives, without its divisions: each edge's limit on the
// row is an exact quotient, and from one row to the next its numerator changes by the same
// step, so quotient and remainder are carried and corrected by one comparison (Bresenham's
// idea), without a branch. Integers only: the same spans, bit for bit
// (tests/raster/edge_test.cpp).
class RowSpans {
 public:
  explicit RowSpans(const TriangleSetup& s) {
    for (int k = 0; k < 3; ++k) {
      const EdgeSetup& e = s.edge[k];
      Limit& l = limit_[k];
      if (e.step_x > 0) {  // a left limit: q = ceil(-row / d), r = q * d + row
        l.d = e.step_x;
        l.q = ceilDiv(-e.row, l.d);
        l.r = l.q * l.d + e.row;
        l.dq = floorDiv(-e.step_y, l.d);
        l.dr = -e.step_y - l.dq * l.d;
        l.left = -1;
      } else if (e.step_x < 0) {  // a right limit: q = floor(row / d), r = d - 1 - (row - q * d)
        l.d = -e.step_x;
        l.q = floorDiv(e.row, l.d);
        l.r = l.d - 1 - (e.row - l.q * l.d);
        l.dq = floorDiv(e.step_y, l.d);
        l.dr = e.step_y - l.dq * l.d;
        l.right = -1;
      } else {  // a horizontal edge: q is the row's value, the whole row inside or outside
        l.q = e.row;
        l.dq = e.step_y;
      }
    }
  }
  // spanOfRow for the current row.
  bool span(int* lo, int* hi) const {
    constexpr std::int64_t kMin = INT64_MIN, kMax = INT64_MAX;
    std::int64_t a = *lo, b = *hi;
    bool outside = false;
    for (const Limit& l : limit_) {
      const std::int64_t low = l.left ? l.q : kMin, high = l.right ? l.q : kMax;
      a = a > low ? a : low;
      b = b < high ? b : high;
      outside |= !(l.left | l.right) & (l.q < 0);
    }
    if (outside || a > b) return false;
    *lo = static_cast<int>(a);
    *hi = static_cast<int>(b);
    return true;
  }
  // nextRow: numerator + step = (q + dq) * d - (r - dr), corrected once when r - dr < 0 (a
  // horizontal edge has d = dr = r = 0 and only adds its step).
  void next() {
    for (Limit& l : limit_) {
      l.q += l.dq;
      l.r -= l.dr;
      const std::int64_t borrow = l.r >> 63;  // -1 when r went below 0
      l.q -= borrow;
      l.r += l.d & borrow;
    }
  }

 private:
  struct Limit {
    std::int64_t q = 0;   // the limit (for a horizontal edge, the row's value)
    std::int64_t r = 0;   // remainder, in [0, d)
    std::int64_t d = 0;   // divisor: |step_x|
    std::int64_t dq = 0;  // quotient and remainder of the numerator's change per row
    std::int64_t dr = 0;
    std::int64_t left = 0;   // -1: a lower limit on the column
    std::int64_t right = 0;  // -1: an upper limit
  };
  Limit limit_[3];
};

inline std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}
inline std::int64_t ceilDiv(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && a > 0) ? q + 1 : q;
}

}  // namespace hsr::detail
