// The painter's algorithm with Newell, Newell & Sancha's depth sort (1972; the notes' "depth
// sort"). A painter puts the far things on the canvas first and paints the near ones over
// them; there is no depth test. The whole difficulty is the order:
//
//   1. Sort the polygons by their farthest depth, farthest first.
//   2. Take P, the polygon at the far end of the list. Before painting it, look at every Q
//      whose depth extent overlaps P's, and ask, cheapest test first, whether P can be painted
//      before Q (P cannot hide any part of Q):
//        a. the depth extents do not overlap (P is wholly farther);
//        b. the x extents of their projections do not overlap;
//        c. the y extents do not overlap;
//        d. P is wholly behind Q's plane;
//        e. Q is wholly in front of P's plane;
//        f. the projections do not overlap;
//        g. (hsr's addition) where the projections overlap, P is behind Q.
//      If one test succeeds for every Q, paint P and take it off the list.
//   3. If every test fails for some Q, ask the same of Q before P (tests d and e reversed). If
//      Q can go first, swap: move Q to the far end and mark it. A polygon that has to move
//      again while marked closes a cycle (the notes' three sticks, which no order can paint).
//   4. A cycle, or a pair that cannot go in either order (interpenetrating polygons), is
//      broken by splitting one polygon along the other's plane; the pieces take its place in
//      the list and the sort goes on.
//
// How hsr does each step. Every polygon is the pipeline's clipped window-space polygon
// (pipeline/pipeline.hpp, WindowPolygon) with the depth plane its screen triangles use: the
// depth of a point (x, y) of it is z = z0 + dzdy y + dzdx x (raster/depth.hpp). Depth grows
// away from the viewer and the view direction is +z, so "P's plane" is that plane, "behind" is
// deeper, and the line along which two planes cross is where z_P(x, y) = z_Q(x, y): a line in
// the picture. Splitting along it keeps both pieces on their parent's plane, with its id and
// colour, so the depth a piece paints is the depth the z-buffer would have written there.
// The tests ask about pixel centres, the only points painted: a polygon enters the list as its
// outline snapped to the filler's sub-pixel grid (8 bits, as the pipeline), exactly the region
// whose centres it covers, and a piece is that region cut by exact lines; a piece paints its
// parent's pixels on its side of every cut (raster/fill_polygons.hpp, paintPolygonPart), so
// pieces share out their parent's pixels exactly.
// Test f is exact for whole polygons: their convex hulls on the grid, separated by one of their
// edges (separating axes), decided with integer orientation; a cut piece's hull is grown by one
// sub-pixel, so f never separates two regions that share a centre.
// Test g clips P's region by Q's and compares the two planes at the overlap's corners, or, for
// a sliver holding at most kCentresAsked centres, at each centre: without it, two polygons that
// overlap only where one is clearly behind (each crossing the other's plane somewhere else),
// or two triangles folding along a shared edge whose snapped corners stick out of each other's
// planes, fail every test both ways and are split for nothing.
// The Q to test are found through a grid of screen cells, not by looking at every pair.
// Transparent polygons are blended as they are painted: back to front.
//
// Guarantee: each pixel shows the nearest polygon at its centre, as the z-buffer does, except
// where two depths are within kOnPlane of each other. Where two depths are equal as floats
// the first submitted shows, the z-buffer's rule for ties (paintPolygonPart). If the sort
// would exceed its budget (kSplitsPerPolygon, kMaxCutsPerPiece, kTestsPerPolygon) the rest is
// painted in the order reached and counted ("painter: unresolved"; `hsr render` says so on
// stderr): never a silent wrong order.
// Cost: O(n log n) for the sort plus the tests, about (candidates per polygon) x n, where the
// candidates are the polygons overlapping it in the picture and in depth; memory ~300 bytes
// per polygon and piece. Tests: tests/visibility/painter_test.cpp and every suite of the
// registry its capabilities join.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <queue>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>

#include "core/frame.hpp"
#include "core/stopwatch.hpp"
#include "geometry/clip.hpp"
#include "geometry/predicates.hpp"
#include "raster/edge.hpp"
#include "raster/fill_polygons.hpp"
#include "visibility/algorithm.hpp"

namespace hsr::detail {
namespace {

// Step names: what `hsr explain painter` shows.
constexpr std::string_view kStepSort = "sort";
constexpr std::string_view kStepSwap = "swap";
constexpr std::string_view kStepSplit = "split";
constexpr std::string_view kStepPaint = "paint";
constexpr std::string_view kStepDone = "done";

// Two depths closer than this (window depth, 0..1) are equal for the plane tests: a vertex
// this close to a plane is on it, and is on both sides of a split. Far below what a float
// depth buffer resolves (6e-8 near 1; distant surfaces of a real model are 1e-8 apart), far
// above double's rounding of a plane's value (~1e-16 of its terms).
constexpr double kOnPlane = 1e-12;
// Splits allowed in one render: kSplitsPerPolygon per polygon of the input plus kSplitsAtLeast;
// beyond that the rest is painted in the order reached (reported). Real models and the random
// scenes of the tests need under 1 per polygon (see painter_test's figures).
constexpr std::uint64_t kSplitsPerPolygon = 4;
constexpr std::uint64_t kSplitsAtLeast = 4096;
// A piece cut this many times is not cut again (unresolved, reported): halving a 2^22-pixel
// picture down to one pixel takes 44 cuts; the pixel loop tests each cut.
constexpr std::size_t kMaxCutsPerPiece = 48;
// Pair tests allowed in one render: kTestsPerPolygon per polygon plus kTestsAtLeast. Real
// models need under 100 per polygon; a soup of large random triangles all overlapping in a
// small picture needs ~n per polygon (every pair overlaps), and is stopped here.
constexpr std::uint64_t kTestsPerPolygon = 512;
constexpr std::uint64_t kTestsAtLeast = 1u << 16;

double depthAt(const DepthPlane& p, const glm::dvec2& v) {
  return (p.z0 + p.dzdy * v.y) + p.dzdx * v.x;
}

// How many P a piece remembers having passed the tests for (a P swapped aside comes back to
// the same candidates; four cover the usual chain of swaps).
constexpr std::size_t kClearedSlots = 4;

// A polygon in the list: the parent's outline (or a piece of it) and what it paints with.
struct Piece {
  std::vector<glm::dvec2> xy;        // window space, pixel centres at integers, y down
  std::vector<std::int64_t> hull;    // convex hull on the sub-pixel grid: x0, y0, x1, y1, ...
  std::vector<PixelHalfPlane> cuts;  // the lines it was cut along, and its side of each
  const WindowPolygon* parent = nullptr;
  std::uint32_t polygon = 0;                    // the parent's index in the pipeline's list
  double zmin = 0, zmax = 0;                    // depth extent (on the parent's plane)
  std::int64_t x0 = 0, x1 = 0, y0 = 0, y1 = 0;  // extent of the hull, sub-pixel grid
  bool alive = true;                            // in the list, not yet painted or split
  bool marked = false;     // at the far end (taken from the list's end, or moved
                           // there by a swap), still waiting
  std::uint32_t seen = 0;  // stamp of the last candidate search that met it
  // The last P it passed the tests for (P can be painted before it): not asked again.
  std::uint32_t cleared_for[kClearedSlots] = {0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu};
  std::uint32_t next_slot = 0;
};

// The convex hull of snapped points (Andrew's monotone chain), counter-clockwise with y up in
// the orientation predicate's sense; fewer than 3 points when the snapped area is zero. With
// `grow` each point stands for the square of half-side `grow` sub-pixels around it.
std::vector<std::int64_t> snappedHull(const std::vector<glm::dvec2>& xy, std::int64_t grow) {
  std::vector<std::pair<std::int64_t, std::int64_t>> p;
  p.reserve(4 * xy.size());
  for (const glm::dvec2& v : xy) {
    const std::int64_t x = std::llrint(v.x * kSubpixelOne), y = std::llrint(v.y * kSubpixelOne);
    if (grow == 0) {
      p.emplace_back(x, y);
      continue;
    }
    for (const std::int64_t dx : {-grow, grow})
      for (const std::int64_t dy : {-grow, grow}) p.emplace_back(x + dx, y + dy);
  }
  std::sort(p.begin(), p.end());
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return {};
  std::vector<std::pair<std::int64_t, std::int64_t>> h(2 * p.size());
  std::size_t k = 0;
  auto turn = [&](std::size_t a, std::size_t b, const auto& c) {
    return orient2d(h[a].first, h[a].second, h[b].first, h[b].second, c.first, c.second);
  };
  for (std::size_t i = 0; i < p.size(); ++i) {  // lower chain
    while (k >= 2 && turn(k - 2, k - 1, p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && turn(k - 2, k - 1, p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  --k;  // the last point repeats the first
  if (k < 3) return {};
  std::vector<std::int64_t> out;
  for (std::size_t i = 0; i < k; ++i) {
    out.push_back(h[i].first);
    out.push_back(h[i].second);
  }
  return out;
}

// Whether one of a's edges separates the hulls (every vertex of b on its outer side or on it).
bool edgeOfASeparates(const std::vector<std::int64_t>& a, const std::vector<std::int64_t>& b) {
  const std::size_t n = a.size() / 2, m = b.size() / 2;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    bool separates = true;
    for (std::size_t k = 0; k < m && separates; ++k)
      separates =
          orient2d(a[2 * i], a[2 * i + 1], a[2 * j], a[2 * j + 1], b[2 * k], b[2 * k + 1]) <= 0;
    if (separates) return true;
  }
  return false;
}

// Test f: the projections' interiors are disjoint (convex hulls are; two convex shapes are
// disjoint exactly when an edge of one separates them).
bool projectionsDisjoint(const Piece& p, const Piece& q) {
  return edgeOfASeparates(p.hull, q.hull) || edgeOfASeparates(q.hull, p.hull);
}

// The convex region that holds every pixel centre a piece paints: its parent's snapped hull,
// cut by the piece's cut lines; as half-planes a x + b y + c >= 0.
struct HalfPlane {
  double a, b, c;
};
void coverageRegion(const Piece& piece, const std::vector<std::int64_t>& parent_hull,
                    std::vector<HalfPlane>& out) {
  const std::size_t n = parent_hull.size() / 2;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    const double ax = static_cast<double>(parent_hull[2 * i]) / kSubpixelOne;
    const double ay = static_cast<double>(parent_hull[2 * i + 1]) / kSubpixelOne;
    const double bx = static_cast<double>(parent_hull[2 * j]) / kSubpixelOne;
    const double by = static_cast<double>(parent_hull[2 * j + 1]) / kSubpixelOne;
    // The inside is to the left of a->b (positive orientation): (b - a) x (v - a) >= 0.
    const double a = -(by - ay), b = bx - ax;
    out.push_back({a, b, -(a * ax + b * ay)});
  }
  for (const PixelHalfPlane& h : piece.cuts) {
    const double sign = h.negative ? -1.0 : 1.0;
    out.push_back({sign * h.a, sign * h.b, sign * h.c});
  }
}

// Test g (hsr's addition): at every pixel centre both paint, P is behind Q (or on it). P's
// outline is exactly the region whose pixel centres it paints; clipped by Q's convex coverage
// region it holds every centre both paint, and the depth difference is linear, so P behind Q
// at the clipped outline's corners settles it. Where it does not and the overlap is small (a
// sliver along a shared edge, narrower than the snapping), the centres in it are few: each is
// asked. Tests d and e look at whole polygons and fail for two polygons that overlap only
// where one is clearly behind; this one does not.
constexpr int kCentresAsked = 64;
bool behindWhereTheyOverlap(const Piece& p, const Piece& q,
                            const std::vector<std::int64_t>& p_parent_hull,
                            const std::vector<std::int64_t>& q_parent_hull) {
  std::vector<HalfPlane> region;
  coverageRegion(q, q_parent_hull, region);
  std::vector<glm::dvec2> overlap = p.xy;
  for (const HalfPlane& h : region) {
    if (overlap.empty()) return true;
    clipToHalfPlane(overlap, h.a, h.b, h.c);
  }
  auto behind = [&](const glm::dvec2& v) {
    return depthAt(p.parent->depth, v) - depthAt(q.parent->depth, v) >= -kOnPlane;
  };
  if (std::all_of(overlap.begin(), overlap.end(), behind)) return true;
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const glm::dvec2& v : overlap)
    x0 = std::min(x0, v.x), x1 = std::max(x1, v.x), y0 = std::min(y0, v.y), y1 = std::max(y1, v.y);
  const double cx0 = std::ceil(x0 - 1e-9), cx1 = std::floor(x1 + 1e-9);
  const double cy0 = std::ceil(y0 - 1e-9), cy1 = std::floor(y1 + 1e-9);
  if (cx0 > cx1 || cy0 > cy1) return true;  // no pixel centre in the overlap
  if ((cx1 - cx0 + 1) * (cy1 - cy0 + 1) > kCentresAsked) return false;
  coverageRegion(p, p_parent_hull, region);  // both regions: a centre both may paint
  for (double y = cy0; y <= cy1; ++y)
    for (double x = cx0; x <= cx1; ++x) {
      bool inside = true;
      for (const HalfPlane& h : region) inside = inside && h.a * x + h.b * y + h.c >= -1e-9;
      if (inside && !behind({x, y})) return false;
    }
  return true;
}

// Where the vertices of `of` lie against the plane of `against`, as depth differences
// z_against - z_of: all >= -kOnPlane when `of` is wholly behind (or on) that plane, all
// <= kOnPlane when wholly in front (or on).
struct SideOfPlane {
  bool behind = true, in_front = true;
};
SideOfPlane sideOf(const Piece& of, const Piece& against) {
  SideOfPlane s;
  for (const glm::dvec2& v : of.xy) {
    const double d = depthAt(of.parent->depth, v) - depthAt(against.parent->depth, v);
    if (d < -kOnPlane) s.behind = false;
    if (d > kOnPlane) s.in_front = false;
  }
  return s;
}

// The counts the stats report.
struct Counts {
  std::uint64_t candidates = 0, by_depth = 0, by_x = 0, by_y = 0, by_p_behind = 0,
                by_q_in_front = 0, by_projection = 0, by_overlap = 0, by_coplanar = 0,
                all_failed = 0;
  std::uint64_t swaps = 0, splits = 0, cycles = 0, screen_cuts = 0, unresolved = 0,
                pieces_painted = 0, no_pixel_centre = 0;
};

// Step 2: can P be painted before Q, P hiding no part of Q? The notes' tests, cheapest first.
bool canPaintBefore(const Piece& p, const Piece& q, const std::vector<std::int64_t>& p_parent_hull,
                    const std::vector<std::int64_t>& q_parent_hull, Counts& c) {
  if (p.zmin >= q.zmax) return ++c.by_depth, true;          // a. P wholly farther
  if (p.x1 <= q.x0 || q.x1 <= p.x0) return ++c.by_x, true;  // b. x extents apart
  if (p.y1 <= q.y0 || q.y1 <= p.y0) return ++c.by_y, true;  // c. y extents apart
  const SideOfPlane p_side = sideOf(p, q), q_side = sideOf(q, p);
  if (p_side.behind && p_side.in_front && q_side.behind && q_side.in_front) {
    // In one plane: neither hides the other, and the z-buffer's tie rule (the first submitted
    // stays) is kept by painting the later polygon first.
    if (p.parent->id >= q.parent->id || projectionsDisjoint(p, q)) return ++c.by_coplanar, true;
    return false;
  }
  if (p_side.behind) return ++c.by_p_behind, true;                // d. P behind Q's plane
  if (q_side.in_front) return ++c.by_q_in_front, true;            // e. Q in front of P's plane
  if (projectionsDisjoint(p, q)) return ++c.by_projection, true;  // f. projections apart
  if (behindWhereTheyOverlap(p, q, p_parent_hull, q_parent_hull))
    return ++c.by_overlap, true;  // g. behind in the overlap
  ++c.all_failed;
  return false;
}

class DepthSort {
 public:
  DepthSort(const std::vector<WindowPolygon>& polygons, int width, int height) {
    // The grid of screen cells through which the Q near a P are found: about four pieces per
    // cell on average, cells of 8 to 256 pixels.
    // Cells no smaller than the polygons' mean box side either: when every polygon is large
    // (a soup of big triangles in a small picture) small cells only list each many times.
    const double area = static_cast<double>(width) * height;
    double box_sides = 0;
    for (const WindowPolygon& p : polygons) {
      double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
      for (const glm::dvec3& v : p.vertices) {
        x0 = std::min(x0, v.x), x1 = std::max(x1, v.x), y0 = std::min(y0, v.y),
        y1 = std::max(y1, v.y);
      }
      box_sides +=
          std::sqrt(std::clamp(x1 - x0, 0.0, 1.0 * width) * std::clamp(y1 - y0, 0.0, 1.0 * height));
    }
    const double n = static_cast<double>(std::max<std::size_t>(polygons.size(), 1));
    cell_ = static_cast<int>(
        std::clamp(std::max(std::sqrt(4.0 * area / n), box_sides / n), 4.0, 256.0));
    cols_ = (width + cell_ - 1) / cell_;
    rows_ = (height + cell_ - 1) / cell_;
    cells_.resize(static_cast<std::size_t>(cols_) * rows_);
    pieces_.reserve(polygons.size() + polygons.size() / 4);
    outlines_.resize(polygons.size());
    hulls_.resize(polygons.size());
    for (std::uint32_t i = 0; i < polygons.size(); ++i) {
      for (const glm::dvec3& v : polygons[i].vertices) outlines_[i].emplace_back(v.x, v.y);
      // A polygon whose box holds no pixel centre paints nothing (the fill rule covers only
      // centres): it need not be sorted. Dense models at small sizes are mostly such.
      if (holdsNoPixelCentre(outlines_[i])) {
        ++counts_.no_pixel_centre;
        continue;
      }
      // The polygon as the list sees it: its snapped outline, exactly the region whose pixel
      // centres it covers, so that tests d, e and g hold for every pixel it paints.
      std::vector<glm::dvec2> snapped;
      for (const glm::dvec2& v : outlines_[i])
        snapped.emplace_back(static_cast<double>(std::llrint(v.x * kSubpixelOne)) / kSubpixelOne,
                             static_cast<double>(std::llrint(v.y * kSubpixelOne)) / kSubpixelOne);
      hulls_[i] = snappedHull(snapped, 0);
      add(std::move(snapped), &polygons[i], i, {});
    }
    for (std::vector<std::uint32_t>& cell : cells_)
      std::stable_sort(cell.begin(), cell.end(), [this](std::uint32_t a, std::uint32_t b) {
        return pieces_[a].zmax > pieces_[b].zmax;
      });
    sorted_ = true;
    max_splits_ = kSplitsPerPolygon * polygons.size() + kSplitsAtLeast;
    max_tests_ = kTestsPerPolygon * polygons.size() + kTestsAtLeast;
  }

  // Steps 1 to 4; paint(piece) is called in painting order.
  template <class PaintFn, class TraceFn>
  void run(PaintFn&& paint, TraceFn&& trace) {
    // 1. The list, farthest first: a heap on the farthest depth (ties: the later polygon
    // first, so that a coplanar pair paints in the z-buffer's tie order).
    auto farther = [this](std::uint32_t a, std::uint32_t b) {
      const Piece &pa = pieces_[a], &pb = pieces_[b];
      if (pa.zmax != pb.zmax) return pa.zmax < pb.zmax;
      if (pa.parent->id != pb.parent->id) return pa.parent->id < pb.parent->id;
      return a > b;
    };
    std::priority_queue<std::uint32_t, std::vector<std::uint32_t>, decltype(farther)> list(farther);
    for (std::uint32_t i = 0; i < pieces_.size(); ++i) list.push(i);
    trace(kStepSort, nullptr, nullptr);
    // The far end of the list, with the polygons swapped in front of it (each marked).
    std::vector<std::uint32_t> far_end;
    // Paints P, the piece at the far end, and takes it off the list.
    auto paintFarEnd = [&] {
      const std::uint32_t p = far_end.back();
      pieces_[p].alive = false;
      pieces_[p].marked = false;
      far_end.pop_back();
      ++counts_.pieces_painted;
      paint(pieces_[p]);
    };
    while (true) {
      if (far_end.empty()) {
        while (!list.empty() && !pieces_[list.top()].alive) list.pop();
        if (list.empty()) break;
        far_end.push_back(list.top());
        pieces_[list.top()].marked = true;
      }
      const std::uint32_t p = far_end.back();
      budget_spent_ =
          budget_spent_ || counts_.splits >= max_splits_ || counts_.candidates >= max_tests_;
      const std::uint32_t q = budget_spent_ ? kNone : firstHidden(p);
      if (q == kNone) {
        // Out of budget: painted as reached, unchecked, and counted (reported).
        if (budget_spent_) ++counts_.unresolved;
        // Nothing P could hide is still waiting: paint P.
        paintFarEnd();
        continue;
      }
      // 3. Q might be hidden by P. If Q may go first and is not marked, swap.
      if (!pieces_[q].marked && canPaintBefore(pieces_[q], pieces_[p], hulls_[pieces_[q].polygon],
                                               hulls_[pieces_[p].polygon], counts_)) {
        ++counts_.swaps;
        pieces_[q].marked = true;
        far_end.push_back(q);
        trace(kStepSwap, &pieces_[p], &pieces_[q]);
        continue;
      }
      // 4. A cycle (Q is marked: it is at the far end, waiting for what P must be painted
      // after), or neither order works (the two interpenetrate): split.
      std::uint32_t pieces[2];
      std::uint32_t cut;
      if (pieces_[q].marked) {
        ++counts_.cycles;
        const auto from = std::find(far_end.begin(), far_end.end(), q);
        cut = breakCycle(std::span<const std::uint32_t>(&*from, far_end.end() - from), p, pieces);
      } else {
        const std::uint32_t pair[2] = {q, p};
        cut = breakCycle(pair, p, pieces);
      }
      if (cut == kNone) {
        // Left unresolved (breakCycle): painted as reached, counted and reported.
        ++counts_.unresolved;
        paintFarEnd();
        continue;
      }
      ++counts_.splits;
      trace(kStepSplit, pieces[0] == kNone ? nullptr : &pieces_[pieces[0]],
            pieces[1] == kNone ? nullptr : &pieces_[pieces[1]]);
      // The pieces join the list unmarked; the far end is rebuilt from where the cut one was.
      const auto at = std::find(far_end.begin(), far_end.end(), cut);
      for (auto it = at; it != far_end.end(); ++it) pieces_[*it].marked = false;
      far_end.erase(at, far_end.end());
      for (const std::uint32_t piece : pieces)
        if (piece != kNone) list.push(piece);
    }
  }

  const Counts& counts() const { return counts_; }
  const std::vector<glm::dvec2>& outlineOf(const Piece& p) const { return outlines_[p.polygon]; }
  std::size_t pieceCount() const { return pieces_.size(); }
  std::size_t bytes() const {
    std::size_t b = pieces_.capacity() * sizeof(Piece);
    for (const Piece& p : pieces_)
      b += p.xy.capacity() * sizeof(glm::dvec2) + p.hull.capacity() * 8;
    for (const auto& c : cells_) b += c.capacity() * sizeof(std::uint32_t);
    return b;
  }

 private:
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;

  // Whether no pixel centre (integer x and y) lies in the box of the snapped vertices.
  static bool holdsNoPixelCentre(const std::vector<glm::dvec2>& xy) {
    std::int64_t x0 = INT64_MAX, x1 = INT64_MIN, y0 = INT64_MAX, y1 = INT64_MIN;
    for (const glm::dvec2& v : xy) {
      const std::int64_t fx = std::llrint(v.x * kSubpixelOne), fy = std::llrint(v.y * kSubpixelOne);
      x0 = std::min(x0, fx);
      x1 = std::max(x1, fx);
      y0 = std::min(y0, fy);
      y1 = std::max(y1, fy);
    }
    return ceilDiv(x0, kSubpixelOne) > floorDiv(x1, kSubpixelOne) ||
           ceilDiv(y0, kSubpixelOne) > floorDiv(y1, kSubpixelOne);
  }

  // Adds a piece to the list's storage and the grid; returns its index, or kNone when it
  // covers no area on the sub-pixel grid (it would paint nothing).
  std::uint32_t add(std::vector<glm::dvec2> xy, const WindowPolygon* parent, std::uint32_t polygon,
                    std::vector<PixelHalfPlane> cuts) {
    Piece p;
    // A whole polygon paints exactly the pixel centres inside its snapped hull. A piece paints
    // the whole's pixels on its side of exact cut lines, and its own vertices, snapped, can
    // be half a sub-pixel inside that region: its hull is grown by one sub-pixel, so that tests
    // b, c, f and g never find apart two pieces that share a pixel centre.
    if (snappedHull(xy, 0).empty()) return kNone;
    p.hull = snappedHull(xy, cuts.empty() ? 0 : 1);
    p.parent = parent;
    p.polygon = polygon;
    p.cuts = std::move(cuts);
    p.zmin = std::numeric_limits<double>::infinity();
    p.zmax = -std::numeric_limits<double>::infinity();
    for (const glm::dvec2& v : xy) {
      const double z = depthAt(parent->depth, v);
      p.zmin = std::min(p.zmin, z);
      p.zmax = std::max(p.zmax, z);
    }
    p.x0 = p.x1 = p.hull[0];
    p.y0 = p.y1 = p.hull[1];
    for (std::size_t i = 0; i < p.hull.size(); i += 2) {
      p.x0 = std::min(p.x0, p.hull[i]);
      p.x1 = std::max(p.x1, p.hull[i]);
      p.y0 = std::min(p.y0, p.hull[i + 1]);
      p.y1 = std::max(p.y1, p.hull[i + 1]);
    }
    p.xy = std::move(xy);
    const auto index = static_cast<std::uint32_t>(pieces_.size());
    // Each cell lists its pieces farthest first (by the far end of their depth extent), so
    // that a search stops at the first one wholly in front of P: as the notes walk the sorted
    // list only while depth extents overlap. The first pieces are sorted once, when all are in.
    const double zmax = p.zmax;
    forCells(p, [&](std::vector<std::uint32_t>& cell) {
      if (!sorted_) {
        cell.push_back(index);
        return;
      }
      const auto at =
          std::upper_bound(cell.begin(), cell.end(), zmax,
                           [this](double z, std::uint32_t q) { return z > pieces_[q].zmax; });
      cell.insert(at, index);
    });
    pieces_.push_back(std::move(p));
    return index;
  }

  template <class Fn>
  void forCells(const Piece& p, Fn&& fn) {
    // Cells in whole pixels; the extents are on the sub-pixel grid.
    auto col = [&](std::int64_t x) {
      return static_cast<int>(
          std::clamp<std::int64_t>(floorDiv(x, kSubpixelOne * cell_), 0, cols_ - 1));
    };
    auto row = [&](std::int64_t y) {
      return static_cast<int>(
          std::clamp<std::int64_t>(floorDiv(y, kSubpixelOne * cell_), 0, rows_ - 1));
    };
    for (int r = row(p.y0); r <= row(p.y1); ++r)
      for (int c = col(p.x0); c <= col(p.x1); ++c)
        fn(cells_[static_cast<std::size_t>(r) * cols_ + c]);
  }

  // The first waiting Q that P might hide (every test of step 2 failed), or kNone.
  std::uint32_t firstHidden(std::uint32_t p) {
    ++stamp_;
    std::uint32_t found = kNone;
    forCells(pieces_[p], [&](std::vector<std::uint32_t>& cell) {
      // Only the Q whose depth extent overlaps P's (the rest pass test a); painted and split
      // pieces leave the cell as it is scanned.
      const double zmin = pieces_[p].zmin;
      std::size_t kept = 0, i = 0;
      for (; i < cell.size() && found == kNone; ++i) {
        const std::uint32_t q = cell[i];
        if (!pieces_[q].alive) continue;
        if (pieces_[q].zmax <= zmin) break;
        cell[kept++] = q;
        if (q == p || pieces_[q].seen == stamp_ ||
            std::find(std::begin(pieces_[q].cleared_for), std::end(pieces_[q].cleared_for), p) !=
                std::end(pieces_[q].cleared_for))
          continue;
        pieces_[q].seen = stamp_;
        ++counts_.candidates;
        if (canPaintBefore(pieces_[p], pieces_[q], hulls_[pieces_[p].polygon],
                           hulls_[pieces_[q].polygon], counts_))
          pieces_[q].cleared_for[pieces_[q].next_slot++ % kClearedSlots] = p;
        else
          found = q;
      }
      cell.erase(cell.begin() + static_cast<std::ptrdiff_t>(kept),
                 cell.begin() + static_cast<std::ptrdiff_t>(i));
    });
    return found;
  }

  // The line along which `along`'s plane meets the plane of `own`: the half-plane where
  // own's depth minus along's is >= 0, i.e. where own lies behind along's plane.
  static PixelHalfPlane planeLine(const DepthPlane& own, const DepthPlane& along) {
    return {own.dzdx - along.dzdx, own.dzdy - along.dzdy, own.z0 - along.z0, false};
  }
  static double valueOf(const PixelHalfPlane& h, const glm::dvec2& v) {
    return (h.c + h.b * v.y) + h.a * v.x;
  }
  // Whether the piece has vertices on both sides of the line, beyond kOnPlane.
  static bool spans(const Piece& p, const PixelHalfPlane& line) {
    bool above = false, below = false;
    for (const glm::dvec2& v : p.xy) {
      const double d = valueOf(line, v);
      above |= d > kOnPlane;
      below |= d < -kOnPlane;
    }
    return above && below;
  }

  // Cuts piece `cut` along `line` (it spans it) into the part where the line's value is >= 0
  // and the part where it is < 0; the cut piece leaves the list, the parts (kNone for a part
  // with no area on the grid) are returned in `parts`.
  void split(std::uint32_t cut, PixelHalfPlane line, std::uint32_t parts[2]) {
    const Piece& c = pieces_[cut];
    std::vector<glm::dvec2> non_negative, negative;
    const std::size_t n = c.xy.size();
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = (i + 1) % n;
      const glm::dvec2 &u = c.xy[i], &v = c.xy[j];
      const double du = valueOf(line, u), dv = valueOf(line, v);
      // A vertex within kOnPlane of the line goes to both parts.
      if (du >= -kOnPlane) non_negative.push_back(u);
      if (du <= kOnPlane) negative.push_back(u);
      // An edge crossing the line strictly: the crossing point goes to both parts.
      if ((du > kOnPlane && dv < -kOnPlane) || (du < -kOnPlane && dv > kOnPlane)) {
        const glm::dvec2 x = u + (du / (du - dv)) * (v - u);
        non_negative.push_back(x);
        negative.push_back(x);
      }
    }
    // Painting keeps to the whole polygon's pixels, each part to its side of the line: the
    // two parts share out the pixels exactly, on the line as well.
    std::vector<PixelHalfPlane> non_negative_cuts = c.cuts, negative_cuts = c.cuts;
    non_negative_cuts.push_back(line);
    line.negative = true;
    negative_cuts.push_back(line);
    const WindowPolygon* parent = c.parent;
    const std::uint32_t polygon = c.polygon;
    pieces_[cut].alive = false;
    pieces_[cut].marked = false;
    parts[0] = add(std::move(non_negative), parent, polygon, std::move(non_negative_cuts));
    parts[1] = add(std::move(negative), parent, polygon, std::move(negative_cuts));
  }

  // Step 4: splits one polygon along another's plane, to break the cycle `cycle` (the polygons
  // each of which might hide the next; a single pair for two that interpenetrate). The notes
  // split P or Q along the other's plane; a cycle whose polygons each lie wholly on one side
  // of the others' planes has none to cut along, and then P is cut across the middle of its
  // longer side, which separates its overlaps with its neighbours in the cycle as the pieces
  // shrink. Returns the piece cut, or kNone when P is too small to cut.
  std::uint32_t breakCycle(std::span<const std::uint32_t> cycle, std::uint32_t p,
                           std::uint32_t parts[2]) {
    for (const std::uint32_t x : cycle)
      for (const std::uint32_t y : cycle) {
        if (x == y) continue;
        if (pieces_[x].cuts.size() >= kMaxCutsPerPiece) continue;
        const PixelHalfPlane line = planeLine(pieces_[x].parent->depth, pieces_[y].parent->depth);
        if (spans(pieces_[x], line)) {
          split(x, line, parts);
          return x;
        }
      }
    const Piece& c = pieces_[p];
    // A piece within one pixel both ways is not cut further: the cycle is left unresolved
    // (reported); it can only come from depths that tie within kOnPlane.
    if ((c.x1 - c.x0 <= kSubpixelOne && c.y1 - c.y0 <= kSubpixelOne) ||
        c.cuts.size() >= kMaxCutsPerPiece)
      return kNone;
    const bool wide = c.x1 - c.x0 >= c.y1 - c.y0;
    const double middle = wide ? 0.5 * static_cast<double>(c.x0 + c.x1) / kSubpixelOne
                               : 0.5 * static_cast<double>(c.y0 + c.y1) / kSubpixelOne;
    ++counts_.screen_cuts;
    split(
        p,
        wide ? PixelHalfPlane{1.0, 0.0, -middle, false} : PixelHalfPlane{0.0, 1.0, -middle, false},
        parts);
    return p;
  }

  int cell_ = 64, cols_ = 1, rows_ = 1;
  std::vector<std::vector<glm::dvec2>> outlines_;  // each pipeline polygon's x, y
  std::vector<std::vector<std::int64_t>> hulls_;   // and its snapped convex hull
  std::vector<Piece> pieces_;
  std::vector<std::vector<std::uint32_t>> cells_;
  std::uint32_t stamp_ = 0;
  bool sorted_ = false;  // the cells are in order (all first pieces are in)
  std::uint64_t max_splits_ = 0, max_tests_ = 0;
  bool budget_spent_ = false;  // tests or splits: the rest is painted in the list's order
  Counts counts_;
};

std::vector<TraceOutline> outlineOf(const Piece* a, const Piece* b) {
  std::vector<TraceOutline> out;
  for (const Piece* p : {a, b}) {
    if (p == nullptr) continue;
    TraceOutline o;
    for (const glm::dvec2& v : p->xy)
      o.emplace_back(static_cast<float>(v.x), static_cast<float>(v.y));
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace

void drawPainter(const AlgorithmInput& in, Frame& frame) {
  const detail::Stopwatch t0;
  const FrameView fb(frame);
  FragmentCounts fragments;
  DepthSort sort(in.prepared.polygons, frame.width, frame.height);
  std::uint64_t painted = 0, swaps = 0, splits = 0;
  const std::uint64_t polygons = in.prepared.polygons.size();
  auto trace = [&](std::string_view step, const Piece* a, const Piece* b) {
    if (!in.trace || (step != kStepSort && a == nullptr && b == nullptr)) return;
    if (a == nullptr) std::swap(a, b);
    const std::uint64_t index = step == kStepSwap ? swaps++ : step == kStepSplit ? splits++ : 0;
    if (!in.trace->wants(step, index, step == kStepSort ? 1 : polygons)) return;
    std::string caption;
    if (step == kStepSort)
      caption = "Sort the " + std::to_string(polygons) +
                " polygons by their farthest depth, farthest first. Nothing is painted yet.";
    else if (step == kStepSwap)
      caption = "Swap: polygon " + std::to_string(a->parent->id) + " might hide part of polygon " +
                std::to_string(b->parent->id) + " (every test failed), and polygon " +
                std::to_string(b->parent->id) +
                " can go first: it moves to the far end of the list, marked.";
    else
      caption = "Split: a cycle or an interpenetration; polygon " + std::to_string(a->parent->id) +
                " is cut along the other polygon's plane into the two pieces outlined.";
    in.trace->record({step, std::move(caption), &frame, outlineOf(a, b)});
  };
  sort.run(
      [&](const Piece& p) {
        // The piece's pixels lie in its snapped hull's box give or take the rounding of its
        // split vertices: one pixel more each way is plenty.
        const PixelBox box{static_cast<int>(floorDiv(p.x0, kSubpixelOne)) - 1,
                           static_cast<int>(floorDiv(p.y0, kSubpixelOne)) - 1,
                           static_cast<int>(ceilDiv(p.x1, kSubpixelOne)) + 1,
                           static_cast<int>(ceilDiv(p.y1, kSubpixelOne)) + 1};
        paintPolygonPart(sort.outlineOf(p), p.cuts, box, p.parent->depth, p.parent->id,
                         p.parent->rgba, fb, fragments);
        if (in.trace && in.trace->wants(kStepPaint, painted, polygons))
          in.trace->record({kStepPaint,
                            "Paint polygon " + std::to_string(p.parent->id) + " (piece " +
                                std::to_string(painted + 1) +
                                "): nothing still waiting can be hidden by it, so it goes on "
                                "the canvas over whatever is there.",
                            &frame, outlineOf(&p, nullptr)});
        ++painted;
      },
      trace);
  const Counts& c = sort.counts();
  if (in.trace && in.trace->wants(kStepDone, 0, 1))
    in.trace->record({kStepDone,
                      "Done: " + std::to_string(c.pieces_painted) +
                          " pieces painted back to front, " + std::to_string(c.swaps) + " swaps, " +
                          std::to_string(c.splits) + " splits, " + std::to_string(c.cycles) +
                          " cycles broken.",
                      &frame,
                      {}});
  frame.stats.fragments_tested += fragments.tested;
  frame.stats.fragments_written += fragments.written;
  frame.stats.state_bytes += frameBufferBytes(frame) + sort.bytes();
  frame.stats.addCounter("painter: polygons between pixel centres", c.no_pixel_centre);
  frame.stats.addCounter("painter: overlap candidates", c.candidates);
  frame.stats.addCounter("painter: passed a. depth extents", c.by_depth);
  frame.stats.addCounter("painter: passed b. x extents", c.by_x);
  frame.stats.addCounter("painter: passed c. y extents", c.by_y);
  frame.stats.addCounter("painter: passed d. behind Q's plane", c.by_p_behind);
  frame.stats.addCounter("painter: passed e. Q in front of P's plane", c.by_q_in_front);
  frame.stats.addCounter("painter: passed f. projections apart", c.by_projection);
  frame.stats.addCounter("painter: passed g. behind where they overlap", c.by_overlap);
  frame.stats.addCounter("painter: coplanar pairs", c.by_coplanar);
  frame.stats.addCounter("painter: every test failed", c.all_failed);
  frame.stats.addCounter("painter: swaps", c.swaps);
  frame.stats.addCounter("painter: splits", c.splits);
  frame.stats.addCounter("painter: cycles broken", c.cycles);
  frame.stats.addCounter("painter: cuts across a piece", c.screen_cuts);
  frame.stats.addCounter("painter: pieces painted", c.pieces_painted);
  frame.stats.addCounter("painter: unresolved", c.unresolved);
  frame.stats.addStage("depth sort + paint", t0.ms());
}

}  // namespace hsr::detail
