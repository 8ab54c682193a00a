// The scan-line algorithm (Wylie, Romney, Evans & Erdahl 1967; Bouknight 1970; Watkins 1970;
// the notes' "scan-line algorithm").
//
// The picture is made one row (scan line) at a time, top to bottom, each row left to right,
// with no depth buffer. What the algorithm keeps:
//   - the polygon table: for every polygon its depth plane, colour and id;
//   - the edge table: the polygons' edges, bucketed by the row where they start;
//   - the active edge list (AEL): the edges that cross the current row, sorted by x, and
//     for every polygon an in/out flag.
// For every row:
//   1. move the edges that start on this row from the edge table into the AEL;
//   2. walk the AEL left to right. At each edge, flip its polygon's in/out flag. Between two
//      consecutive edges lies a span of pixels, inside exactly the polygons whose flag is in:
//        none    -> the background shows;
//        one     -> that polygon shows on the whole span, no depth is compared;
//        several -> compare depths, here and only here. The order found on the previous row
//                   is tried first; when one polygon is in front at both ends of the span,
//                   it is in front all along it (planes cannot cross in between unless they
//                   cross at an end); otherwise (an intersection line, or a near tie) the
//                   depths are compared pixel by pixel;
//   3. drop the edges that end on this row; step the others' x by 1/m to the next row and
//      restore the order of the list.
//
// The pipeline hands each polygon over as triangles snapped to the sub-pixel grid, sharing
// the polygon's plane; the edges are those triangles' sides, and where two triangles of one
// polygon meet on a diagonal, the flag flips out and in again at the same x. Coverage is the
// shared edge setup's (raster/edge.hpp), depth the shared fragment depth (raster/depth.hpp)
// and the tie rule the z-buffer's under LESS (the polygon submitted first wins), so the
// picture equals the z-buffer's bit for bit: ids, depth and colour.
//
// Cost: O(edges x rows they cross + pixels + pixels where polygons overlap x overlap);
// memory O(width + polygons): no buffer of depths. Rows run in bands of kBandRows on all
// cores, each band a scan-line pass of its own.
//
// Tests: tests/visibility/scanline_test.cpp and every suite of the registry its capabilities join.

#include "visibility/scanline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/check.hpp"
#include "core/frame.hpp"
#include "core/parallel.hpp"
#include "core/stopwatch.hpp"
#include "raster/edge.hpp"
#include "raster/fragment.hpp"
#include "raster/lines.hpp"
#include "raster/span.hpp"

namespace hsr::detail {
namespace {

// Step names: what `hsr explain scanline` shows.
constexpr std::string_view kStepInitialise = "initialise";
constexpr std::string_view kStepRow = "scan row";
constexpr std::string_view kStepDone = "done";

// Rows per band. Each band starts its own AEL at its first row, so bands run in parallel;
// the size is fixed, so the picture and every count are the same at any thread count.
constexpr int kBandRows = 32;

// How many triangles ahead the edge table's entries are fetched into the cache.
constexpr std::uint32_t kPrefetch = 8;

// ---------------------------------------------------------------------------------------------
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
EdgeRows rowsOfEdge(const ScreenTriangle& t, int k) {
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
EdgeRows rowsOfTriangle(const ScreenTriangle& t) {
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

Sides sidesOf(const ScreenTriangle& t) {
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

// What the walk reads of an active edge, in the list's order.
struct Crossing {
  std::int32_t x;
  std::uint32_t polygon;
  std::int16_t flip;
  bool transparent;
};

int flipColumn(const ActiveEdge& e) {
  const std::int64_t x = e.flip > 0 ? -e.q : e.q + 1;
  return static_cast<int>(std::min<std::int64_t>(std::max<std::int64_t>(x, e.x_min), e.x_max));
}

// Edge `k` of triangle `tri`, set up at row y (the shared edge setup's formula).
void startEdge(const ScreenTriangle& t, std::uint32_t tri, std::uint32_t polygon, int k, int y,
               std::int8_t next_edge, ActiveEdge& e) {
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

void stepEdge(ActiveEdge& e) {
  const std::int64_t rem = e.rem + e.drem;
  const bool carry = rem >= e.den;  // (without a branch: the carry comes as the slope says)
  e.rem = rem - (carry ? e.den : 0);
  e.q += e.dq + carry;
  e.x = flipColumn(e);
}

// Both sides of a triangle entering the AEL at row y (its first row, or a band's first row
// when it began above the band: a bent side then starts on the edge that holds row y).
void enterTriangle(const ScreenTriangles& tris, std::uint32_t tri, std::uint32_t polygon, int y,
                   std::vector<ActiveEdge>& out) {
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

// ---------------------------------------------------------------------------------------------
// The shared state of one frame's pass: the polygon and edge tables.

// The edge table's bucket of a row lists its triangles in increasing order, each as the
// difference from the one before in 7-bit groups (LEB128: most take two bytes where an index
// would take four), so the table stays a small part of the frame's memory.
int deltaBytes(std::uint32_t delta) {
  return delta < (1u << 7)    ? 1
         : delta < (1u << 14) ? 2
         : delta < (1u << 21) ? 3
         : delta < (1u << 28) ? 4
                              : 5;
}

std::uint8_t* putDelta(std::uint8_t* out, std::uint32_t delta) {
  for (; delta >= 0x80; delta >>= 7) *out++ = static_cast<std::uint8_t>(delta | 0x80);
  *out++ = static_cast<std::uint8_t>(delta);
  return out;
}

// Reads one row's bucket, triangle by triangle.
struct BucketReader {
  const std::uint8_t* at;
  const std::uint8_t* end;
  std::uint32_t triangle = 0;
  bool next(std::uint32_t& out) {
    if (at == end) return false;
    std::uint32_t delta = 0;
    for (int shift = 0;; shift += 7) {
      const std::uint8_t b = *at++;
      delta |= static_cast<std::uint32_t>(b & 0x7F) << shift;
      if (b < 0x80) break;
    }
    out = triangle += delta;
    return true;
  }
};

struct Tables {
  const ScreenTriangles* tris = nullptr;
  PolygonStarts polygon_starts;           // the polygon table: triangle -> its polygon
  std::vector<std::size_t> bucket_start;  // the edge table: row -> its bucket's first byte
  std::vector<std::uint8_t> buckets;      // the triangles whose edges enter on each row
  std::uint64_t polygons = 0;
  EdgeRows rows{0, -1};  // the first and last row any triangle covers
  BucketReader bucket(int y) const {
    return {buckets.data() + bucket_start[y], buckets.data() + bucket_start[y + 1]};
  }
  std::size_t bytes() const {
    return polygon_starts.bytes() + bucket_start.capacity() * sizeof(std::size_t) +
           buckets.capacity();
  }
};

// Fills the polygon table and buckets each triangle by the row where its edges enter the
// AEL: its first row, or the first row of each later band it reaches (bands start afresh).
void buildTables(const ScreenTriangles& tris, int height, int band_rows, Tables& tb) {
  tb.tris = &tris;
  tb.polygons = tb.polygon_starts.build(tris);  // the polygon table (raster/primitives.hpp)
  tb.rows = {0, -1};
  auto forEachEntry = [&](auto&& f) {
    for (std::size_t i = 0; i < tris.size(); ++i) {
      const EdgeRows rows = rowsOfTriangle(tris[i]);
      const int first = rows.first, last = rows.last;
      if (first > last) continue;
      if (tb.rows.first > tb.rows.last) tb.rows = rows;
      tb.rows = {std::min(tb.rows.first, first), std::max(tb.rows.last, last)};
      f(first, i);
      for (int b = (first / band_rows + 1) * band_rows; b <= last; b += band_rows) f(b, i);
    }
  };
  // Each row's size in bytes, then the entries themselves.
  std::vector<std::uint32_t> last(static_cast<std::size_t>(height), 0);  // each row's last entry
  tb.bucket_start.assign(static_cast<std::size_t>(height) + 1, 0);
  forEachEntry([&](int row, std::size_t i) {
    tb.bucket_start[row + 1] += deltaBytes(static_cast<std::uint32_t>(i) - last[row]);
    last[row] = static_cast<std::uint32_t>(i);
  });
  for (int y = 0; y < height; ++y) tb.bucket_start[y + 1] += tb.bucket_start[y];
  tb.buckets.resize(tb.bucket_start[height]);
  std::vector<std::size_t> fill(tb.bucket_start.begin(), tb.bucket_start.end() - 1);
  std::fill(last.begin(), last.end(), 0);
  forEachEntry([&](int row, std::size_t i) {
    const std::uint8_t* end =
        putDelta(tb.buckets.data() + fill[row], static_cast<std::uint32_t>(i) - last[row]);
    fill[row] = static_cast<std::size_t>(end - tb.buckets.data());
    last[row] = static_cast<std::uint32_t>(i);
  });
}

// ---------------------------------------------------------------------------------------------
// One band's pass.

struct Counts {
  std::uint64_t rows = 0, edges_entered = 0, max_active = 0, edge_rows = 0;
  std::uint64_t spans = 0, spans_one = 0, spans_several = 0;
  std::uint64_t order_reused = 0, decided_at_ends = 0, pixel_by_pixel = 0, short_spans = 0;
  FragmentCounts fragments;
  void add(const Counts& o) {
    rows += o.rows, edges_entered += o.edges_entered, edge_rows += o.edge_rows,
        max_active = std::max(max_active, o.max_active);
    spans += o.spans, spans_one += o.spans_one, spans_several += o.spans_several;
    order_reused += o.order_reused, decided_at_ends += o.decided_at_ends,
        pixel_by_pixel += o.pixel_by_pixel, short_spans += o.short_spans;
    fragments += o.fragments;
  }
};

// A polygon the walk is inside, with how many of its triangles it is inside (the in/out flag:
// more than one only where a polygon's own triangles overlap).
struct Inside {
  std::uint32_t polygon;
  std::int32_t count;
};

struct BandState {
  std::vector<ActiveEdge> ael;           // the active edges, in order of x when there are few
  std::vector<Crossing> crossings;       // the list's order: the edges' crossings of the row, by x
  std::vector<std::uint32_t> key_start;  // the counting sort's buckets: O(width)
  std::vector<Inside> opaque, transparent;  // the walk's flags
  std::vector<std::uint32_t> order;         // see-through polygons in submission order
  std::vector<double> near_a, near_b;
  std::size_t bytes() const {
    return ael.capacity() * sizeof(ActiveEdge) + crossings.capacity() * sizeof(Crossing) +
           key_start.capacity() * 4 +
           (opaque.capacity() + transparent.capacity()) * sizeof(Inside) + order.capacity() * 4 +
           (near_a.capacity() + near_b.capacity()) * 8;
  }
};

// The walk's flags: the polygons it is inside, opaque and see-through apart, in no particular
// order (there are few). Where `polygon` is, or inside.size(): every entry is looked at, with
// no branch to mispredict (whether a polygon is met for the first time cannot be foreseen).
std::size_t findInside(const std::vector<Inside>& inside, std::uint32_t polygon) {
  std::size_t k = inside.size();
  for (std::size_t j = 0; j < inside.size(); ++j) k = inside[j].polygon == polygon ? j : k;
  return k;
}

class BandPass {
 public:
  BandPass(const Tables& tb, const FrameView& fb, SpanFn span, BandState& st, Counts& c,
           ScanlineObserver* observer, const AlgorithmInput& in, Frame& frame)
      : tb_(tb),
        tris_(*tb.tris),
        fb_(fb),
        span_(span),
        st_(st),
        c_(c),
        observer_(observer),
        in_(in),
        frame_(frame) {}

  void run(int first_row, int end_row) {
    std::vector<ActiveEdge>& ael = st_.ael;
    ael.clear();
    first_row_ = first_row;
    for (int y = first_row; y < end_row; ++y) {
      // 1. Edges starting on this row join the list; the list is put in order of x.
      // The triangles are scattered in memory: a second reader runs ahead, asking for them early.
      BucketReader bucket = tb_.bucket(y), ahead = tb_.bucket(y);
      std::uint32_t tri = 0, next = 0;
      for (std::uint32_t k = 0; k < kPrefetch && ahead.next(next); ++k)
        __builtin_prefetch(&tris_[next]);
      while (bucket.next(tri)) {
        if (ahead.next(next)) __builtin_prefetch(&tris_[next]);
        const std::size_t before = ael.size();
        enterTriangle(tris_, tri, tb_.polygon_starts.polygonOf(tri), y, ael);
        c_.edges_entered += ael.size() - before;
      }
      sortByX();
      c_.max_active = std::max<std::uint64_t>(c_.max_active, ael.size());
      c_.edge_rows += ael.size();
      c_.rows++;

      // 2. The walk along the row.
      const bool show =
          in_.trace && y >= trace_rows_.first && y <= trace_rows_.last &&
          in_.trace->wants(kStepRow, static_cast<std::uint64_t>(y - trace_rows_.first),
                           static_cast<std::uint64_t>(trace_rows_.last - trace_rows_.first + 1));
      notes_.clear();
      notes_shown_ = 0;
      noting_ = show;
      walkRow(y);
      if (show) traceRow(y);

      // 3. Edges ending here leave (a bent side goes on with its second edge; the last edge
      // takes the place of one that leaves). The others step to the next row.
      for (std::size_t i = 0; i < ael.size();) {
        ActiveEdge& e = ael[i];
        if (e.last_row > y) {
          stepEdge(e);
        } else if (e.next_edge >= 0 && y + 1 <= rowsOfEdge(tris_[e.triangle], e.next_edge).last) {
          startEdge(tris_[e.triangle], e.triangle, e.polygon, e.next_edge, y + 1, -1, e);
        } else {
          e = ael.back();
          ael.pop_back();
          continue;
        }
        ++i;
      }
    }
    // After the band's last row, only edges going on below it may be left (the next band sets
    // them up itself); after the picture's last row, none.
    std::size_t left = 0;
    for (const ActiveEdge& e : ael) left += e.last_row < end_row || end_row == fb_.height;
    HSR_CHECK_EQ(left, 0u);
    if (observer_ && end_row == fb_.height) observer_->finished(ael.size());
  }

 private:
  // The AEL's order: by x, and at one x entering edges first.
  static bool byX(const ActiveEdge& a, const ActiveEdge& b) {
    return a.x < b.x || (a.x == b.x && a.flip > b.flip);
  }

  // The AEL in order of x, entering edges first at one x: st_.crossings. Few edges: an
  // insertion sort of the list itself, as the notes keep it (edges cross rarely in a big
  // polygon). Many: in a dense mesh they cross all the time (a small triangle's sides meet at
  // its corners), and since x is a pixel column, a counting sort by x puts the crossings in
  // order in O(width + edges), the edges staying where they are.
  void sortByX() {
    std::vector<ActiveEdge>& ael = st_.ael;
    std::vector<Crossing>& out = st_.crossings;
    auto crossing = [](const ActiveEdge& e) {
      return Crossing{e.x, e.polygon, e.flip, e.transparent};
    };
    out.resize(ael.size());
    if (ael.size() < 64) {
      for (std::size_t i = 1; i < ael.size(); ++i) {
        const ActiveEdge e = ael[i];
        std::size_t j = i;
        for (; j > 0 && byX(e, ael[j - 1]); --j) ael[j] = ael[j - 1];
        ael[j] = e;
      }
      for (std::size_t i = 0; i < ael.size(); ++i) out[i] = crossing(ael[i]);
      return;
    }
    // key = 2 x + (leaving): entering edges first
    auto key = [](const ActiveEdge& e) { return 2 * static_cast<std::size_t>(e.x) + (e.flip < 0); };
    std::vector<std::uint32_t>& start = st_.key_start;
    start.assign(2 * static_cast<std::size_t>(fb_.width) + 3, 0);
    std::size_t lo = start.size(), hi = 0;  // the keys' range: the prefix sum needs no more
    for (const ActiveEdge& e : ael) {
      const std::size_t k = key(e);
      start[k + 1]++;
      lo = std::min(lo, k), hi = std::max(hi, k);
    }
    for (std::size_t k = lo + 1; k <= hi; ++k) start[k] += start[k - 1];
    for (const ActiveEdge& e : ael) out[start[key(e)]++] = crossing(e);
  }

  void walkRow(int y) {
    const std::vector<Crossing>& ael = st_.crossings;
    st_.opaque.clear();
    st_.transparent.clear();
    int x = 0;  // the start of the current span
    for (std::size_t i = 0; i < ael.size();) {
      // The edges at one x flip their flags together, entering edges first. Where they leave
      // the same polygons in (two triangles of one polygon meeting on a diagonal: 1 -> 2 -> 1)
      // the span goes on; otherwise the span so far is finished before the first flag that
      // changes.
      const int at = ael[i].x;
      for (; i < ael.size() && ael[i].x == at; ++i) {
        const Crossing& e = ael[i];
        std::vector<Inside>& inside = e.transparent ? st_.transparent : st_.opaque;
        const std::size_t k = findInside(inside, e.polygon);
        const bool in = k < inside.size();
        const bool changes = !in || inside[k].count + e.flip == 0;
        if (changes && at > x) {
          resolveSpan(y, x, at);
          x = at;
        }
        if (!in) {
          inside.push_back({e.polygon, e.flip});        // -1 only for a moment: an exit before
        } else if ((inside[k].count += e.flip) == 0) {  // its entry at one x
          inside[k] = inside.back();
          inside.pop_back();
        }
      }
    }
    HSR_CHECK(st_.opaque.empty() && st_.transparent.empty());  // every triangle entered was left
    if (x < fb_.width) resolveSpan(y, x, fb_.width);
  }

  // Columns [xa, xb) of row y, inside the polygons of st_.opaque and st_.transparent.
  void resolveSpan(int y, int xa, int xb) {
    HSR_CHECK(0 <= xa && xa < xb && xb <= fb_.width);
    const std::vector<Inside>& opaque = st_.opaque;
    const std::vector<Inside>& transparent = st_.transparent;
    if (observer_) observer_->span(y, xa, xb, opaque.size() + transparent.size());
    if (opaque.empty() && transparent.empty()) return;  // background: render() has cleared it
    c_.spans++;
    const char* how = "see-through only";
    if (opaque.size() == 1) {
      c_.spans_one++;
      how = "one polygon";
      fill(opaque[0].polygon, y, xa, xb);
    } else if (opaque.size() > 1 && xb - xa <= 2) {
      // One or two pixels: the span's ends are all its pixels.
      c_.spans_several++;
      c_.short_spans++;
      how = "one or two pixels, compared at each";
      pixelByPixel(y, xa, xb);
    } else if (opaque.size() > 1) {
      c_.spans_several++;
      const std::uint32_t front = frontOnWholeSpan(y, xa, xb, &how);
      if (front != kNone)
        fill(front, y, xa, xb);
      else
        pixelByPixel(y, xa, xb);
    }
    if (!transparent.empty()) blendTransparent(y, xa, xb);
    if (noting_ && notes_shown_++ < 8) {
      std::string ids;
      for (const auto* list : {&opaque, &transparent})
        for (const Inside& p : *list) {
          if (!ids.empty()) ids += '+';
          ids += std::to_string(tris_[p.polygon].id);
        }
      if (!notes_.empty()) notes_ += "; ";
      notes_ += "[" + std::to_string(xa) + ", " + std::to_string(xb) + ") in " + ids + ": " + how;
    }
  }

  static constexpr std::uint32_t kNone = ~0u;

  // The one polygon in front of the others at both ends of the span, by a margin that no
  // rounding can close, or kNone. The previous row's polygon at the span's start is tried
  // first: where it still holds, that row's order is reused.
  std::uint32_t frontOnWholeSpan(int y, int xa, int xb, const char** how) {
    *how = "compared pixel by pixel";
    const std::vector<Inside>& opaque = st_.opaque;
    std::vector<double>& a = st_.near_a;
    std::vector<double>& b = st_.near_b;
    a.resize(opaque.size());
    b.resize(opaque.size());
    for (std::size_t i = 0; i < opaque.size(); ++i) {
      const DepthPlane& p = tris_[opaque[i].polygon].depth;
      if (!planeDepthIsSafe(p, xa, y) || !planeDepthIsSafe(p, xb - 1, y)) {
        c_.pixel_by_pixel++;
        return kNone;
      }
      a[i] = planeDepth(p, xa, y);
      b[i] = planeDepth(p, xb - 1, y);
    }
    auto inFront = [&](std::size_t w) {
      if (!(a[w] >= 0.0 && a[w] <= 1.0 && b[w] >= 0.0 && b[w] <= 1.0)) return false;
      for (std::size_t i = 0; i < opaque.size(); ++i)
        if (i != w && !(a[w] + kSafeDepthGap <= a[i] && b[w] + kSafeDepthGap <= b[i])) return false;
      return true;
    };
    // The previous row's order: the polygon shown above the span's first pixel.
    if (y > first_row_) {
      const PolygonId above = fb_.ids[fb_.index(xa, y - 1)];
      for (std::size_t i = 0; i < opaque.size(); ++i)
        if (tris_[opaque[i].polygon].id == above && inFront(i)) {
          c_.order_reused++;
          *how = "previous row's order holds";
          return opaque[i].polygon;
        }
    }
    std::size_t nearest = 0;
    for (std::size_t i = 1; i < opaque.size(); ++i)
      if (a[i] < a[nearest]) nearest = i;
    if (inFront(nearest)) {
      c_.decided_at_ends++;
      *how = "decided at its ends";
      return opaque[nearest].polygon;
    }
    c_.pixel_by_pixel++;
    return kNone;
  }

  // The whole span shows `polygon`: its fragments, each tested only against the cleared
  // depth (a depth at the far plane or beyond is not drawn, as under the z-buffer's LESS).
  void fill(std::uint32_t polygon, int y, int xa, int xb) {
    span_(tris_[polygon], fb_, y, xa, xb - 1, true, c_.fragments);
  }

  // Where planes cross (or nearly tie) inside the span: at every pixel, the nearest; of equal
  // depths the polygon submitted first (the lowest number), the z-buffer's rule under LESS.
  void pixelByPixel(int y, int xa, int xb) {
    const std::vector<Inside>& opaque = st_.opaque;
    for (int x = xa; x < xb; ++x) {
      const std::size_t k = fb_.index(x, y);
      std::uint32_t best = kNone;
      float best_z = std::numeric_limits<float>::infinity();  // (NaN never wins, as under LESS)
      for (const Inside& p : opaque) {
        const float z = fragmentDepth(tris_[p.polygon].depth, x, y);
        if (z < best_z || (z == best_z && p.polygon < best)) best = p.polygon, best_z = z;
      }
      c_.fragments.tested += opaque.size();
      if (best == kNone) continue;
      if (!(best_z < fb_.depth[k])) continue;  // at or beyond the cleared depth
      const ScreenTriangle& t = tris_[best];
      c_.fragments.written++;
      fb_.overdraw[k]++;
      fb_.depth[k] = best_z;
      fb_.ids[k] = t.id;
      fb_.rgba[k] = t.rgba;
    }
  }

  // See-through polygons (st_.transparent), after the visible opaque one: blended over it in
  // submission order where they are nearer than it, leaving its depth and id (the z-buffer's
  // second pass).
  void blendTransparent(int y, int xa, int xb) {
    std::vector<std::uint32_t>& order = st_.order;
    order.clear();
    for (const Inside& p : st_.transparent) order.push_back(p.polygon);
    std::sort(order.begin(), order.end());  // submission order
    for (const std::uint32_t p : order) {
      const ScreenTriangle& t = tris_[p];
      const double row = depthRowStart(t.depth, y);
      for (int x = xa; x < xb; ++x) {
        const std::size_t k = fb_.index(x, y);
        c_.fragments.tested++;
        if (!(depthInRow(row, t.depth, x) < fb_.depth[k])) continue;
        c_.fragments.written++;
        fb_.overdraw[k]++;
        fb_.rgba[k] = blendOver(t.rgba, fb_.rgba[k]);
      }
    }
  }

  // The teaching view: the row, each edge of the AEL as a tick where it flips its polygon's
  // flag, and the list spelled out.
  void traceRow(int y) {
    std::vector<TraceOutline> outlines;
    const float fy = static_cast<float>(y);
    outlines.push_back({{-0.5f, fy - 0.5f},
                        {fb_.width - 0.5f, fy - 0.5f},
                        {fb_.width - 0.5f, fy + 0.5f},
                        {-0.5f, fy + 0.5f}});
    std::string list;
    int shown = 0;
    for (const Crossing& e : st_.crossings) {
      const float fx = static_cast<float>(e.x) - 0.5f;
      outlines.push_back({{fx, fy - 6.0f}, {fx, fy + 6.0f}});
      if (shown++ < 12) {
        if (!list.empty()) list += ", ";
        list += "x=" + std::to_string(e.x) + (e.flip > 0 ? " in " : " out ") +
                std::to_string(tris_[e.polygon].id);
      }
    }
    if (shown > 12) list += ", ... (" + std::to_string(shown - 12) + " more)";
    if (notes_shown_ > 8) notes_ += "; ... (" + std::to_string(notes_shown_ - 8) + " more)";
    in_.trace->record(
        {kStepRow,
         "Row " + std::to_string(y) + ": the active edge list holds " +
             std::to_string(st_.ael.size()) +
             " edges, sorted by x; walking it left to right flips each polygon's "
             "in/out flag (x = the first column inside, or the first past it; the "
             "number is the polygon id): " +
             (list.empty() ? std::string("(empty: the row is background)") : list) +
             (notes_.empty() ? std::string()
                             : ". The spans and the polygons whose flag is in: " + notes_) +
             ". Rows above are finished; the rows below are still empty.",
         &frame_, std::move(outlines)});
  }

  const Tables& tb_;
  const ScreenTriangles& tris_;
  const FrameView& fb_;
  SpanFn span_;
  BandState& st_;
  Counts& c_;
  ScanlineObserver* observer_;
  const AlgorithmInput& in_;
  Frame& frame_;
  int first_row_ = 0;
  EdgeRows trace_rows_{0, -1};  // the rows that hold any triangle: where pictures are worth it
  bool noting_ = false;         // spelling out this row's spans for the picture
  std::string notes_;
  int notes_shown_ = 0;

 public:
  void traceRows(EdgeRows rows) { trace_rows_ = rows; }
};

struct Scratch {
  Tables tables;
  std::vector<BandState> workers;  // one per thread: a band runs on one thread, start to end
};

}  // namespace

void drawScanlineObserved(const AlgorithmInput& in, Frame& frame, ScanlineObserver* observer) {
  detail::Stopwatch watch;
  std::unique_ptr<Scratch> own;
  Scratch& scratch = algorithmScratch(in, own);
  const ScreenTriangles& tris = in.prepared.triangles;
  const FrameView fb(frame);
  const bool one_pass = observer != nullptr || in.trace != nullptr;
  const int band_rows = one_pass ? std::max(1, frame.height) : kBandRows;

  // The polygon table and the edge table.
  Tables& tb = scratch.tables;
  buildTables(tris, frame.height, band_rows, tb);
  frame.stats.addStage("edge table", watch.lap());
  if (in.trace && in.trace->wants(kStepInitialise, 0, 1))
    in.trace->record({kStepInitialise,
                      "Initialise: the polygon table holds " + std::to_string(tb.polygons) +
                          " polygons (plane, colour, id); the edge table holds their triangles' "
                          "edges, bucketed by the row where each starts. The active edge list "
                          "is empty, and there is no depth buffer.",
                      &frame,
                      {}});

  // The rows, band by band.
  const int bands = (frame.height + band_rows - 1) / band_rows;
  const int threads = tbb::this_task_arena::max_concurrency();
  if (scratch.workers.size() < static_cast<std::size_t>(threads)) scratch.workers.resize(threads);
  std::vector<Counts> counts(static_cast<std::size_t>(bands));
  const SpanFn span = spanFunction(DepthFunc::Less);
  auto runBand = [&](int b) {
    const int worker = std::max(0, tbb::this_task_arena::current_thread_index());
    HSR_CHECK_LT(static_cast<std::size_t>(worker), scratch.workers.size());
    BandPass pass(tb, fb, span, scratch.workers[worker], counts[b], observer, in, frame);
    pass.traceRows(tb.rows);
    pass.run(b * band_rows, std::min(frame.height, (b + 1) * band_rows));
  };
  if (one_pass) {
    for (int b = 0; b < bands; ++b) runBand(b);
  } else {
    tbb::parallel_for(0, bands, runBand);
  }
  Counts c;
  for (const Counts& b : counts) c.add(b);

  // Outlines over the finished picture, as every renderer draws them.
  const PixelBox viewport{0, 0, frame.width - 1, frame.height - 1};
  for (const ScreenLine& o : in.prepared.outline) drawOutlinePen(o, viewport, fb);

  if (in.trace && in.trace->wants(kStepDone, 0, 1))
    in.trace->record({kStepDone,
                      "Done: " + std::to_string(c.spans) + " spans inside polygons; " +
                          std::to_string(c.spans_one) +
                          " inside one polygon (no depth compared), " +
                          std::to_string(c.spans_several) + " inside several: " +
                          std::to_string(c.order_reused) + " kept the previous row's order, " +
                          std::to_string(c.decided_at_ends) + " were decided at their ends, " +
                          std::to_string(c.pixel_by_pixel) + " pixel by pixel.",
                      &frame,
                      {}});

  std::size_t worker_bytes = 0;
  for (const BandState& w : scratch.workers) worker_bytes += w.bytes();
  frame.stats.state_bytes += tb.bytes() + worker_bytes;
  frame.stats.fragments_tested += c.fragments.tested;
  frame.stats.fragments_written += c.fragments.written;
  frame.stats.addCounter("scanline: polygons", tb.polygons);
  frame.stats.addCounter("scanline: rows", c.rows);
  frame.stats.addCounter("scanline: edges entered", c.edges_entered);
  frame.stats.addCounter("scanline: most active edges", c.max_active);
  frame.stats.addCounter("scanline: edge crossings (edges x rows)", c.edge_rows);
  frame.stats.addCounter("scanline: spans", c.spans);
  frame.stats.addCounter("scanline: spans inside one polygon", c.spans_one);
  frame.stats.addCounter("scanline: spans inside several", c.spans_several);
  frame.stats.addCounter("scanline: previous row's order reused", c.order_reused);
  frame.stats.addCounter("scanline: decided at the span's ends", c.decided_at_ends);
  frame.stats.addCounter("scanline: compared pixel by pixel", c.pixel_by_pixel);
  frame.stats.addCounter("scanline: one or two pixels, compared at each", c.short_spans);
  frame.stats.addStage("scan lines", watch.ms());
}

void drawScanline(const AlgorithmInput& in, Frame& frame) {
  drawScanlineObserved(in, frame, nullptr);
}

}  // namespace hsr::detail
