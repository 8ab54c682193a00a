// Which parts of a scene's lines are visible (line_visibility.hpp), in four steps:
//
//   1. Edges. Every edge of every polygon, found once with the polygons on either side of it
//      (by its two corners' window positions, within one object; EdgeMatcher).
//   2. Which edges are lines, before any visibility test. An outline: one polygon only (an open
//      border, or the other culled or clipped away), or the two fold over each other in the
//      picture (both lie on one side of the edge: a silhouette). A crease: the two meet at more
//      than the crease angle, their normals turned towards the eye. Every other edge (inside a
//      smooth surface) is no line and costs nothing more.
//   3. Intersection lines: where a triangle of one object passes through one of another (or of
//      its own object, sharing no corner with it), the segment both hold. Candidate pairs
//      share a grid cell and overlap in depth.
//   4. Hiding. A point of a line is hidden when a triangle lies in front of it on its line of
//      sight. In the window the lines of sight run along z, so a triangle hides the interval
//      of the line inside its outline (clipped against its three sides) where its depth is
//      less than the line's: depth is linear along both, so that is one interval. The
//      triangles to try are those in the grid cells the line crosses and that come nearer
//      than its far end. What no interval covers is visible; the rest is the hidden part.
// Polygons are cut into triangles for step 4 (the line's own polygons are never tried against
// it). A closed object the view does not cut is seen from outside, so its faces turned away
// from the eye are hidden by its own faces turned towards it: they hide nothing that those do
// not, and are left out of steps 3 and 4 (edges between two of them are hidden whole).
// See-through polygons are left out: they hide nothing, and their edges are not drawn (the
// z-buffer's ids, which the drawings are checked against, do not show them either).

#include "lines/line_visibility.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/parallel.hpp"
#include "core/stopwatch.hpp"
#include "geometry/triangulate.hpp"

namespace hsr::detail {
namespace {

using glm::dvec2;
using glm::dvec3;

// A point must lie this far inside a triangle's outline (pixels) to be hidden by it: a line
// that runs along a triangle's side, or only touches it at a corner, is not hidden.
constexpr double kInside = 1e-7;
// ... and this far behind it in window depth, where two triangles are compared (step 3): a
// line on a triangle's own plane (its edge, a corner it shares) is not hidden by it.
constexpr double kBehind = 1e-11;
// Step 4 compares a line with a triangle of another polygon, both given by the pipeline's float
// window positions: a line lying in the triangle's plane is off it by their rounding, which is
// a few float ulps of the depth plus the plane's slope times a few ulps of x and y (1e-7 of
// depth, not 1e-11: on a tilted floor, a quarter of a fin's foot standing on it was hidden).
// Within kRoundingUlps such ulps of the triangle's plane, a line is on it, not behind it.
constexpr double kRoundingUlps = 16;
// Triangles with less doubled area than this in the window (pixels squared) are edge-on:
// they hide nothing.
constexpr double kEdgeOn = 1e-12;
// Pieces shorter than this (pixels) are left out, as on Roberts' path.
constexpr double kShortest = 1.0 / 256;

// ---- Step 1: edges keyed by object and corners

struct EdgeKey {
  std::uint32_t object = 0;
  std::array<float, 3> a{}, b{};  // a < b
  bool operator==(const EdgeKey&) const = default;
};

std::array<float, 3> corner(const dvec3& p) {
  // + 0.0f makes -0 into +0, so equal positions have equal bits
  return {static_cast<float>(p.x) + 0.0f, static_cast<float>(p.y) + 0.0f,
          static_cast<float>(p.z) + 0.0f};
}

std::uint64_t hashOf(const EdgeKey& k) {
  std::uint32_t words[7];
  std::memcpy(words, &k.object, 4);
  std::memcpy(words + 1, k.a.data(), 12);
  std::memcpy(words + 4, k.b.data(), 12);
  std::uint64_t h = 0x9E3779B97F4A7C15ull;
  for (const std::uint32_t w : words) {
    h ^= w;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 31;
  }
  return h;
}

struct EdgeUse {
  EdgeKey key;                          // its corners are the edge's exact end points
  std::uint32_t first = 0, second = 0;  // window polygon indices
  std::uint32_t hash = 0;               // where it belongs in the matcher's table
  std::uint8_t uses = 0;                // 1: one polygon (an open border), 2: two
  bool first_forward = true;            // `first` runs the edge from key.a to key.b
  bool opposite = true;                 // `second` runs it the other way
};

// Pairs each edge's two polygons. The table (open addressing, linear probing) holds only the
// edges still waiting for their second polygon: taken in order, a mesh's polygons meet their
// neighbours soon, so that is the front of the mesh reached so far, small enough to stay in
// the cache (a table of every edge would not, and its random accesses grew the time faster
// than the scene). A pair found leaves the table for the list. A third polygon on an edge
// starts it again, so a non-manifold edge ends as a pair and a border.
class EdgeMatcher {
 public:
  explicit EdgeMatcher(std::size_t expected) {
    grow(1024);
    found_.reserve(expected);
  }
  void add(std::uint32_t object, const dvec3& p, const dvec3& q, std::uint32_t polygon) {
    EdgeKey key{object, corner(p), corner(q)};
    const bool forward = key.a < key.b;
    if (!forward) std::swap(key.a, key.b);
    if (key.a == key.b) return;  // a zero-length edge draws nothing
    const std::uint32_t hash = static_cast<std::uint32_t>(hashOf(key) >> 32);
    std::size_t i = hash & mask_;
    for (; slots_[i].uses != 0; i = (i + 1) & mask_)
      if (slots_[i].hash == hash && slots_[i].key == key) {
        EdgeUse e = slots_[i];
        e.second = polygon, e.opposite = forward != e.first_forward, e.uses = 2;
        found_.push_back(e);
        erase(i);
        return;
      }
    slots_[i] = {key, polygon, 0, hash, 1, forward, true};
    if (++waiting_ * 2 > slots_.size()) grow(slots_.size() * 2);
  }
  // Every edge: the pairs, then those left with one polygon.
  std::vector<EdgeUse> finish() {
    for (const EdgeUse& e : slots_)
      if (e.uses != 0) found_.push_back(e);
    return std::move(found_);
  }

 private:
  // Backward-shift deletion: later entries of the run move up unless they belong after i.
  void erase(std::size_t i) {
    for (std::size_t j = i;;) {
      j = (j + 1) & mask_;
      if (slots_[j].uses == 0) break;
      const std::size_t home = slots_[j].hash & mask_;
      const bool stays = i <= j ? (i < home && home <= j) : (i < home || home <= j);
      if (stays) continue;
      slots_[i] = slots_[j];
      i = j;
    }
    slots_[i].uses = 0;
    --waiting_;
  }
  void grow(std::size_t capacity) {
    std::vector<EdgeUse> old(capacity);
    old.swap(slots_);
    mask_ = capacity - 1;
    for (const EdgeUse& e : old)
      if (e.uses != 0) {
        std::size_t i = e.hash & mask_;
        while (slots_[i].uses != 0) i = (i + 1) & mask_;
        slots_[i] = e;
      }
  }
  std::vector<EdgeUse> slots_, found_;
  std::size_t mask_ = 0, waiting_ = 0;
};

dvec3 pointOf(const std::array<float, 3>& c) { return dvec3(c[0], c[1], c[2]); }

// ---- Step 4's triangles

// Window positions are the pipeline's floats, so the corners, boxes and depth ranges are
// exact as floats (and the struct a third smaller: one-shot drawings pay for fresh memory).
struct Occluder {
  glm::vec3 v[3];              // counter-clockwise in x, y
  double ex[3], ey[3], ec[3];  // sides: ex x + ey y + ec is the distance inside (pixels)
  double dzdx = 0, dzdy = 0;   // depth plane: v[0].z + dzdx (x - v[0].x) + dzdy (y - v[0].y)
  double behind = 0;           // a line must lie this far behind the plane to be hidden by it
  float zmin = 0, zmax = 0;
  float xmin = 0, ymin = 0, xmax = 0, ymax = 0;
  PolygonId id = kNoPolygon;
  std::uint32_t object = 0;

  dvec3 at(int k) const { return dvec3(v[k]); }
  double depthAt(double x, double y) const {
    return v[0].z + dzdx * (x - v[0].x) + dzdy * (y - v[0].y);
  }
};

bool makeOccluder(dvec3 a, dvec3 b, dvec3 c, PolygonId id, std::uint32_t object, Occluder& o) {
  double area2 = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (!(std::abs(area2) > kEdgeOn)) return false;
  if (area2 < 0) std::swap(b, c), area2 = -area2;
  const dvec3 p[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) {
    const dvec3 &u = p[k], &w = p[(k + 1) % 3];
    const double dx = w.x - u.x, dy = w.y - u.y, len = std::sqrt(dx * dx + dy * dy);
    o.ex[k] = -dy / len, o.ey[k] = dx / len;
    o.ec[k] = -(o.ex[k] * u.x + o.ey[k] * u.y);
    o.v[k] = glm::vec3(u);
  }
  const dvec3 e1 = b - a, e2 = c - a;
  o.dzdx = (e1.z * e2.y - e2.z * e1.y) / area2;
  o.dzdy = (e2.z * e1.x - e1.z * e2.x) / area2;
  o.zmin = static_cast<float>(std::min({a.z, b.z, c.z}));
  o.zmax = static_cast<float>(std::max({a.z, b.z, c.z}));
  const double reach_z = std::max({std::abs(a.z), std::abs(b.z), std::abs(c.z)});
  const double reach_xy = std::max(
      {std::abs(a.x), std::abs(b.x), std::abs(c.x), std::abs(a.y), std::abs(b.y), std::abs(c.y)});
  o.behind = std::max(kBehind, kRoundingUlps * 0x1p-24 *
                                   (reach_z + (std::abs(o.dzdx) + std::abs(o.dzdy)) * reach_xy));
  o.xmin = static_cast<float>(std::min({a.x, b.x, c.x}));
  o.xmax = static_cast<float>(std::max({a.x, b.x, c.x}));
  o.ymin = static_cast<float>(std::min({a.y, b.y, c.y}));
  o.ymax = static_cast<float>(std::max({a.y, b.y, c.y}));
  o.id = id, o.object = object;
  return true;
}

// Screen cells, each listing the triangles whose boxes reach it.
struct Grid {
  double cell = 1;
  int columns = 1, rows = 1;
  std::vector<std::uint32_t> start, items;  // cell c holds items[start[c] .. start[c + 1])

  int column(double x) const {
    return std::clamp(static_cast<int>(std::floor(x / cell)), 0, columns - 1);
  }
  int row(double y) const {
    return std::clamp(static_cast<int>(std::floor(y / cell)), 0, rows - 1);
  }
};

Grid makeGrid(const std::vector<Occluder>& occ, int width, int height) {
  Grid g;
  double side = 0;
  for (const Occluder& o : occ) side += std::max(o.xmax - o.xmin, o.ymax - o.ymin);
  const double n = std::max<double>(1.0, static_cast<double>(occ.size()));
  // About two triangles per cell, and cells no smaller than the typical triangle
  g.cell = std::max({side / n, std::sqrt(2.0 * width * height / n), 0.5});
  g.columns = std::clamp(static_cast<int>(std::ceil(width / g.cell)), 1, 4096);
  g.rows = std::clamp(static_cast<int>(std::ceil(height / g.cell)), 1, 4096);
  g.cell = std::max(width / static_cast<double>(g.columns), height / static_cast<double>(g.rows));
  g.start.assign(static_cast<std::size_t>(g.columns) * g.rows + 1, 0);
  auto each = [&](const Occluder& o, auto&& f) {
    const int c0 = g.column(o.xmin), c1 = g.column(o.xmax);
    for (int r = g.row(o.ymin), r1 = g.row(o.ymax); r <= r1; ++r)
      for (int c = c0; c <= c1; ++c) f(static_cast<std::size_t>(r) * g.columns + c);
  };
  for (const Occluder& o : occ) each(o, [&](std::size_t c) { g.start[c + 1]++; });
  for (std::size_t c = 1; c < g.start.size(); ++c) g.start[c] += g.start[c - 1];
  g.items.resize(g.start.back());
  std::vector<std::uint32_t> fill(g.start.begin(), g.start.end() - 1);
  for (std::uint32_t i = 0; i < occ.size(); ++i)
    each(occ[i], [&](std::size_t c) { g.items[fill[c]++] = i; });
  return g;
}

// A line to test: its window end points, the polygons it belongs to (never tried against it)
// and its kind.
struct Line {
  dvec3 a, b;
  PolygonId face = kNoPolygon, other = kNoPolygon;
  std::uint8_t kind = 0;
  bool hidden_whole = false;
};

// ---- Step 2's tests

// The polygon's eye-space normal on the side the eye is (in perspective the eye is the origin;
// in parallel it is far towards +z).
dvec3 towardsEye(const WindowPolygon& w, bool ortho) {
  const dvec3 n(w.eye_plane);
  return (ortho ? n.z : w.eye_plane.w) < 0 ? -n : n;
}

// ---- Step 3: where two triangles cross

// The points of triangle t on the plane of triangle s (signed depth differences d), as the
// two ends of a segment; false when t does not cross it.
bool sectionOn(const Occluder& t, const double d[3], dvec3& p, dvec3& q) {
  dvec3 pts[4];
  int n = 0;
  for (int k = 0; k < 3 && n < 4; ++k) {
    const int j = (k + 1) % 3;
    if (std::abs(d[k]) <= kBehind) pts[n++] = t.at(k);
    if ((d[k] > kBehind && d[j] < -kBehind) || (d[k] < -kBehind && d[j] > kBehind)) {
      const double s = d[k] / (d[k] - d[j]);
      pts[n++] = t.at(k) + s * (t.at(j) - t.at(k));
    }
  }
  if (n < 2) return false;
  // The two farthest apart (more than two only through rounding)
  p = pts[0], q = pts[1];
  double best = glm::length(dvec2(q - p));
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (const double l = glm::length(dvec2(pts[j] - pts[i])); l > best)
        best = l, p = pts[i], q = pts[j];
  return best > 0;
}

bool crosses(const Occluder& s, const Occluder& t, dvec3& p, dvec3& q) {
  double ds[3], dt[3];  // s's corners against t's plane, and t's against s's
  for (int k = 0; k < 3; ++k) {
    ds[k] = s.v[k].z - t.depthAt(s.v[k].x, s.v[k].y);
    dt[k] = t.v[k].z - s.depthAt(t.v[k].x, t.v[k].y);
  }
  auto straddles = [](const double d[3]) {
    return std::max({d[0], d[1], d[2]}) > kBehind && std::min({d[0], d[1], d[2]}) < -kBehind;
  };
  if (!straddles(ds) || !straddles(dt)) return false;
  dvec3 s0, s1, t0, t1;
  if (!sectionOn(s, ds, s0, s1) || !sectionOn(t, dt, t0, t1)) return false;
  // Both lie on the planes' common line: overlap them along s's segment
  const dvec2 u = dvec2(s1 - s0);
  const double uu = glm::dot(u, u);
  double a = glm::dot(dvec2(t0 - s0), u) / uu, b = glm::dot(dvec2(t1 - s0), u) / uu;
  if (a > b) std::swap(a, b);
  a = std::max(a, 0.0), b = std::min(b, 1.0);
  if (!((b - a) * std::sqrt(uu) > kShortest)) return false;
  p = s0 + a * (s1 - s0), q = s0 + b * (s1 - s0);
  return true;
}

bool shareCorner(const Occluder& s, const Occluder& t) {
  for (const glm::vec3& p : s.v)
    for (const glm::vec3& q : t.v)
      if (p == q) return true;
  return false;
}

// ---- Step 4: the hidden intervals of one line

struct Scratch {
  std::vector<std::uint32_t> stamp;  // per triangle: the last line (+1) that tried it
  std::vector<std::pair<double, double>> hidden;
};

void hide(const Line& line, std::uint32_t stamp, const std::vector<Occluder>& occ, const Grid& grid,
          Scratch& s, std::uint64_t& tests) {
  s.hidden.clear();
  const dvec3 a = line.a, b = line.b;
  const double zfar = std::max(a.z, b.z);
  const double lx0 = std::min(a.x, b.x), lx1 = std::max(a.x, b.x);
  const double ly0 = std::min(a.y, b.y), ly1 = std::max(a.y, b.y);
  auto tryCell = [&](std::size_t c) {
    for (std::uint32_t k = grid.start[c]; k < grid.start[c + 1]; ++k) {
      const std::uint32_t i = grid.items[k];
      if (s.stamp[i] == stamp) continue;
      s.stamp[i] = stamp;
      const Occluder& o = occ[i];
      if (o.zmin >= zfar || o.id == line.face || o.id == line.other) continue;
      if (o.xmin >= lx1 || o.xmax <= lx0 || o.ymin >= ly1 || o.ymax <= ly0) continue;
      ++tests;
      // The part of the line inside the triangle's outline
      double t0 = 0, t1 = 1;
      for (int e = 0; e < 3 && t0 < t1; ++e) {
        const double f0 = o.ex[e] * a.x + o.ey[e] * a.y + o.ec[e] - kInside;
        const double f1 = o.ex[e] * b.x + o.ey[e] * b.y + o.ec[e] - kInside;
        if (f0 <= 0 && f1 <= 0)
          t1 = -1;
        else if (f0 < 0)
          t0 = std::max(t0, f0 / (f0 - f1));
        else if (f1 < 0)
          t1 = std::min(t1, f0 / (f0 - f1));
      }
      if (!(t0 < t1)) continue;
      // ... where the triangle is in front: d(t) = line depth - triangle depth, linear in t
      const double d0 = a.z - o.depthAt(a.x, a.y) - o.behind;
      const double d1 = b.z - o.depthAt(b.x, b.y) - o.behind;
      const double dt0 = d0 + t0 * (d1 - d0), dt1 = d0 + t1 * (d1 - d0);
      if (dt0 <= 0 && dt1 <= 0) continue;
      if (dt0 < 0)
        t0 = t0 + (t1 - t0) * (dt0 / (dt0 - dt1));
      else if (dt1 < 0)
        t1 = t0 + (t1 - t0) * (dt0 / (dt0 - dt1));
      if (t0 < t1) s.hidden.emplace_back(t0, t1);
    }
  };
  // The cells the line crosses, row by row
  const int r0 = grid.row(ly0), r1 = grid.row(ly1);
  for (int r = r0; r <= r1; ++r) {
    double xa = lx0, xb = lx1;
    if (r0 != r1 && b.y != a.y) {
      const double y0 = std::max(ly0, r * grid.cell), y1 = std::min(ly1, (r + 1) * grid.cell);
      const double sa = (y0 - a.y) / (b.y - a.y), sb = (y1 - a.y) / (b.y - a.y);
      xa = a.x + std::clamp(sa, 0.0, 1.0) * (b.x - a.x);
      xb = a.x + std::clamp(sb, 0.0, 1.0) * (b.x - a.x);
      if (xa > xb) std::swap(xa, xb);
    }
    for (int c = grid.column(xa), c1 = grid.column(xb); c <= c1; ++c)
      tryCell(static_cast<std::size_t>(r) * grid.columns + c);
  }
  // The union of the hidden intervals
  std::sort(s.hidden.begin(), s.hidden.end());
  std::size_t n = 0;
  for (const auto& h : s.hidden)
    if (n > 0 && h.first <= s.hidden[n - 1].second)
      s.hidden[n - 1].second = std::max(s.hidden[n - 1].second, h.second);
    else
      s.hidden[n++] = h;
  s.hidden.resize(n);
}

struct Pieces {
  std::vector<StrokeSegment> visible, hidden;
  std::vector<LinePiece> visible3, hidden3;
  std::uint64_t counts[3] = {0, 0, 0};
  std::uint64_t tests = 0;
};

bool addPiece(std::vector<StrokeSegment>& to, std::vector<LinePiece>* to3, const Line& line,
              double t0, double t1) {
  const dvec2 a(line.a), d = dvec2(line.b) - a;
  if ((t1 - t0) * glm::length(d) < kShortest) return false;
  to.push_back({a + t0 * d, a + t1 * d, line.kind});
  if (to3) {
    const dvec3 e = line.b - line.a;
    to3->push_back({line.a + t0 * e, line.a + t1 * e, line.face, line.other, line.kind});
  }
  return true;
}

}  // namespace

LineVisibility lineVisibility(const Scene& scene, const std::vector<WindowPolygon>& polygons,
                              int width, int height, const LineRequest& request) {
  LineVisibility out;
  detail::Stopwatch t0;
  auto lap = [&](const char* stage) { out.stages.emplace_back(stage, t0.lap()); };
  const std::uint32_t np = static_cast<std::uint32_t>(polygons.size());
  // ---- 1. Edges
  std::size_t corners = 0;
  for (const WindowPolygon& w : polygons) corners += w.vertices.size();
  EdgeMatcher matcher(corners / 2 + 16);  // a closed mesh's edges: half its corners
  std::vector<std::uint32_t> object_of(np);
  for (std::uint32_t i = 0; i < np; ++i) {
    const WindowPolygon& w = polygons[i];
    object_of[i] = scene.object(w.id);
    if (w.transparent) continue;  // see-through: neither drawn nor hiding, as on Roberts' path
    for (std::size_t k = 0, n = w.vertices.size(); k < n; ++k)
      matcher.add(object_of[i], w.vertices[k], w.vertices[(k + 1) % n], i);
    checkDeadline(request.deadline, i);
  }
  const std::vector<EdgeUse> edges = matcher.finish();
  lap("edges");
  // Closed objects (every edge in view has two polygons running it in opposite directions),
  // and which way they wind: the sign of their volume in the window
  std::vector<std::int8_t> open(scene.objects.size(), 0);
  std::vector<double> volume(scene.objects.size(), 0.0), size(scene.objects.size(), 0.0);
  for (const EdgeUse& e : edges)
    if (e.uses != 2 || !e.opposite) open[e.key.object] = 1;
  std::vector<double> facing(np);  // doubled signed area in x, y: the normal's z
  for (std::uint32_t i = 0; i < np; ++i) {
    const std::vector<dvec3>& v = polygons[i].vertices;
    double area2 = 0;
    for (std::size_t k = 0, n = v.size(); k < n; ++k) {
      const dvec3 &p = v[k], &q = v[(k + 1) % n];
      area2 += p.x * q.y - q.x * p.y;
      if (k > 0 && k + 1 < n) {
        const double term = glm::dot(v[0], glm::cross(p, q));
        volume[object_of[i]] += term, size[object_of[i]] += std::abs(term);
      }
    }
    facing[i] = area2;
  }
  // Faces turned away from the eye (outward normal towards +z, away from it) of closed objects
  std::vector<char> away(np, 0);
  for (std::uint32_t i = 0; i < np; ++i) {
    const std::uint32_t o = object_of[i];
    // (a flat closed object, as a two-sided sheet, has no volume to wind around: none)
    away[i] = !open[o] && std::abs(volume[o]) > 1e-9 * size[o] &&
              (volume[o] > 0 ? facing[i] : -facing[i]) > 0;
  }

  // ---- 2. Which edges are lines
  const double cos_crease = std::cos(request.crease_angle_deg * 3.14159265358979323846 / 180.0);
  // Each polygon's normal in eye space, of unit length, turned towards the eye (0 when it has none)
  std::vector<dvec3> normal(np);
  for (std::uint32_t i = 0; i < np; ++i) {
    const dvec3 n = towardsEye(polygons[i], request.ortho);
    const double l = glm::length(n);
    normal[i] = l > 0 ? n / l : dvec3(0.0);
  }
  std::vector<Line> lines;
  for (const EdgeUse& e : edges) {
    Line line{pointOf(e.key.a), pointOf(e.key.b), polygons[e.first].id};
    int kind = 0;  // an outline, unless:
    if (e.uses == 2) {
      const std::uint32_t f = e.first, g = e.second;
      line.other = polygons[g].id;
      if (line.other == line.face) continue;  // inside a non-planar polygon
      // Each polygon lies on the left of the edge as it runs it when it turns counter-clockwise
      // in x, y (positive area), on the right when clockwise, on it when edge-on.
      const int side_f = (facing[f] > 0) - (facing[f] < 0);
      const int side_g = ((facing[g] > 0) - (facing[g] < 0)) * (e.opposite ? -1 : 1);
      if (side_f == 0 || side_f != side_g) {
        if (normal[f] != dvec3(0.0) && normal[g] != dvec3(0.0)) {
          if (!(glm::dot(normal[f], normal[g]) < cos_crease)) {
            out.smooth_edges++;
            continue;
          }
          kind = 1;
        }
      }
      line.hidden_whole = away[f] && away[g];
    }
    if (!(kind == 0 ? request.outlines : request.creases)) continue;
    if (line.hidden_whole && !request.hidden) continue;
    line.kind = static_cast<std::uint8_t>(kind);
    lines.push_back(line);
  }
  lap("classify");
  // Triangles that hide: all but the see-through and the closed objects' faces turned away
  std::vector<Occluder> occ;
  std::size_t triangles = 0;
  for (std::uint32_t i = 0; i < np; ++i)
    if (!polygons[i].transparent && !away[i]) triangles += polygons[i].vertices.size() - 2;
  occ.reserve(triangles);
  std::vector<std::array<std::uint32_t, 3>> fan;
  std::vector<dvec2> flat;
  for (std::uint32_t i = 0; i < np; ++i) {
    const WindowPolygon& w = polygons[i];
    if (w.transparent || away[i]) continue;
    const std::vector<dvec3>& v = w.vertices;
    Occluder o;
    if (v.size() == 3) {
      if (makeOccluder(v[0], v[1], v[2], w.id, object_of[i], o)) occ.push_back(o);
      continue;
    }
    flat.clear();
    for (const dvec3& p : v) flat.emplace_back(p.x, p.y);
    fan.clear();
    triangulate2d(flat, fan);
    for (const auto& t : fan)
      if (makeOccluder(v[t[0]], v[t[1]], v[t[2]], w.id, object_of[i], o)) occ.push_back(o);
  }
  lap("triangles");
  const Grid grid = makeGrid(occ, width, height);
  lap("occluders");

  // ---- 3. Intersection lines
  if (request.intersections) {
    // A row of cells per task, joined in row order (the same lines for any thread count)
    std::vector<std::vector<Line>> crossings(static_cast<std::size_t>(grid.rows));
    tbb::parallel_for(0, grid.rows, [&](int r) {
      if (request.deadline && request.deadline->passed()) throw DeadlinePassed();
      for (int c = 0; c < grid.columns; ++c) {
        const std::size_t cell = static_cast<std::size_t>(r) * grid.columns + c;
        for (std::uint32_t i = grid.start[cell]; i < grid.start[cell + 1]; ++i)
          for (std::uint32_t j = i + 1; j < grid.start[cell + 1]; ++j) {
            const Occluder &s = occ[grid.items[i]], &t = occ[grid.items[j]];
            if (s.id == t.id || s.zmin >= t.zmax || t.zmin >= s.zmax) continue;
            if (s.xmin >= t.xmax || t.xmin >= s.xmax || s.ymin >= t.ymax || t.ymin >= s.ymax)
              continue;
            // Each pair once: in the cell of its boxes' common corner
            if (grid.column(std::max(s.xmin, t.xmin)) != c ||
                grid.row(std::max(s.ymin, t.ymin)) != r)
              continue;
            if (s.object == t.object && shareCorner(s, t)) continue;
            Line line;
            if (!crosses(s, t, line.a, line.b)) continue;
            line.face = s.id, line.other = t.id, line.kind = 2;
            crossings[static_cast<std::size_t>(r)].push_back(line);
          }
      }
    });
    for (const std::vector<Line>& row : crossings)
      lines.insert(lines.end(), row.begin(), row.end());
  }
  out.line_edges = lines.size();
  // Lines near each other on screen try the same triangles: in the order of the cells their
  // first ends fall in, the triangles stay in the cache (edges come in the order their pairs were
  // found, intersection lines by rows).
  {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> order(lines.size());
    for (std::uint32_t i = 0; i < lines.size(); ++i)
      order[i] = {static_cast<std::uint32_t>(grid.row(lines[i].a.y) * grid.columns +
                                             grid.column(lines[i].a.x)),
                  i};
    std::sort(order.begin(), order.end());
    std::vector<Line> sorted(lines.size());
    for (std::size_t i = 0; i < order.size(); ++i) sorted[i] = lines[order[i].second];
    lines.swap(sorted);
  }
  lap("intersections");

  // ---- 4. Hiding, in chunks of lines (the same pieces in the same order for any thread count)
  constexpr std::size_t kChunk = 512;
  const std::size_t chunks = (lines.size() + kChunk - 1) / kChunk;
  std::vector<Pieces> pieces(chunks);
  tbb::enumerable_thread_specific<Scratch> scratch([&] {
    Scratch s;
    s.stamp.assign(occ.size(), 0);
    return s;
  });
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t ch) {
    if (request.deadline && request.deadline->passed()) throw DeadlinePassed();
    Scratch& s = scratch.local();
    Pieces& p = pieces[ch];
    std::vector<LinePiece>* v3 = request.keep_pieces ? &p.visible3 : nullptr;
    std::vector<LinePiece>* h3 = request.keep_pieces ? &p.hidden3 : nullptr;
    for (std::size_t i = ch * kChunk, end = std::min(lines.size(), i + kChunk); i < end; ++i) {
      const Line& line = lines[i];
      if (line.hidden_whole) {
        addPiece(p.hidden, h3, line, 0, 1);
        continue;
      }
      hide(line, static_cast<std::uint32_t>(i + 1), occ, grid, s, p.tests);
      double from = 0;
      for (const auto& [h0, h1] : s.hidden) {
        if (h0 > from && addPiece(p.visible, v3, line, from, h0)) p.counts[line.kind]++;
        if (request.hidden) addPiece(p.hidden, h3, line, std::max(h0, 0.0), std::min(h1, 1.0));
        from = std::max(from, h1);
      }
      if (from < 1 && addPiece(p.visible, v3, line, from, 1)) p.counts[line.kind]++;
    }
  });
  for (Pieces& p : pieces) {
    out.visible.insert(out.visible.end(), p.visible.begin(), p.visible.end());
    out.hidden.insert(out.hidden.end(), p.hidden.begin(), p.hidden.end());
    out.visible_pieces.insert(out.visible_pieces.end(), p.visible3.begin(), p.visible3.end());
    out.hidden_pieces.insert(out.hidden_pieces.end(), p.hidden3.begin(), p.hidden3.end());
    for (int k = 0; k < 3; ++k) out.pieces[k] += p.counts[k];
    out.occluder_tests += p.tests;
  }
  lap("hide");
  return out;
}

}  // namespace hsr::detail
