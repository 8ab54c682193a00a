// The scan-line algorithm, as the notes teach it (Wylie, Romney, Evans & Erdahl 1967; Bouknight
// 1970; Watkins 1970; the notes' "scan-line algorithm").
//
// The picture is made one row (scan line) at a time, top to bottom, each row left to right,
// with no depth buffer:
//
//     for each scan line (row) of the image:
//       for each pixel of the scan line:
//         determine the closest polygon; draw the pixel in its colour
//
// and what makes it cheap is coherence, kept in three tables:
//   - the polygon table: for every polygon its depth plane, colour and id;
//   - the edge table: the polygons' edges, listed by the row where they start;
//   - the active edge list (AEL): the edges that cross the current row, sorted by x, and for
//     every polygon an in/out flag.
// For every row:
//   1. move the edges that start on this row from the edge table into the AEL, and sort it by x;
//   2. walk the AEL left to right. At each edge, flip its polygon's in/out flag. Between two
//      consecutive edges lies a span of pixels, inside exactly the polygons whose flag is in:
//        none    -> the background shows;
//        one     -> that polygon shows on the whole span, no depth is compared;
//        several -> compare depths, here and only here: at each pixel of the span the
//                   polygon nearest there shows;
//   3. drop the edges that end on this row; step the others' x by 1/m to the next row.
//
// This file is that loop on one core, to be read beside the notes. The renderer registered as
// "scanline" (scanline_fast.cpp) is the same algorithm in bands on all cores, with a compressed
// edge table and spans decided at their ends; tests/cross/textbook_test.cpp proves the two
// equal bit for bit.
//
// The pipeline hands each polygon over as triangles snapped to the sub-pixel grid, sharing the
// polygon's plane; the edges are those triangles' sides (scanline_edges.hpp), and where two
// triangles of one polygon meet on a diagonal, the flag flips out and in again at the same x.
// Coverage is the shared edge setup's (raster/edge.hpp), depth the shared fragment depth
// (raster/depth.hpp) and the tie rule the z-buffer's under LESS (the polygon submitted first
// wins).
// Guarantee: the picture equals the z-buffer's bit for bit: ids, depth and colour.
// Cost: O(edges x rows they cross + pixels + pixels where polygons overlap x overlap); memory
// O(width + polygons + edges): no buffer of depths.
//
// Tests: tests/visibility/scanline_test.cpp and every suite of the registry its capabilities join.

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/frame.hpp"
#include "core/stopwatch.hpp"
#include "raster/fragment.hpp"
#include "raster/lines.hpp"
#include "visibility/algorithm.hpp"
#include "visibility/scanline_edges.hpp"

namespace hsr::detail {
namespace {

using scan::ActiveEdge;
using scan::EdgeRows;

// Step names: what `hsr explain scanline-textbook` (and `hsr explain scanline`) shows.
constexpr std::string_view kStepInitialise = "initialise";
constexpr std::string_view kStepRow = "scan row";
constexpr std::string_view kStepDone = "done";

// A polygon whose flag is in, with how many of its triangles the walk is inside (more than one
// only where a polygon's own triangles overlap).
struct Inside {
  std::uint32_t polygon;  // the polygon table's number: its first triangle
  std::int32_t count;
};

struct Counts {
  std::uint64_t rows = 0, edges_entered = 0, most_active = 0, spans = 0, spans_one = 0,
                spans_several = 0;
  FragmentCounts fragments;
};

class ScanLines {
 public:
  ScanLines(const AlgorithmInput& in, Frame& frame)
      : in_(in), tris_(in.prepared.triangles), frame_(frame), fb_(frame) {}

  void run() {
    // The polygon table: each triangle's polygon (numbered by its first triangle, so a lower
    // number was submitted first), whose plane, colour and id that triangle carries.
    const std::uint64_t polygons = numberPolygons(tris_, polygon_of_);
    // The edge table: each triangle listed by the row where its edges start.
    std::vector<std::vector<std::uint32_t>> edge_table(static_cast<std::size_t>(fb_.height));
    EdgeRows used{fb_.height, -1};  // the rows any triangle covers: where pictures are worth it
    for (std::uint32_t i = 0; i < tris_.size(); ++i) {
      const EdgeRows rows = scan::rowsOfTriangle(tris_[i]);
      if (rows.first > rows.last) continue;
      edge_table[rows.first].push_back(i);
      used = {std::min(used.first, rows.first), std::max(used.last, rows.last)};
    }
    if (in_.trace && in_.trace->wants(kStepInitialise, 0, 1))
      in_.trace->record({kStepInitialise,
                         "Initialise: the polygon table holds " + std::to_string(polygons) +
                             " polygons (plane, colour, id); the edge table holds their "
                             "triangles' edges, listed by the row where each starts. The active "
                             "edge list is empty, and there is no depth buffer.",
                         &frame_,
                         {}});

    for (int y = 0; y < fb_.height; ++y) {
      // 1. The edges that start on this row join the list, which is sorted by x again.
      for (const std::uint32_t tri : edge_table[y]) {
        const std::size_t before = ael_.size();
        scan::enterTriangle(tris_, tri, polygon_of_[tri], y, ael_);
        c_.edges_entered += ael_.size() - before;
      }
      sortByX();
      c_.most_active = std::max<std::uint64_t>(c_.most_active, ael_.size());
      c_.rows++;

      // 2. The walk along the row.
      noting_ = in_.trace && y >= used.first && y <= used.last &&
                in_.trace->wants(kStepRow, static_cast<std::uint64_t>(y - used.first),
                                 static_cast<std::uint64_t>(used.last - used.first + 1));
      notes_.clear();
      notes_shown_ = 0;
      walkRow(y);
      if (noting_) traceRow(y);

      // 3. Edges that end here leave (a bent side goes on with its second edge); the others
      // step to the next row.
      std::vector<ActiveEdge> next;
      for (ActiveEdge& e : ael_) {
        if (e.last_row > y) {
          scan::stepEdge(e);
        } else if (e.next_edge >= 0 &&
                   y + 1 <= scan::rowsOfEdge(tris_[e.triangle], e.next_edge).last) {
          scan::startEdge(tris_[e.triangle], e.triangle, e.polygon, e.next_edge, y + 1, -1, e);
        } else {
          continue;
        }
        next.push_back(e);
      }
      ael_.swap(next);
    }

    // Outlines over the finished picture, as every renderer draws them.
    const PixelBox viewport{0, 0, fb_.width - 1, fb_.height - 1};
    for (const ScreenLine& o : in_.prepared.outline) drawOutlinePen(o, viewport, fb_);

    if (in_.trace && in_.trace->wants(kStepDone, 0, 1))
      in_.trace->record(
          {kStepDone,
           "Done: " + std::to_string(c_.spans) + " spans inside polygons; " +
               std::to_string(c_.spans_one) + " inside one polygon (no depth compared), " +
               std::to_string(c_.spans_several) + " inside several, compared pixel by pixel.",
           &frame_,
           {}});
    frame_.stats.state_bytes += polygon_of_.capacity() * 4 + tris_.size() * 4 +
                                static_cast<std::size_t>(fb_.height) * 24 +
                                c_.most_active * sizeof(ActiveEdge);
    frame_.stats.fragments_tested += c_.fragments.tested;
    frame_.stats.fragments_written += c_.fragments.written;
    frame_.stats.addCounter("scanline: polygons", polygons);
    frame_.stats.addCounter("scanline: rows", c_.rows);
    frame_.stats.addCounter("scanline: edges entered", c_.edges_entered);
    frame_.stats.addCounter("scanline: most active edges", c_.most_active);
    frame_.stats.addCounter("scanline: spans", c_.spans);
    frame_.stats.addCounter("scanline: spans inside one polygon", c_.spans_one);
    frame_.stats.addCounter("scanline: spans inside several", c_.spans_several);
  }

 private:
  // The AEL in order of x, and at one x the entering edges first, by insertion (edges cross
  // rarely, so the list is nearly in order already).
  void sortByX() {
    for (std::size_t i = 1; i < ael_.size(); ++i) {
      const ActiveEdge e = ael_[i];
      std::size_t j = i;
      for (; j > 0 && (e.x < ael_[j - 1].x || (e.x == ael_[j - 1].x && e.flip > ael_[j - 1].flip));
           --j)
        ael_[j] = ael_[j - 1];
      ael_[j] = e;
    }
  }

  void walkRow(int y) {
    opaque_.clear();
    transparent_.clear();
    int x = 0;  // the start of the current span
    for (const ActiveEdge& e : ael_) {
      if (e.x > x) {  // the span up to this edge is finished
        resolveSpan(y, x, e.x);
        x = e.x;
      }
      // Flip the edge's polygon's flag
      std::vector<Inside>& inside = e.transparent ? transparent_ : opaque_;
      auto it = std::find_if(inside.begin(), inside.end(),
                             [&](const Inside& p) { return p.polygon == e.polygon; });
      if (it == inside.end())
        inside.push_back({e.polygon, e.flip});
      else if ((it->count += e.flip) == 0)
        inside.erase(it);
    }
    if (x < fb_.width) resolveSpan(y, x, fb_.width);
  }

  // Columns [xa, xb) of row y, inside the polygons whose flags are in.
  void resolveSpan(int y, int xa, int xb) {
    if (opaque_.empty() && transparent_.empty()) return;  // background: render() has cleared it
    c_.spans++;
    const char* how = "see-through only";
    if (opaque_.size() == 1) {  // one polygon: it shows, no depth compared
      c_.spans_one++;
      how = "one polygon";
      const ScreenTriangle& t = tris_[opaque_[0].polygon];
      const double row = depthRowStart(t.depth, y);
      for (int x = xa; x < xb; ++x) write(t, x, y, depthInRow(row, t.depth, x));
    } else if (opaque_.size() > 1) {  // several: at each pixel, the nearest
      c_.spans_several++;
      how = "depths compared pixel by pixel";
      for (int x = xa; x < xb; ++x) {
        std::uint32_t best = 0;
        float best_z = std::numeric_limits<float>::infinity();  // (NaN never wins, as under LESS)
        bool found = false;
        for (const Inside& p : opaque_) {
          const float z = fragmentDepth(tris_[p.polygon].depth, x, y);
          // Of equal depths the polygon submitted first, the z-buffer's rule under LESS
          if (z < best_z || (z == best_z && found && p.polygon < best))
            best = p.polygon, best_z = z, found = true;
        }
        c_.fragments.tested += opaque_.size() - 1;  // (write() counts the nearest's test)
        if (found) write(tris_[best], x, y, best_z);
      }
    }
    if (!transparent_.empty()) blendTransparent(y, xa, xb);
    if (noting_ && notes_shown_++ < 8) {
      std::string ids;
      for (const auto* list : {&opaque_, &transparent_})
        for (const Inside& p : *list) {
          if (!ids.empty()) ids += '+';
          ids += std::to_string(tris_[p.polygon].id);
        }
      if (!notes_.empty()) notes_ += "; ";
      notes_ += "[" + std::to_string(xa) + ", " + std::to_string(xb) + ") in " + ids + ": " + how;
    }
  }

  // The pixel shows polygon t at depth z, unless z is at or beyond the cleared depth (the far
  // plane: not drawn, as under the z-buffer's LESS).
  void write(const ScreenTriangle& t, int x, int y, float z) {
    const std::size_t k = fb_.index(x, y);
    c_.fragments.tested++;
    if (!(z < fb_.depth[k])) return;
    c_.fragments.written++;
    fb_.overdraw[k]++;
    fb_.depth[k] = z;
    fb_.ids[k] = t.id;
    fb_.rgba[k] = t.rgba;
  }

  // See-through polygons, after the visible opaque one: blended over it in submission order
  // where they are nearer than it, leaving its depth and id (the z-buffer's second pass).
  void blendTransparent(int y, int xa, int xb) {
    std::vector<std::uint32_t> order;
    for (const Inside& p : transparent_) order.push_back(p.polygon);
    scan::blendSeeThrough(tris_, fb_, order, y, xa, xb, c_.fragments);
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
    for (const ActiveEdge& e : ael_) {
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
             std::to_string(ael_.size()) +
             " edges, sorted by x; walking it left to right flips each polygon's "
             "in/out flag (x = the first column inside, or the first past it; the "
             "number is the polygon id): " +
             (list.empty() ? std::string("(empty: the row is background)") : list) +
             (notes_.empty() ? std::string()
                             : ". The spans and the polygons whose flag is in: " + notes_) +
             ". Rows above are finished; the rows below are still empty.",
         &frame_, std::move(outlines)});
  }

  const AlgorithmInput& in_;
  const ScreenTriangles& tris_;
  Frame& frame_;
  const FrameView fb_;
  std::vector<std::uint32_t> polygon_of_;     // the polygon table: triangle -> its polygon
  std::vector<ActiveEdge> ael_;               // the active edge list
  std::vector<Inside> opaque_, transparent_;  // the in/out flags: the polygons the walk is in
  Counts c_;
  bool noting_ = false;  // spelling out this row's spans for the picture
  std::string notes_;
  int notes_shown_ = 0;
};

}  // namespace

void drawScanlineTextbook(const AlgorithmInput& in, Frame& frame) {
  const detail::Stopwatch watch;
  ScanLines(in, frame).run();
  frame.stats.addStage("scan lines", watch.ms());
}

}  // namespace hsr::detail
