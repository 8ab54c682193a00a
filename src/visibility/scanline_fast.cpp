// The scan-line algorithm reorganised for cores: the same frame as scanline.cpp (the notes'
// loop, one row after another on one core), bit for bit, made faster in four ways:
//   - bands: the rows run in bands of kBandRows on all cores, each band a scan-line pass of its
//     own that sets up the edges crossing its first row (the size is fixed, so the picture and
//     every count are the same at any thread count);
//   - a compressed edge table: each row's bucket lists its triangles as differences in 7-bit
//     groups (most take two bytes where an index takes four), fetched ahead into the cache;
//   - the active edge list kept in order by insertion while it is short and by a counting sort
//     on x (O(width + edges)) while it is long (a dense mesh's edges cross all the time);
//   - spans inside several polygons decided at their ends: the previous row's order is tried
//     first; when one polygon is in front at both ends by a margin no rounding can close, it is
//     in front all along the span (planes cannot cross in between), and the span is filled by
//     the SIMD span path (raster/span.hpp); only where planes cross or nearly tie are depths
//     compared pixel by pixel, as scanline.cpp compares them everywhere.
// The edges themselves step as in scanline.cpp (scanline_edges.hpp).
//
// Guarantee: bit-identical to scanline-textbook (tests/cross/textbook_test.cpp), and so to the
// z-buffer (ids, depth and colour). `hsr explain scanline` walks scanline.cpp.
// Cost: O(edges x rows they cross + pixels + pixels where polygons overlap x overlap);
// memory O(width + polygons) per core: no buffer of depths.
//
// Tests: tests/visibility/scanline_test.cpp and every suite of the registry its capabilities join.

#include "visibility/scanline.hpp"
#include "visibility/scanline_edges.hpp"

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

using scan::ActiveEdge;
using scan::EdgeRows;
using scan::enterTriangle;
using scan::rowsOfEdge;
using scan::rowsOfTriangle;
using scan::startEdge;
using scan::stepEdge;

// Rows per band. Each band starts its own AEL at its first row, so bands run in parallel;
// the size is fixed, so the picture and every count are the same at any thread count.
constexpr int kBandRows = 32;

// How many triangles ahead the edge table's entries are fetched into the cache.
constexpr std::uint32_t kPrefetch = 8;

// What the walk reads of an active edge, in the list's order.
struct Crossing {
  std::int32_t x;
  std::uint32_t polygon;
  std::int16_t flip;
  bool transparent;
};

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
           ScanlineObserver* observer)
      : tb_(tb), tris_(*tb.tris), fb_(fb), span_(span), st_(st), c_(c), observer_(observer) {}

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
      walkRow(y);

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
    if (opaque.size() == 1) {
      c_.spans_one++;
      fill(opaque[0].polygon, y, xa, xb);
    } else if (opaque.size() > 1 && xb - xa <= 2) {
      // One or two pixels: the span's ends are all its pixels.
      c_.spans_several++;
      c_.short_spans++;
      pixelByPixel(y, xa, xb);
    } else if (opaque.size() > 1) {
      c_.spans_several++;
      const std::uint32_t front = frontOnWholeSpan(y, xa, xb);
      if (front != kNone)
        fill(front, y, xa, xb);
      else
        pixelByPixel(y, xa, xb);
    }
    if (!transparent.empty()) blendTransparent(y, xa, xb);
  }

  static constexpr std::uint32_t kNone = ~0u;

  // The one polygon in front of the others at both ends of the span, by a margin that no
  // rounding can close, or kNone. The previous row's polygon at the span's start is tried
  // first: where it still holds, that row's order is reused.
  std::uint32_t frontOnWholeSpan(int y, int xa, int xb) {
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
          return opaque[i].polygon;
        }
    }
    std::size_t nearest = 0;
    for (std::size_t i = 1; i < opaque.size(); ++i)
      if (a[i] < a[nearest]) nearest = i;
    if (inFront(nearest)) {
      c_.decided_at_ends++;
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
    scan::blendSeeThrough(tris_, fb_, order, y, xa, xb, c_.fragments);
  }

  const Tables& tb_;
  const ScreenTriangles& tris_;
  const FrameView& fb_;
  SpanFn span_;
  BandState& st_;
  Counts& c_;
  ScanlineObserver* observer_;
  int first_row_ = 0;
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
  const bool one_pass = observer != nullptr;
  const int band_rows = one_pass ? std::max(1, frame.height) : kBandRows;

  // The polygon table and the edge table.
  Tables& tb = scratch.tables;
  buildTables(tris, frame.height, band_rows, tb);
  frame.stats.addStage("edge table", watch.lap());
  // The rows, band by band.
  const int bands = (frame.height + band_rows - 1) / band_rows;
  const int threads = tbb::this_task_arena::max_concurrency();
  if (scratch.workers.size() < static_cast<std::size_t>(threads)) scratch.workers.resize(threads);
  std::vector<Counts> counts(static_cast<std::size_t>(bands));
  const SpanFn span = spanFunction(DepthFunc::Less);
  auto runBand = [&](int b) {
    const int worker = std::max(0, tbb::this_task_arena::current_thread_index());
    HSR_CHECK_LT(static_cast<std::size_t>(worker), scratch.workers.size());
    BandPass pass(tb, fb, span, scratch.workers[worker], counts[b], observer);
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
