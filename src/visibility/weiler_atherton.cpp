// Weiler-Atherton hidden-surface removal (Weiler & Atherton 1977; the notes' "Weiler-Atherton"):
// visibility decided in object space by clipping polygons against one another, so that the
// answer is polygons, not pixels.
//
//   1. Sort the polygons by their nearest depth.
//   2. Take the front polygon P of the list as the clip polygon.
//   3. Clip every other polygon Q against P: the part of Q inside P goes to the inside list,
//      the part outside P to the outside list.
//   4. Compare each piece of the inside list with P: a piece behind P is hidden, and removed.
//      A piece in front of P (the polygons overlap cyclically, or the sort put Q after P
//      because of its far corner) hides that part of P instead: the notes recurse with it as
//      the clip polygon, and what that clip removes is the part of P under the piece: P loses
//      it and the piece stays in the list. A piece that is partly in front (Q and P cross each
//      other) is first split along the line where their depths are equal.
//   5. What is left of P is visible: nothing still in the list is in front of it there. Output
//      it, and go on with the list (the outside pieces, and the inside pieces in front) from
//      step 2.
//
// How hsr does each step. Every polygon is the pipeline's clipped window-space polygon
// (pipeline/pipeline.hpp, WindowPolygon) with its vertices snapped to the sub-pixel grid, as
// its screen triangles are; the clipper (hsr/clipping.hpp) works on that grid exactly, and its
// results, whose corners are crossings of edges, stay exact when clipped again. A polygon's
// entry in the list is what is left of it, so steps 3 and 4 become, for P and each Q:
//   - inside = Q ∩ P; each of its pieces compared with P by depth at its corners: the depth
//     difference of two planes is linear, so its sign over a piece is the sign at its corners;
//   - behind: Q loses the piece (all of the inside behind: Q becomes Q − P, the outside list);
//   - in front: P loses it (all of it in front: P becomes P − Q);
//   - crossing: the piece is cut by the line where the planes meet, snapped to the grid (the
//     line through two grid points rounded from points 2^24 units either side of the piece's
//     centre: within about a unit of the true line over the picture); each side goes as above.
// Two quick answers come before any clip: Q entirely deeper than P (Q becomes Q − P), and an
// edge line of one with the two regions on opposite sides (no overlap: nothing to do, as for
// two triangles of a mesh sharing an edge). The Q to look at are found through a grid of
// screen cells. Entries only shrink, so a polygon's cells are those of its original box.
//
// Guarantee (hsr/visible_set.hpp): the visible regions never overlap and together make up the
// union of the snapped polygons; filled with paintExactRegion (the fill rule's own test), they
// cover the pixel centres the z-buffer's triangles cover. Each shows its polygon, the nearest
// there, except within a grid unit of a crossing line and where depths are within kOnPlane
// (the polygon found first, the nearer or the lower id among equals, keeps the point).
// See-through polygons hide nothing: they are blended afterwards with the depth test, as the
// z-buffer draws them.
// Cost: a few Boolean operations per pair of polygons whose boxes overlap and that do not
// separate at once; each O((n + m + k) log(n + m + k) + n m) (hsr/clipping.hpp).
// Tests: tests/visibility/weiler_atherton_test.cpp and every suite of the registry its
// capabilities join.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/frame.hpp"
#include "hsr/error.hpp"
#include "hsr/visible_set.hpp"
#include "core/stopwatch.hpp"
#include "raster/fill_polygons.hpp"
#include "raster/lines.hpp"
#include "visibility/algorithm.hpp"

namespace hsr::detail {
namespace {

// Two depths closer than this (window depth, 0..1) are equal: as the painter's kOnPlane, far
// below what a float depth buffer resolves, far above double's rounding of a plane's value.
constexpr double kOnPlane = 1e-12;
// Two polygons whose depths come this close where they overlap (or cross there) are "close":
// at pixel centres a float depth buffer may order them either way (a float step near depth 1
// is 6e-8), so the frame settles their shared pixels as one does (see drawWeilerAtherton).
// Planes with huge terms (an edge-on polygon: 1e8 per pixel) are evaluated with larger
// errors, in doubles here and before the rounding to float in every algorithm: their pairs
// are close within kFloatClose plus kTermError times the size of the plane's terms.
constexpr double kFloatClose = 1e-6;
constexpr double kTermError = 1e-14;
// The work limit: edges handed to the clipper, kWorkPerPolygon per polygon plus kWorkAtLeast.
// Meshes need 24-410 per polygon (spheres:100000: 26; the 2CylinderEngine: 408), soup:5000
// 285; a soup of large triangles all overlapping one another in a small picture needs
// thousands, each polygon cut to pieces by the others. Past the limit the polygons left are drawn
// with a depth test (reported).
constexpr std::uint64_t kWorkPerPolygon = 1024;
constexpr std::uint64_t kWorkAtLeast = std::uint64_t{1} << 18;
// The split line's two grid points lie this far (grid units, 2^16 pixels) either side of the
// piece's centre: the line's direction is then rounded by under 2^-24 radians.
constexpr double kSplitReach = 16777216.0;

struct Entry {
  ExactRegion region;  // what is left of the polygon
  ExactRegion whole;   // the whole snapped polygon
  DepthPlane plane;
  PolygonId id = kNoPolygon;
  std::uint32_t rgba = 0;
  double zmin = 0, zmax = 0;              // depth extent of the whole polygon
  double terms = 0;                       // size of its plane's terms over the picture
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // box of what is left, grid units
  std::vector<GridPoint> hull;            // the whole polygon counter-clockwise, when it is convex
  bool pristine = false;                  // the region is still that whole convex polygon
  bool done = false;                      // output (or emptied)
};

double depthAt(const DepthPlane& p, double gx, double gy) {
  return (p.z0 + p.dzdy * (gy / kSubpixelOne)) + p.dzdx * (gx / kSubpixelOne);
}

void updateBox(Entry& e) {
  bool any = false;
  for (const ExactPolygon& poly : e.region)
    for (const ExactPoint& v : poly.outer) {
      const double x = v.xd(), y = v.yd();
      if (!any) e.x0 = e.x1 = x, e.y0 = e.y1 = y, any = true;
      e.x0 = std::min(e.x0, x), e.x1 = std::max(e.x1, x), e.y0 = std::min(e.y0, y),
      e.y1 = std::max(e.y1, y);
    }
  if (!any) e.done = true;  // nothing left
}

// An edge line of one region with all of it on one side and all of the other on the other
// (or on the line): their interiors do not meet. Looked for on outer rings of up to 24 edges
// in all; exact (each side an integer sign).
bool separated(const ExactRegion& a, const ExactRegion& b) {
  std::size_t edges = 0;
  for (const ExactRegion* r : {&a, &b})
    for (const ExactPolygon& p : *r) edges += p.outer.size();
  if (edges > 24) return false;
  auto sideOf = [](const ExactPoint& line, const ExactPoint& v) {
    const __int128 s = __int128{line.a} * v.x + __int128{line.b} * v.y + __int128{line.c} * v.d;
    return (s > 0) - (s < 0);
  };
  auto allOn = [&](const ExactRegion& r, const ExactPoint& line, int want) {
    for (const ExactPolygon& p : r)
      for (const ExactPoint& v : p.outer)
        if (sideOf(line, v) == -want) return false;
    return true;
  };
  for (const auto& [self, other] : {std::pair{&a, &b}, std::pair{&b, &a}})
    for (const ExactPolygon& p : *self)
      for (const ExactPoint& line : p.outer)
        if (allOn(*self, line, 1) && allOn(*other, line, -1)) return true;
  return false;
}

// The same for two whole convex polygons, in 64-bit integers: the test most pairs of a mesh
// end with (neighbours sharing an edge), and the one a fan of thin triangles round one vertex
// asks of every pair.
bool hullsSeparated(const std::vector<GridPoint>& a, const std::vector<GridPoint>& b) {
  auto edgeSeparates = [](const std::vector<GridPoint>& h, const std::vector<GridPoint>& other) {
    for (std::size_t i = 0, n = h.size(); i < n; ++i) {
      const GridPoint p = h[i], q = h[(i + 1) % n];
      const std::int64_t dx = q.x - p.x, dy = q.y - p.y;
      bool all = true;
      for (const GridPoint& v : other)
        if (dx * (v.y - p.y) - dy * (v.x - p.x) > 0) {  // strictly inside the edge's half-plane
          all = false;
          break;
        }
      if (all) return true;
    }
    return false;
  };
  return edgeSeparates(a, b) || edgeSeparates(b, a);
}

enum class Verdict { Behind, InFront, Crossing };

// Where a piece of Q inside P lies against P: the sign of z_Q - z_P at its corners. `closest`
// gets the smallest |z_Q - z_P| there.
Verdict compare(const ExactPolygon& piece, const Entry& p, const Entry& q, double* closest) {
  bool behind = true, in_front = true;
  for (const ExactPoint& v : piece.outer) {
    const double dz = depthAt(q.plane, v.xd(), v.yd()) - depthAt(p.plane, v.xd(), v.yd());
    behind = behind && dz >= -kOnPlane;
    in_front = in_front && dz <= kOnPlane;
    *closest = std::min(*closest, std::abs(dz));
  }
  if (behind && in_front) return p.id < q.id ? Verdict::Behind : Verdict::InFront;  // one plane
  return behind ? Verdict::Behind : in_front ? Verdict::InFront : Verdict::Crossing;
}

// The half of the plane where Q is deeper than P, bounded by the line where their depths are
// equal snapped to the grid (see the top of this file), as a quad around the piece.
GridRegion deeperSide(const ExactPolygon& piece, const Entry& p, const Entry& q) {
  // z_Q - z_P = A gx + B gy + C in grid units
  const double A = (q.plane.dzdx - p.plane.dzdx) / kSubpixelOne,
               B = (q.plane.dzdy - p.plane.dzdy) / kSubpixelOne;
  const double C = q.plane.z0 - p.plane.z0;
  double cx = 0, cy = 0;
  for (const ExactPoint& v : piece.outer) cx += v.xd(), cy += v.yd();
  cx /= static_cast<double>(piece.outer.size()), cy /= static_cast<double>(piece.outer.size());
  const double len = std::hypot(A, B);
  const double nx = A / len, ny = B / len;              // towards Q deeper
  const double off = (A * cx + B * cy + C) / len;       // the centre's distance from the line
  const double px = cx - nx * off, py = cy - ny * off;  // its foot on the line
  const double r = kSplitReach;
  if (!(len > 0) || !(std::abs(px) < 2 * r && std::abs(py) < 2 * r)) return {};
  auto at = [](double x, double y) { return GridPoint{std::llround(x), std::llround(y)}; };
  return {{{at(px - ny * r, py + nx * r), at(px + ny * r, py - nx * r),
            at(px + ny * r + nx * r, py - nx * r + ny * r),
            at(px - ny * r + nx * r, py + nx * r + ny * r)},
           {}}};
}

struct Counts {
  std::uint64_t pairs = 0, clips = 0, splits = 0, separated = 0, deeper = 0, apart = 0;
  std::uint64_t work = 0;  // edges handed to the clipper, both operands, summed over clips
};

std::uint64_t edgesOf(const ExactRegion& r) {
  std::uint64_t n = 0;
  for (const ExactPolygon& p : r) {
    n += p.outer.size();
    for (const ExactRing& h : p.holes) n += h.size();
  }
  return n;
}

// One Boolean operation, its work counted.
ExactRegion clip(const ExactRegion& a, const ExactRegion& b, BooleanOp op, Counts& c) {
  c.clips++;
  c.work += edgesOf(a) + edgesOf(b);
  return booleanOp(a, b, op);
}

// What one pair came to, for the teaching view: Q's inside list and where it went.
struct PairEvent {
  enum Kind { kNothing, kDeeper, kInside } kind = kNothing;
  ExactRegion behind, in_front;  // the inside pieces hidden behind P, and those in front of it
  bool split = false;            // a piece crossed P and was split
};

// Steps 3 and 4 for the clip polygon p and one other polygon q. Returns whether they are close
// (kFloatClose) somewhere they overlap. `event`, when given, says what happened.
bool clipPair(Entry& p, Entry& q, Counts& c, PairEvent* event) {
  c.pairs++;
  const double close = kFloatClose + kTermError * std::max(p.terms, q.terms);
  if (q.x0 >= p.x1 || q.x1 <= p.x0 || q.y0 >= p.y1 || q.y1 <= p.y0) {
    c.apart++;
    return false;
  }
  if (p.pristine && q.pristine && hullsSeparated(p.hull, q.hull)) {
    c.separated++;
    return false;
  }
  if (q.zmin > p.zmax + close) {  // Q deeper than P everywhere: its part inside P is hidden
    c.deeper++;
    if (event) event->kind = PairEvent::kDeeper;
    q.pristine = false;
    q.region = clip(q.region, p.region, BooleanOp::AMinusB, c);
    updateBox(q);
    return false;
  }
  if (separated(p.region, q.region)) {
    c.separated++;
    return false;
  }
  const std::uint64_t splits_before = c.splits;
  const ExactRegion inside = clip(q.region, p.region, BooleanOp::Intersection, c);
  if (inside.empty()) return false;
  double closest = INFINITY;
  bool crossing = false;
  ExactRegion hidden_q, hidden_p;  // pieces behind P, pieces in front of it
  for (const ExactPolygon& piece : inside) {
    const Verdict v = compare(piece, p, q, &closest);
    if (v == Verdict::Behind)
      hidden_q.push_back(piece);
    else if (v == Verdict::InFront)
      hidden_p.push_back(piece);
    else {
      crossing = true;
      const GridRegion side = deeperSide(piece, p, q);
      if (side.empty() ||
          !invalidRegionReason(side).empty()) {  // planes all but parallel: no line to cut along
        (p.id < q.id ? hidden_q : hidden_p).push_back(piece);
        continue;
      }
      c.splits++;
      const ExactRegion one{piece}, deeper = exactRegion(side);
      for (const ExactPolygon& s : clip(one, deeper, BooleanOp::Intersection, c))
        hidden_q.push_back(s);
      for (const ExactPolygon& s : clip(one, deeper, BooleanOp::AMinusB, c)) hidden_p.push_back(s);
    }
  }
  auto remove = [&](Entry& e, const ExactRegion& pieces, const ExactRegion& rest,
                    const ExactRegion& whole_other) {
    if (pieces.empty()) return;
    e.pristine = false;
    if (rest.empty()) {
      e.region = clip(e.region, whole_other, BooleanOp::AMinusB, c);  // all of the inside
    } else {
      for (const ExactPolygon& piece : pieces) {
        e.region = clip(e.region, ExactRegion{piece}, BooleanOp::AMinusB, c);
      }
    }
    updateBox(e);
  };
  if (event) *event = {PairEvent::kInside, hidden_q, hidden_p, c.splits != splits_before};
  remove(q, hidden_q, hidden_p, p.region);  // (when all of the inside is behind: Q − P)
  remove(p, hidden_p, hidden_q, q.region);  // (when all of it is in front: P − Q; Q is as it was)
  return crossing || closest < close;
}

// A grid of screen cells, each listing the entries whose box meets it.
class Cells {
 public:
  Cells(const std::vector<Entry>& entries, int width, int height) {
    const double n = std::max<double>(1.0, static_cast<double>(entries.size()));
    const double side_px = std::max(8.0, std::sqrt(static_cast<double>(width) * height / n) * 2);
    side_ = side_px * kSubpixelOne;
    cols_ = std::max(1, static_cast<int>(std::ceil(width / side_px)) + 1);
    rows_ = std::max(1, static_cast<int>(std::ceil(height / side_px)) + 1);
    cells_.resize(static_cast<std::size_t>(cols_) * rows_);
    for (std::uint32_t i = 0; i < entries.size(); ++i) {
      const Entry& e = entries[i];
      if (e.done) continue;
      forCells(e, [&](std::vector<std::uint32_t>& cell) { cell.push_back(i); });
    }
  }
  // The cells of e's box; for a whole convex polygon only those its interior meets.
  template <class Fn>
  void forCells(const Entry& e, Fn&& fn) {
    const int c0 = col(e.x0), c1 = col(e.x1), r0 = row(e.y0), r1 = row(e.y1);
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c)
        if (!e.pristine || (c0 == c1 && r0 == r1) || meets(e.hull, c, r))
          fn(cells_[static_cast<std::size_t>(r) * cols_ + c]);
  }
  std::size_t bytes() const {
    std::size_t b = cells_.capacity() * sizeof(cells_[0]);
    for (const auto& c : cells_) b += c.capacity() * sizeof(std::uint32_t);
    return b;
  }

 private:
  // Does the convex polygon's interior meet cell (c, r)? (No edge has the whole cell on its
  // outer side; the boxes already meet.) Conservative in doubles: a cell on the edge counts.
  bool meets(const std::vector<GridPoint>& hull, int c, int r) const {
    const double x0 = c * side_, y0 = r * side_, x1 = x0 + side_, y1 = y0 + side_;
    for (std::size_t i = 0, n = hull.size(); i < n; ++i) {
      const GridPoint p = hull[i], q = hull[(i + 1) % n];
      const double dx = static_cast<double>(q.x - p.x), dy = static_cast<double>(q.y - p.y);
      auto left = [&](double x, double y) {
        return dx * (y - static_cast<double>(p.y)) - dy * (x - static_cast<double>(p.x)) >= 0;
      };
      if (!left(x0, y0) && !left(x1, y0) && !left(x0, y1) && !left(x1, y1)) return false;
    }
    return true;
  }
  int col(double x) const {
    return std::clamp(static_cast<int>(std::floor(x / side_)), 0, cols_ - 1);
  }
  int row(double y) const {
    return std::clamp(static_cast<int>(std::floor(y / side_)), 0, rows_ - 1);
  }
  double side_ = 1;
  int cols_ = 1, rows_ = 1;
  std::vector<std::vector<std::uint32_t>> cells_;
};

// The list: each opaque polygon snapped to the grid. A polygon that snapping folds (rare: a
// sliver clipped at the frustum) enters as the triangles of a fan, each valid one an entry.
std::vector<Entry> makeEntries(const std::vector<WindowPolygon>& polygons, int width, int height) {
  std::vector<Entry> entries;
  entries.reserve(polygons.size());
  auto add = [&](const WindowPolygon& w, const GridRing& ring) {
    const GridRegion region{{ring, {}}};
    if (!invalidRegionReason(region).empty()) return false;
    Entry e;
    e.region = exactRegion(region);
    e.whole = e.region;
    e.plane = w.depth;
    e.terms = std::abs(w.depth.z0) + std::abs(w.depth.dzdx) * (width + 1) +
              std::abs(w.depth.dzdy) * (height + 1);
    e.id = w.id;
    e.rgba = w.rgba;
    e.zmin = INFINITY, e.zmax = -INFINITY;
    for (const GridPoint& v : ring) {
      const double z = depthAt(w.depth, static_cast<double>(v.x), static_cast<double>(v.y));
      e.zmin = std::min(e.zmin, z), e.zmax = std::max(e.zmax, z);
    }
    // Convex (every turn the same way, or straight): kept counter-clockwise for hullsSeparated
    int turns = 0;
    bool convex = true;
    for (std::size_t i = 0, n = ring.size(); i < n && convex; ++i) {
      const GridPoint a = ring[i], b = ring[(i + 1) % n], c = ring[(i + 2) % n];
      const std::int64_t t = (b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x);
      const int sign = (t > 0) - (t < 0);
      if (sign != 0 && turns != 0 && sign != turns) convex = false;
      if (sign != 0) turns = sign;
    }
    if (convex) {
      e.hull = ring;
      if (turns < 0) std::reverse(e.hull.begin(), e.hull.end());
      e.pristine = true;
    }
    updateBox(e);
    entries.push_back(std::move(e));
    return true;
  };
  for (const WindowPolygon& w : polygons) {
    if (w.transparent) continue;
    GridRing ring;
    bool in_range = true;
    for (const glm::dvec3& v : w.vertices) {
      in_range = in_range && std::abs(v.x) < 4194304.0 && std::abs(v.y) < 4194304.0;  // 2^22 pixels
      if (in_range)
        ring.push_back({std::llrint(v.x * kSubpixelOne), std::llrint(v.y * kSubpixelOne)});
    }
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    while (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
    if (!in_range || ring.size() < 3) continue;
    if (add(w, ring)) continue;
    for (std::size_t k = 1; k + 1 < ring.size(); ++k) add(w, {ring[0], ring[k], ring[k + 1]});
  }
  return entries;
}

// Step names: what `hsr explain weiler-atherton` shows.
constexpr std::string_view kStepSort = "sort";
constexpr std::string_view kStepClipPolygon = "clip polygon";
constexpr std::string_view kStepInside = "inside list";
constexpr std::string_view kStepVisible = "visible";
constexpr std::string_view kStepDone = "done";

void addOutlines(const ExactRegion& r, std::vector<TraceOutline>& out) {
  auto ring = [&](const ExactRing& g) {
    TraceOutline o;
    for (const ExactPoint& v : g)
      o.emplace_back(static_cast<float>(v.xd() / kSubpixelOne),
                     static_cast<float>(v.yd() / kSubpixelOne));
    out.push_back(std::move(o));
  };
  for (const ExactPolygon& p : r) {
    ring(p.outer);
    for (const ExactRing& h : p.holes) ring(h);
  }
}

}  // namespace

// The Weiler-Atherton visible set of the pipeline's window polygons (weiler_atherton.cpp);
// `state_bytes`, when given, gets the memory its list and cells held; `close`, when given, the
// pairs of overlapping polygons whose depths come within a float step of each other.
struct ClosePair {
  ExactRegion whole_a, whole_b;  // the two snapped polygons
  DepthPlane plane_a, plane_b;
  PolygonId id_a, id_b;
  std::uint32_t rgba_a, rgba_b;
};
// With `frame`, each visible region is painted into it as it is found; with `trace`, the steps
// are recorded (`hsr explain`).
VisibleSet weilerAthertonVisibleSet(const std::vector<WindowPolygon>& polygons, int width,
                                    int height, std::size_t* state_bytes,
                                    std::vector<ClosePair>* close, Frame* frame, Trace* trace) {
  std::optional<FrameView> fb;
  if (frame) fb.emplace(*frame);
  FragmentCounts fragments;
  std::vector<Entry> entries = makeEntries(polygons, width, height);
  VisibleSet out;
  out.width = width, out.height = height;
  out.polygons_in = entries.size();
  out.see_through = static_cast<std::uint64_t>(std::count_if(
      polygons.begin(), polygons.end(), [](const WindowPolygon& w) { return w.transparent; }));
  // 1. Sort by nearest depth (ties: lower id first, the z-buffer's winner among equals).
  std::vector<std::uint32_t> order(entries.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t l, std::uint32_t r) {
    if (entries[l].zmin != entries[r].zmin) return entries[l].zmin < entries[r].zmin;
    return entries[l].id < entries[r].id;
  });
  Cells cells(entries, width, height);
  Counts c;
  if (trace && frame && trace->wants(kStepSort, 0, 1))
    trace->record(
        {kStepSort,
         "Sort the " + std::to_string(entries.size()) +
             " polygons by their nearest depth. The front one will be the first clip polygon.",
         frame,
         {}});
  std::uint64_t taken = 0, reported = 0;
  std::uint32_t stamp = 0;
  std::vector<std::uint32_t> seen(entries.size(), 0);  // the last candidate search that met each
  const std::uint64_t work_limit = kWorkPerPolygon * entries.size() + kWorkAtLeast;
  for (const std::uint32_t pi : order) {
    Entry& p = entries[pi];
    if (p.done) continue;
    if (c.work > work_limit) {  // spent: what is left goes out unresolved
      VisiblePolygon& v = out.polygons.emplace_back();
      v.id = p.id, v.rgba = p.rgba, v.resolved = false;
      v.dzdx = p.plane.dzdx, v.dzdy = p.plane.dzdy, v.z0 = p.plane.z0;
      v.area = area(p.region) / (double{kSubpixelOne} * kSubpixelOne);
      v.region = std::move(p.region);
      p.done = true;
      out.unresolved++;
      continue;
    }
    // 2.-4. P clips every polygon still in the list whose cells it shares
    if (trace && frame && trace->wants(kStepClipPolygon, taken, entries.size())) {
      std::vector<TraceOutline> o;
      addOutlines(p.region, o);
      trace->record(
          {kStepClipPolygon,
           "Take the front polygon of the list, " + std::to_string(p.id) +
               " (outlined), as the clip polygon: every polygon still in the list that it may "
               "overlap is clipped against it.",
           frame, std::move(o)});
    }
    ++taken;
    ++stamp;
    seen[pi] = stamp;
    cells.forCells(p, [&](std::vector<std::uint32_t>& cell) {
      for (std::size_t k = 0; k < cell.size();) {
        const std::uint32_t qi = cell[k];
        if (entries[qi].done) {  // output or emptied: off the cell's list
          cell[k] = cell.back();
          cell.pop_back();
          continue;
        }
        ++k;
        if (seen[qi] == stamp) continue;
        seen[qi] = stamp;
        if (p.done) continue;
        Entry& q = entries[qi];
        PairEvent event;
        if (clipPair(p, q, c, trace ? &event : nullptr) && close)
          close->push_back({p.whole, q.whole, p.plane, q.plane, p.id, q.id, p.rgba, q.rgba});
        if (trace && frame && event.kind == PairEvent::kInside &&
            trace->wants(kStepInside, reported++, entries.size())) {
          std::vector<TraceOutline> o;
          addOutlines(p.region, o);
          addOutlines(event.behind, o);
          addOutlines(event.in_front, o);
          std::string caption =
              "Clip polygon " + std::to_string(q.id) + " against " + std::to_string(p.id) +
              ": its part outside goes to the outside list. Of its part inside (outlined), ";
          if (event.in_front.empty())
            caption += "all lies behind " + std::to_string(p.id) + ": removed.";
          else if (event.behind.empty())
            caption += "all lies in front of " + std::to_string(p.id) +
                       ": the notes recurse with it as the clip polygon, and " +
                       std::to_string(p.id) +
                       " loses what lies under it; the piece stays in the list.";
          else
            caption +=
                std::string(event.split
                                ? "it crosses " + std::to_string(p.id) +
                                      " and was split along the line where their planes meet: "
                                : "some lies behind, some in front: ") +
                "the part behind is removed, " + std::to_string(p.id) +
                " loses the part under the one in front.";
          trace->record({kStepInside, std::move(caption), frame, std::move(o)});
        }
      }
    });
    // 5. What is left of P is visible.
    if (p.done) continue;
    p.done = true;
    VisiblePolygon& v = out.polygons.emplace_back();
    v.id = p.id;
    v.rgba = p.rgba;
    v.dzdx = p.plane.dzdx, v.dzdy = p.plane.dzdy, v.z0 = p.plane.z0;
    v.area = area(p.region) / (double{kSubpixelOne} * kSubpixelOne);
    v.region = std::move(p.region);
    if (fb)
      paintExactRegion(v.region, p.plane, v.id, v.rgba, *fb, fragments);  // nothing is nearer there
    if (trace && frame && trace->wants(kStepVisible, out.polygons.size() - 1, entries.size())) {
      std::vector<TraceOutline> o;
      addOutlines(v.region, o);
      trace->record(
          {kStepVisible,
           "What is left of " + std::to_string(v.id) + " (outlined, " +
               std::to_string(static_cast<int>(v.area)) +
               " square pixels) is visible: nothing still in the list lies in front of it there.",
           frame, std::move(o)});
    }
  }
  if (frame) {
    frame->stats.fragments_tested += fragments.tested;
    frame->stats.fragments_written += fragments.written;
  }
  out.pairs = c.pairs, out.clips = c.clips, out.splits = c.splits, out.work = c.work;
  if (state_bytes) *state_bytes = cells.bytes() + entries.capacity() * sizeof(Entry);
  return out;
}

void drawWeilerAtherton(const AlgorithmInput& in, Frame& frame) {
  detail::Stopwatch watch;
  std::size_t bytes = 0;
  std::vector<ClosePair> close;
  const VisibleSet set = weilerAthertonVisibleSet(in.prepared.polygons, frame.width, frame.height,
                                                  &bytes, &close, &frame, in.trace);
  const double visible_set_ms = watch.lap();
  const FrameView fb(frame);
  FragmentCounts fragments;
  // The visible set was painted as it was found (no depth test: nothing is nearer there).
  // Unresolved polygons (the work limit was reached) after it, in submission order, with GL_LESS.
  std::vector<const VisiblePolygon*> left;
  for (const VisiblePolygon& v : set.polygons)
    if (!v.resolved) left.push_back(&v);
  std::stable_sort(left.begin(), left.end(),
                   [](const VisiblePolygon* l, const VisiblePolygon* r) { return l->id < r->id; });
  for (const VisiblePolygon* v : left)
    paintExactRegion(v->region, {v->dzdx, v->dzdy, v->z0}, v->id, v->rgba, fb, fragments,
                     DepthFunc::Less);
  // Close pairs: where the exact answer and a float depth buffer may differ (two depths within
  // a float step, or a crossing line snapped to the grid), their shared pixels show what GL_LESS
  // shows: the nearest float depth, the first submitted among equals, of the pixel's polygon
  // and the two. (The pixel's own polygon is nearest in exact terms: a polygon can beat it
  // only by rounding, and so only if close to it, or to one close to it. Order does not
  // matter: each pixel ends with the least of all its candidates.)
  std::uint64_t settled = 0;
  for (const ClosePair& cp : close) {
    const ExactRegion shared = booleanOp(cp.whole_a, cp.whole_b, BooleanOp::Intersection);
    forEachCentreIn(shared, frame.width, frame.height, [&](int y, int x0, int x1) {
      const double row_a = depthRowStart(cp.plane_a, y), row_b = depthRowStart(cp.plane_b, y);
      for (int x = x0; x <= x1; ++x) {
        const std::size_t idx = fb.index(x, y);
        float z = fb.depth[idx];
        PolygonId id = fb.ids[idx];
        std::uint32_t rgba = fb.rgba[idx];
        auto consider = [&](float zc, PolygonId idc, std::uint32_t rgbac) {
          if (zc < z || (zc == z && idc < id)) z = zc, id = idc, rgba = rgbac;
        };
        consider(depthInRow(row_a, cp.plane_a, x), cp.id_a, cp.rgba_a);
        consider(depthInRow(row_b, cp.plane_b, x), cp.id_b, cp.rgba_b);
        if (id == fb.ids[idx]) continue;
        fb.ids[idx] = id, fb.depth[idx] = z, fb.rgba[idx] = rgba;
        ++settled;
      }
    });
  }
  // See-through polygons over the finished picture, in submission order, as the z-buffer.
  for (const WindowPolygon& w : in.prepared.polygons)
    if (w.transparent) fillPolygon(w, fb, DepthFunc::Less, true, fragments);
  const PixelBox viewport{0, 0, frame.width - 1, frame.height - 1};
  for (const ScreenLine& o : in.prepared.outline) drawOutlinePen(o, viewport, fb);
  if (in.trace && in.trace->wants(kStepDone, 0, 1))
    in.trace->record(
        {kStepDone,
         "Done: " + std::to_string(set.polygons.size()) + " polygons are visible, after " +
             std::to_string(set.clips) + " clips and " + std::to_string(set.splits) +
             " splits; every pixel shows the polygon whose visible part covers its centre.",
         &frame,
         {}});
  frame.stats.fragments_tested += fragments.tested;
  frame.stats.fragments_written += fragments.written;
  frame.stats.state_bytes += frameBufferBytes(frame) + bytes;
  frame.stats.addCounter("weiler-atherton: polygons in", set.polygons_in);
  frame.stats.addCounter("weiler-atherton: visible polygons", set.polygons.size());
  frame.stats.addCounter("weiler-atherton: pairs", set.pairs);
  frame.stats.addCounter("weiler-atherton: clips", set.clips);
  frame.stats.addCounter("weiler-atherton: splits", set.splits);
  frame.stats.addCounter("weiler-atherton: edges clipped", set.work);
  frame.stats.addCounter("weiler-atherton: close pairs", close.size());
  frame.stats.addCounter("weiler-atherton: left to the depth test", set.unresolved);
  frame.stats.addCounter("weiler-atherton: pixels settled as a float depth buffer", settled);
  frame.stats.addStage("visible set, painted as found", visible_set_ms);
  frame.stats.addStage("close pairs, see-through, outline", watch.ms());
}

}  // namespace hsr::detail

namespace hsr {

VisibleSet visibleSet(const Scene& scene, const Camera& camera, const RenderOptions& options) {
  if (options.polygon_mode != PolygonMode::Fill)
    throw Error("visibleSet: the polygon mode must be fill");
  const detail::PreparedScene ps =
      detail::prepare(scene, camera, options, {.window_polygons = true});
  return detail::weilerAthertonVisibleSet(ps.polygons, ps.width, ps.height, nullptr, nullptr,
                                          nullptr, nullptr);
}

}  // namespace hsr
