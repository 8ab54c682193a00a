#pragma once
// The scan-line algorithm's edges, shared by its two files: scanline.cpp (the notes' loop) and
// scanline_fast.cpp (the same in bands on all cores). An edge of the active edge list steps
// from row to row exactly as the shared edge setup (raster/edge.hpp) bounds the row's span, so
// the flags flip where the z-buffer's coverage begins and ends.
//
// Tests: tests/visibility/scanline_test.cpp; tests/cross/textbook_test.cpp pins the two files.

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "raster/depth.hpp"
#include "raster/edge.hpp"
#include "raster/fragment.hpp"
#include "raster/primitives.hpp"

namespace hsr::detail::scan {
// Edges. Directed edge k of a triangle runs from vertex k to vertex k + 1; with the vertices in
// positive (y-down) order, an edge going up (dy < 0) has the inside on its right: the walk
// ENTERS the triangle there (a left side); an edge going down LEAVES it (a right side).
// Horizontal edges lie along a row and cross none.

struct EdgeRows {
  int first, last;  // rows whose pixel centres it bounds
};

// Which rows edge k bounds. Every row of the triangle has exactly one entering and one leaving
// edge: an edge keeps the rows from its upper end down to, not including, its lower end, and
// the edges at the bottom of the triangle keep the bottom row too. The row on a horizontal top
// edge belongs to no edge: the fill rule gives the centres on a top edge to the polygon above.
inline EdgeRows rowsOfEdge(const ScreenTriangle& t, int k) {
  const std::int64_t ya = t.y[k], yb = t.y[(k + 1) % 3];
  const std::int64_t y_top = std::min({t.y[0], t.y[1], t.y[2]});
  const std::int64_t y_bottom = std::max({t.y[0], t.y[1], t.y[2]});
  const std::int64_t upper = std::min(ya, yb), lower = std::max(ya, yb);
  const bool flat_top = (t.y[0] == y_top) + (t.y[1] == y_top) + (t.y[2] == y_top) == 2;
  std::int64_t first = ceilDiv(upper, kSubpixelOne);
  if (flat_top && upper == y_top && upper % kSubpixelOne == 0) ++first;
  const std::int64_t last =
      lower == y_bottom ? floorDiv(lower, kSubpixelOne) : ceilDiv(lower, kSubpixelOne) - 1;
  return {static_cast<int>(std::max<std::int64_t>(first, t.y0)),
          static_cast<int>(std::min<std::int64_t>(last, t.y1))};
}

// The rows a triangle covers: those of its edges, which are its bounding box's rows but for
// the row on a horizontal top edge.
inline EdgeRows rowsOfTriangle(const ScreenTriangle& t) {
  const std::int64_t y_top = std::min({t.y[0], t.y[1], t.y[2]});
  const bool flat_top = (t.y[0] == y_top) + (t.y[1] == y_top) + (t.y[2] == y_top) == 2;
  const bool skip_top = flat_top && y_top == std::int64_t{t.y0} * kSubpixelOne;
  return {t.y0 + (skip_top ? 1 : 0), t.y1};
}

// A triangle's two sides: the entering edges and the leaving edges, upper one first (a side
// bends at the middle vertex when it has two).
struct Sides {
  std::int8_t entering[2] = {-1, -1}, leaving[2] = {-1, -1};
};

inline Sides sidesOf(const ScreenTriangle& t) {
  Sides s;
  int ne = 0, nl = 0;
  for (int k = 0; k < 3; ++k) {
    const std::int64_t dy = std::int64_t{t.y[(k + 1) % 3]} - t.y[k];
    if (dy < 0) s.entering[ne++] = static_cast<std::int8_t>(k);
    if (dy > 0) s.leaving[nl++] = static_cast<std::int8_t>(k);
  }
  // Upper edge first: the one whose higher end is the triangle's top.
  auto upperFirst = [&](std::int8_t* e, int n) {
    if (n == 2 &&
        std::min(t.y[e[1]], t.y[(e[1] + 1) % 3]) < std::min(t.y[e[0]], t.y[(e[0] + 1) % 3]))
      std::swap(e[0], e[1]);
  };
  upperFirst(s.entering, ne);
  upperFirst(s.leaving, nl);
  return s;
}

// An edge in the active edge list. Its x on a row is the column where its polygon's flag
// flips: an entering edge's first column inside, a leaving edge's first column past the
// triangle. x moves by 1/m per row, kept as a whole part q and a remainder and stepped exactly
// (as Bresenham steps a line), so that x equals the shared edge setup's span limit on every
// row: the edge function's value at column 0 of a row, E, grows by a constant per row, and
// x = floor(E / den) + 1 for a leaving edge, -floor(E / den) for an entering one. The walk
// reads the list's order (Crossing) rather than the edges.
struct ActiveEdge {
  std::int32_t x;
  std::uint32_t polygon;  // the polygon table's number
  std::uint32_t triangle;
  std::int32_t last_row;               // the last row of the current edge
  std::int64_t q, rem, den, dq, drem;  // floor(E / den), E mod den, and their steps per row
  std::int16_t x_min, x_max;           // the triangle's columns, [x0, x1 + 1]
  std::int8_t flip;                    // +1 entering, -1 leaving
  bool transparent;                    // its polygon's
  std::int8_t next_edge;               // a bent side's second edge, or -1
};
static_assert(sizeof(ActiveEdge) == 64, "an active edge fills one cache line");

inline int flipColumn(const ActiveEdge& e) {
  const std::int64_t x = e.flip > 0 ? -e.q : e.q + 1;
  return static_cast<int>(std::min<std::int64_t>(std::max<std::int64_t>(x, e.x_min), e.x_max));
}

// Edge `k` of triangle `tri`, set up at row y (the shared edge setup's formula).
inline void startEdge(const ScreenTriangle& t, std::uint32_t tri, std::uint32_t polygon, int k,
                      int y, std::int8_t next_edge, ActiveEdge& e) {
  const std::int64_t ax = t.x[k], ay = t.y[k];
  const std::int64_t dx = std::int64_t{t.x[(k + 1) % 3]} - ax,
                     dy = std::int64_t{t.y[(k + 1) % 3]} - ay;
  const bool owns_centres = dy < 0 || (dy == 0 && dx < 0);  // the fill rule, as setupTriangle
  const std::int64_t value =
      dx * (std::int64_t{y} * kSubpixelOne - ay) + dy * ax + (owns_centres ? 0 : -1);
  e.polygon = polygon;
  e.triangle = tri;
  e.flip = dy < 0 ? 1 : -1;
  e.transparent = t.transparent();
  e.next_edge = next_edge;
  e.last_row = rowsOfEdge(t, k).last;
  e.x_min = t.x0;
  e.x_max = static_cast<std::int16_t>(t.x1 + 1);
  e.den = std::abs(dy) * kSubpixelOne;  // |step_x|
  e.q = floorDiv(value, e.den);
  e.rem = value - e.q * e.den;
  const std::int64_t step = dx * kSubpixelOne;  // per row
  e.dq = floorDiv(step, e.den);
  e.drem = step - e.dq * e.den;
  e.x = flipColumn(e);
}

inline void stepEdge(ActiveEdge& e) {
  const std::int64_t rem = e.rem + e.drem;
  const bool carry = rem >= e.den;  // (without a branch: the carry comes as the slope says)
  e.rem = rem - (carry ? e.den : 0);
  e.q += e.dq + carry;
  e.x = flipColumn(e);
}

// Both sides of a triangle entering the AEL at row y (its first row, or a band's first row
// when it began above the band: a bent side then starts on the edge that holds row y).
inline void enterTriangle(const ScreenTriangles& tris, std::uint32_t tri, std::uint32_t polygon,
                          int y, std::vector<ActiveEdge>& out) {
  const ScreenTriangle& t = tris[tri];
  const Sides s = sidesOf(t);
  for (const std::int8_t* side : {s.entering, s.leaving}) {
    if (side[0] < 0) continue;  // cannot happen for a triangle of positive area
    ActiveEdge& e = out.emplace_back();
    if (side[1] >= 0 && y > rowsOfEdge(t, side[0]).last)
      startEdge(t, tri, polygon, side[1], y, -1, e);
    else
      startEdge(t, tri, polygon, side[0], y, side[1], e);
  }
}

// See-through polygons over the visible opaque one on columns [xa, xb) of row y: blended over it
// in submission order (`order`: their triangles' numbers, sorted here) where they are nearer
// than it, leaving its depth and id (the z-buffer's second pass).
inline void blendSeeThrough(const ScreenTriangles& tris, const FrameView& fb,
                            std::vector<std::uint32_t>& order, int y, int xa, int xb,
                            FragmentCounts& counts) {
  std::sort(order.begin(), order.end());  // submission order
  for (const std::uint32_t p : order) {
    const ScreenTriangle& t = tris[p];
    const double row = depthRowStart(t.depth, y);
    for (int x = xa; x < xb; ++x) {
      const std::size_t k = fb.index(x, y);
      counts.tested++;
      if (!(depthInRow(row, t.depth, x) < fb.depth[k])) continue;
      counts.written++;
      fb.overdraw[k]++;
      fb.rgba[k] = blendOver(t.rgba, fb.rgba[k]);
    }
  }
}

}  // namespace hsr::detail::scan
