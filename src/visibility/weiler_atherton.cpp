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
#include <vector>

#include "core/frame.hpp"
#include "hsr/error.hpp"
#include "hsr/visible_set.hpp"
#include "raster/fill_polygons.hpp"
#include "raster/lines.hpp"
#include "visibility/algorithm.hpp"

namespace hsr::detail {
namespace {

// Two depths closer than this (window depth, 0..1) are equal: as the painter's kOnPlane, far
// below what a float depth buffer resolves, far above double's rounding of a plane's value.
constexpr double kOnPlane = 1e-12;
// The split line's two grid points lie this far (grid units, 2^16 pixels) either side of the
// piece's centre: the line's direction is then rounded by under 2^-24 radians.
constexpr double kSplitReach = 16777216.0;

struct Entry {
  ExactRegion region;        // what is left of the polygon
  DepthPlane plane;
  PolygonId id = kNoPolygon;
  std::uint32_t rgba = 0;
  double zmin = 0, zmax = 0;  // depth extent of the whole polygon
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // box of what is left, grid units
  bool done = false;          // output (or emptied)
  std::uint32_t seen = 0;     // stamp of the last candidate search that met it
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
      e.x0 = std::min(e.x0, x), e.x1 = std::max(e.x1, x), e.y0 = std::min(e.y0, y), e.y1 = std::max(e.y1, y);
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

enum class Verdict { Behind, InFront, Crossing };

// Where a piece of Q inside P lies against P: the sign of z_Q - z_P at its corners.
Verdict compare(const ExactPolygon& piece, const Entry& p, const Entry& q) {
  bool behind = true, in_front = true;
  for (const ExactPoint& v : piece.outer) {
    const double dz = depthAt(q.plane, v.xd(), v.yd()) - depthAt(p.plane, v.xd(), v.yd());
    behind = behind && dz >= -kOnPlane;
    in_front = in_front && dz <= kOnPlane;
  }
  if (behind && in_front) return p.id < q.id ? Verdict::Behind : Verdict::InFront;  // one plane
  return behind ? Verdict::Behind : in_front ? Verdict::InFront : Verdict::Crossing;
}

// The half of the plane where Q is deeper than P, bounded by the line where their depths are
// equal snapped to the grid (see the top of this file), as a quad around the piece.
GridRegion deeperSide(const ExactPolygon& piece, const Entry& p, const Entry& q) {
  // z_Q - z_P = A gx + B gy + C in grid units
  const double A = (q.plane.dzdx - p.plane.dzdx) / kSubpixelOne, B = (q.plane.dzdy - p.plane.dzdy) / kSubpixelOne;
  const double C = q.plane.z0 - p.plane.z0;
  double cx = 0, cy = 0;
  for (const ExactPoint& v : piece.outer) cx += v.xd(), cy += v.yd();
  cx /= static_cast<double>(piece.outer.size()), cy /= static_cast<double>(piece.outer.size());
  const double len = std::hypot(A, B);
  const double nx = A / len, ny = B / len;  // towards Q deeper
  const double off = (A * cx + B * cy + C) / len;  // the centre's distance from the line
  const double px = cx - nx * off, py = cy - ny * off;  // its foot on the line
  const double r = kSplitReach;
  if (!(len > 0) || !(std::abs(px) < 2 * r && std::abs(py) < 2 * r)) return {};
  auto at = [](double x, double y) { return GridPoint{std::llround(x), std::llround(y)}; };
  return {{{at(px - ny * r, py + nx * r), at(px + ny * r, py - nx * r), at(px + ny * r + nx * r, py - nx * r + ny * r),
            at(px - ny * r + nx * r, py + nx * r + ny * r)},
           {}}};
}

struct Counts {
  std::uint64_t pairs = 0, clips = 0, splits = 0, separated = 0, deeper = 0, apart = 0;
};

// Steps 3 and 4 for the clip polygon p and one other polygon q.
void clipPair(Entry& p, Entry& q, Counts& c) {
  c.pairs++;
  if (q.x0 >= p.x1 || q.x1 <= p.x0 || q.y0 >= p.y1 || q.y1 <= p.y0) {
    c.apart++;
    return;
  }
  if (q.zmin > p.zmax + kOnPlane) {  // Q deeper than P everywhere: its part inside P is hidden
    c.deeper++, c.clips++;
    q.region = booleanOp(q.region, p.region, BooleanOp::AMinusB);
    updateBox(q);
    return;
  }
  if (separated(p.region, q.region)) {
    c.separated++;
    return;
  }
  c.clips++;
  const ExactRegion inside = booleanOp(q.region, p.region, BooleanOp::Intersection);
  if (inside.empty()) return;
  ExactRegion hidden_q, hidden_p;  // pieces behind P, pieces in front of it
  for (const ExactPolygon& piece : inside) {
    const Verdict v = compare(piece, p, q);
    if (v == Verdict::Behind) hidden_q.push_back(piece);
    else if (v == Verdict::InFront) hidden_p.push_back(piece);
    else {
      const GridRegion side = deeperSide(piece, p, q);
      if (side.empty() || !invalidRegionReason(side).empty()) {  // planes all but parallel: no line to cut along
        (p.id < q.id ? hidden_q : hidden_p).push_back(piece);
        continue;
      }
      c.splits++, c.clips += 2;
      const ExactRegion one{piece}, deeper = exactRegion(side);
      for (const ExactPolygon& s : booleanOp(one, deeper, BooleanOp::Intersection)) hidden_q.push_back(s);
      for (const ExactPolygon& s : booleanOp(one, deeper, BooleanOp::AMinusB)) hidden_p.push_back(s);
    }
  }
  auto remove = [&](Entry& e, const ExactRegion& pieces, const ExactRegion& rest, const ExactRegion& whole_other) {
    if (pieces.empty()) return;
    if (rest.empty()) {
      c.clips++;
      e.region = booleanOp(e.region, whole_other, BooleanOp::AMinusB);  // all of the inside
    } else {
      for (const ExactPolygon& piece : pieces) {
        c.clips++;
        e.region = booleanOp(e.region, ExactRegion{piece}, BooleanOp::AMinusB);
      }
    }
    updateBox(e);
  };
  remove(q, hidden_q, hidden_p, p.region);  // (when all of the inside is behind: Q − P)
  remove(p, hidden_p, hidden_q, q.region);  // (when all of it is in front: P − Q; Q is as it was)
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
  template <class Fn>
  void forCells(const Entry& e, Fn&& fn) {
    const int c0 = col(e.x0), c1 = col(e.x1), r0 = row(e.y0), r1 = row(e.y1);
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c) fn(cells_[static_cast<std::size_t>(r) * cols_ + c]);
  }
  std::size_t bytes() const {
    std::size_t b = cells_.capacity() * sizeof(cells_[0]);
    for (const auto& c : cells_) b += c.capacity() * sizeof(std::uint32_t);
    return b;
  }

 private:
  int col(double x) const { return std::clamp(static_cast<int>(std::floor(x / side_)), 0, cols_ - 1); }
  int row(double y) const { return std::clamp(static_cast<int>(std::floor(y / side_)), 0, rows_ - 1); }
  double side_ = 1;
  int cols_ = 1, rows_ = 1;
  std::vector<std::vector<std::uint32_t>> cells_;
};

// The list: each opaque polygon snapped to the grid. A polygon that snapping folds (rare: a
// sliver clipped at the frustum) enters as the triangles of a fan, each valid one an entry.
std::vector<Entry> makeEntries(const std::vector<WindowPolygon>& polygons) {
  std::vector<Entry> entries;
  entries.reserve(polygons.size());
  auto add = [&](const WindowPolygon& w, const GridRing& ring) {
    const GridRegion region{{ring, {}}};
    if (!invalidRegionReason(region).empty()) return false;
    Entry e;
    e.region = exactRegion(region);
    e.plane = w.depth;
    e.id = w.id;
    e.rgba = w.rgba;
    e.zmin = INFINITY, e.zmax = -INFINITY;
    for (const GridPoint& v : ring) {
      const double z = depthAt(w.depth, static_cast<double>(v.x), static_cast<double>(v.y));
      e.zmin = std::min(e.zmin, z), e.zmax = std::max(e.zmax, z);
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
      if (in_range) ring.push_back({std::llrint(v.x * kSubpixelOne), std::llrint(v.y * kSubpixelOne)});
    }
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    while (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
    if (!in_range || ring.size() < 3) continue;
    if (add(w, ring)) continue;
    for (std::size_t k = 1; k + 1 < ring.size(); ++k) add(w, {ring[0], ring[k], ring[k + 1]});
  }
  return entries;
}

}  // namespace

VisibleSet weilerAthertonVisibleSet(const std::vector<WindowPolygon>& polygons, int width, int height,
                                    std::size_t* state_bytes) {
  std::vector<Entry> entries = makeEntries(polygons);
  VisibleSet out;
  out.width = width, out.height = height;
  out.polygons_in = entries.size();
  // 1. Sort by nearest depth (ties: lower id first, the z-buffer's winner among equals).
  std::vector<std::uint32_t> order(entries.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t l, std::uint32_t r) {
    if (entries[l].zmin != entries[r].zmin) return entries[l].zmin < entries[r].zmin;
    return entries[l].id < entries[r].id;
  });
  Cells cells(entries, width, height);
  Counts c;
  std::uint32_t stamp = 0;
  for (const std::uint32_t pi : order) {
    Entry& p = entries[pi];
    if (p.done) continue;
    // 2.-4. P clips every polygon still in the list whose cells it shares
    ++stamp;
    p.seen = stamp;
    cells.forCells(p, [&](std::vector<std::uint32_t>& cell) {
      for (const std::uint32_t qi : cell) {
        Entry& q = entries[qi];
        if (q.seen == stamp || q.done) continue;
        q.seen = stamp;
        if (!p.done) clipPair(p, q, c);
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
  }
  out.pairs = c.pairs, out.clips = c.clips, out.splits = c.splits;
  if (state_bytes) *state_bytes = cells.bytes() + entries.capacity() * sizeof(Entry);
  return out;
}

void drawWeilerAtherton(const AlgorithmInput& in, Frame& frame) {
  const auto t0 = std::chrono::steady_clock::now();
  std::size_t bytes = 0;
  const VisibleSet set = weilerAthertonVisibleSet(in.prepared.polygons, frame.width, frame.height, &bytes);
  const auto t1 = std::chrono::steady_clock::now();
  const FrameView fb(frame);
  FragmentCounts fragments;
  for (const VisiblePolygon& v : set.polygons) {
    paintExactRegion(v.region, {v.dzdx, v.dzdy, v.z0}, v.id, v.rgba, fb, fragments);
  }
  // See-through polygons over the finished picture, in submission order, as the z-buffer.
  for (const WindowPolygon& w : in.prepared.polygons)
    if (w.transparent) fillPolygon(w, fb, DepthFunc::Less, true, fragments);
  const PixelBox viewport{0, 0, frame.width - 1, frame.height - 1};
  for (const ScreenLine& o : in.prepared.outline) drawOutlinePen(o, viewport, fb);
  frame.stats.fragments_tested += fragments.tested;
  frame.stats.fragments_written += fragments.written;
  frame.stats.state_bytes += frameBufferBytes(frame) + bytes;
  frame.stats.addCounter("weiler-atherton: polygons in", set.polygons_in);
  frame.stats.addCounter("weiler-atherton: visible polygons", set.polygons.size());
  frame.stats.addCounter("weiler-atherton: pairs", set.pairs);
  frame.stats.addCounter("weiler-atherton: clips", set.clips);
  frame.stats.addCounter("weiler-atherton: splits", set.splits);
  frame.stats.addStage("visible set", std::chrono::duration<double, std::milli>(t1 - t0).count());
  frame.stats.addStage("fill", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count());
}

}  // namespace hsr::detail

namespace hsr {

VisibleSet visibleSet(const Scene& scene, const Camera& camera, const RenderOptions& options) {
  if (options.polygon_mode != PolygonMode::Fill) throw Error("visibleSet: the polygon mode must be fill");
  const detail::PreparedScene ps = detail::prepare(scene, camera, options, {.window_polygons = true});
  return detail::weilerAthertonVisibleSet(ps.polygons, ps.width, ps.height, nullptr);
}

}  // namespace hsr
