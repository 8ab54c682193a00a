// Roberts' algorithm (Roberts 1963; the notes' "Roberts Algorithm"): for scenes of convex
// polyhedra, the visible parts of every edge, decided in object space.
//
//   1. Solids. Find the convex polyhedra among the scene's objects; every other object is
//      decomposed into its faces, each a flat convex solid of its own (hsr/roberts.hpp says
//      exactly when, and the result says which objects and why).
//   2. Back faces. Remove each solid's faces whose outward normal points away from the eye
//      (the notes' test, N . (eye - P) > 0 for a front face, made after the perspective
//      transformation as the pipeline's facing is: the face's snapped outline turns
//      counter-clockwise seen from the eye). A convex solid's back faces are hidden by its own
//      front faces, so they need no further test. So are those of any closed object the view
//      does not cut (the eye is then outside it), which go too; its other faces are then
//      taken one by one.
//   3. Edges. Test each edge of the remaining faces against the volume of every other solid.
//      A point P of the edge is hidden by a solid V when the line of sight from P to the eye
//      passes through V: P - a z lies in V for some a > 0. Here the test runs in window space,
//      after the perspective transformation, as Roberts' does: the eye is then at infinity
//      towards -z and every line of sight is parallel to z. The points of a face's plane that
//      V hides are the section of V's shadow (V + a z, a >= 0) by that plane: a convex polygon,
//      whose corners are where V's edges, and the lines of sight through V's vertices, meet
//      the plane. An edge of the face is hidden where it runs inside one of its face's
//      sections; what no section covers is kept, as visible segments.
//   4. Junction lines. Where a face of one object passes through a face of another, the line
//      they meet on is an edge too (Roberts' junction lines): found for each such pair and
//      tested as in step 3.
//   5. Faces, for the picture. What is left of each face once its sections are removed is its
//      visible part, filled through the shared routine (paintExactRegion). Sections are
//      snapped to the sub-pixel grid to be removed exactly; where that rounding leaves a sliver
//      (within a grid unit of a junction line), the depth test settles the pixel.
//
// Every face is the pipeline's clipped window-space polygon (pipeline/pipeline.hpp,
// WindowPolygon) with its x and y snapped to the grid, as its screen triangles are; depth is
// scaled to the same size (zs grid units for the whole depth range) so that lengths along
// every axis compare. See-through polygons hide nothing: they are blended afterwards with the
// depth test, as the z-buffer draws them.
// Guarantee: every visible segment lies on an edge (or junction line) of the Weiler-Atherton
// visible set and every such edge on a segment, within 1e-6 of the view's size where no faces
// cross and within two grid units along crossing lines; each pixel shows what the z-buffer
// shows with back faces culled, except within a grid unit of a junction line, where the depth
// test settles it as the z-buffer does.
// The steps are RobertsRun's member functions, called in this order by RobertsRun::run().
// Cost: for each face, the volumes whose screen boxes overlap it and that come nearer than it,
// found through a grid of screen cells; each test is O(v) for a volume of v vertices and
// edges, and each face's region one Boolean operation per section.
// Tests: tests/visibility/roberts_test.cpp and every suite of the registry its capabilities join.

#include "hsr/roberts.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/frame.hpp"
#include "core/stopwatch.hpp"
#include "geometry/polygon.hpp"
#include "geometry/triangulate.hpp"
#include "hsr/clipping.hpp"
#include "hsr/error.hpp"
#include "raster/fill_polygons.hpp"
#include "raster/lines.hpp"
#include "visibility/algorithm.hpp"
#include "visibility/roberts.hpp"

namespace hsr::detail {
namespace {

using glm::dvec2;
using glm::dvec3;

constexpr double kGrid = kSubpixelOne;  // grid units per pixel
// A point must lie this far (grid units) inside a section to be hidden: an edge that only
// touches a volume, as the edges two faces share, is not hidden by it.
constexpr double kInside = 1e-6;
// Sections and segments smaller than this (grid units, and grid units squared) are nothing.
constexpr double kTiny = 1e-6;
// An object is convex when no vertex lies more than this times its size outside a face's plane.
constexpr double kConvexTolerance = 1e-6;

// ---------------------------------------------------------------------------------------
// 1. Solids

// Why the object is not a convex polyhedron, or empty when it is; `outward` gets +1 when its
// faces wind counter-clockwise seen from outside, -1 when from inside.
// `closed`, when the object is closed (whatever else it is), gets +1 when its faces wind
// counter-clockwise seen from outside (positive volume), -1 when from inside.
std::string notConvexReason(const Scene& scene, const Object& object, int* outward, int* closed) {
  const PolygonId first = object.first_polygon, end = object.first_polygon + object.polygon_count;
  if (object.polygon_count < 4) return "open: fewer than four faces";
  const double tol =
      kConvexTolerance * std::max(2.0 * static_cast<double>(object.bounds.radius()), 1e-30);
  auto pos = [&](std::uint32_t v) { return dvec3(scene.position(v)); };
  // Closed: each directed edge once, and its reverse once.
  using Key = std::array<float, 6>;
  std::map<Key, int> directed;
  for (PolygonId id = first; id < end; ++id) {
    const auto vi = scene.polygon(id);
    for (std::size_t i = 0; i < vi.size(); ++i) {
      const glm::vec3 a = scene.position(vi[i]), b = scene.position(vi[(i + 1) % vi.size()]);
      if (++directed[{a.x, a.y, a.z, b.x, b.y, b.z}] > 1)
        return "an edge is shared by more than two faces";
    }
  }
  for (const auto& [k, n] : directed)
    if (!directed.contains({k[3], k[4], k[5], k[0], k[1], k[2]}))
      return "open: an edge has no neighbour";
  {
    const dvec3 c(object.bounds.center());
    double volume6 = 0;  // six times the signed volume
    for (PolygonId id = first; id < end; ++id) {
      const auto vi = scene.polygon(id);
      for (std::size_t i = 1; i + 1 < vi.size(); ++i)
        volume6 += glm::dot(pos(vi[0]) - c, glm::cross(pos(vi[i]) - c, pos(vi[i + 1]) - c));
    }
    if (volume6 != 0) *closed = volume6 > 0 ? 1 : -1;
  }
  // Flat, convex faces, with the whole object on one side of each: the same side for all.
  std::vector<std::uint32_t> vertices;
  for (PolygonId id = first; id < end; ++id)
    for (std::uint32_t v : scene.polygon(id)) vertices.push_back(v);
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  // Every vertex against every face when that is cheap; a large mesh (a fine sphere) is checked
  // against each face's own vertices and its neighbours' (convex at every edge) and against 64
  // faces spread over the mesh for the whole object.
  const bool whole = static_cast<double>(vertices.size()) * object.polygon_count <= 4e6;
  const PolygonId stride = whole ? 1 : std::max<PolygonId>(1, object.polygon_count / 64);
  std::map<std::array<float, 3>, std::vector<PolygonId>> faces_at;  // for the neighbours
  if (!whole)
    for (PolygonId id = first; id < end; ++id)
      for (std::uint32_t v : scene.polygon(id)) {
        const glm::vec3 p = scene.position(v);
        faces_at[{p.x, p.y, p.z}].push_back(id);
      }
  int side = 0;
  for (PolygonId id = first; id < end; ++id) {
    const auto vi = scene.polygon(id);
    dvec3 n = newellNormal(vi.size(), [&](std::size_t i) { return pos(vi[i]); });
    const double len = glm::length(n);
    if (!(len > 0)) return "polygon " + std::to_string(id) + " has no area";
    n /= len;
    const dvec3 c = pos(vi[0]);
    for (std::uint32_t v : vi)
      if (std::abs(glm::dot(n, pos(v) - c)) > tol)
        return "polygon " + std::to_string(id) + " is not flat";
    for (std::size_t i = 0; i < vi.size(); ++i) {
      const dvec3 a = pos(vi[i]), b = pos(vi[(i + 1) % vi.size()]),
                  d = pos(vi[(i + 2) % vi.size()]);
      if (glm::dot(glm::cross(b - a, d - b), n) < -tol * glm::length(d - b))
        return "polygon " + std::to_string(id) + " is not convex";
    }
    auto check = [&](std::uint32_t v) {
      const double s = glm::dot(n, pos(v) - c);
      const int here = s > tol ? 1 : s < -tol ? -1 : 0;
      if (here == 0) return true;
      if (side == 0) side = here;
      return here == side;
    };
    if (whole || (id - first) % stride == 0) {
      for (std::uint32_t v : vertices)
        if (!check(v))
          return "not convex: a vertex lies outside the plane of polygon " + std::to_string(id);
    } else {
      for (std::uint32_t v : vi) {
        const glm::vec3 p = scene.position(v);
        for (PolygonId nb : faces_at[{p.x, p.y, p.z}])
          for (std::uint32_t w : scene.polygon(nb))
            if (!check(w)) return "not convex at an edge of polygon " + std::to_string(id);
      }
    }
  }
  if (side == 0) return "flat: no volume";
  *outward = -side;  // the object on the negative side of counter-clockwise normals: outward
  return {};
}

// ---------------------------------------------------------------------------------------
// What the steps work on

struct Face {
  const WindowPolygon* w = nullptr;
  std::vector<dvec3> v;  // corners: x, y on the grid, depth scaled
  GridRing ring;
  std::vector<std::vector<dvec2>> pieces;  // convex pieces: the face, or a concave one's triangles
  std::uint32_t object = 0;
  int solid = -1;  // the solid it belongs to, or -1 when decomposed
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0, zmin = 0, zmax = 0;
};

// A convex volume: a whole solid (its front faces' corners, which bound its shadow), or one
// convex piece of a face of a decomposed object.
struct Volume {
  std::vector<dvec3> vertices;
  std::vector<dvec2> outline;  // convex hull of the vertices on the picture
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  std::vector<std::uint32_t> faces;  // the faces it is made of
  std::uint32_t object = 0;
  int solid = -1, face = -1;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0, zmin = 0, zmax = 0;
};

struct Section {
  std::vector<dvec2> hull;   // counter-clockwise (positive shoelace area)
  std::vector<dvec2> shown;  // what the picture removes (see section()'s use); may be empty
  std::uint32_t volume = 0;
  double area = 0, x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // the hull's
};

double cross(dvec2 a, dvec2 b) { return a.x * b.y - a.y * b.x; }

// Andrew's monotone chain; counter-clockwise, collinear points dropped. `p` is reordered.
void convexHull(std::vector<dvec2>& p, std::vector<dvec2>& h) {
  std::sort(p.begin(), p.end(),
            [](dvec2 a, dvec2 b) { return a.x != b.x ? a.x < b.x : a.y < b.y; });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  h.clear();
  if (p.size() < 3) return;
  h.resize(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 1] - h[k - 2], p[i] - h[k - 2]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(h[k - 1] - h[k - 2], p[i] - h[k - 2]) <= 0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);
}

double hullArea(const std::vector<dvec2>& h) {
  double a = 0;
  for (std::size_t i = 0; i < h.size(); ++i) a += cross(h[i], h[(i + 1) % h.size()]);
  return a / 2;
}

struct Scaled {
  double zs = 1;  // grid units for the whole depth range
  // A face's plane: scaled depth at grid point (x, y).
  double depth(const DepthPlane& p, double x, double y) const {
    return zs * ((p.z0 + p.dzdy * (y / kGrid)) + p.dzdx * (x / kGrid));
  }
};

// Step 3's section of face f's plane by volume v's shadow, by the plane moved `lift` towards
// the eye: false when v hides none of it (wholly behind the plane, or meeting it in a line).
bool section(const Face& f, const Volume& v, const Scaled& sc, double lift, std::vector<double>& s,
             std::vector<dvec2>& hull) {
  const DepthPlane& p = f.w->depth;
  // The plane over the volume's box: wholly behind it, nothing; wholly in front, the
  // section is the volume's outline.
  double lo = INFINITY, hi = -INFINITY;
  for (const double x : {v.x0, v.x1})
    for (const double y : {v.y0, v.y1}) {
      const double z = sc.depth(p, x, y) - lift;
      lo = std::min(lo, z), hi = std::max(hi, z);
    }
  if (v.zmin >= hi) return false;
  if (v.zmax < lo) {
    hull = v.outline;
    return hull.size() >= 3 && hullArea(hull) > kTiny;
  }
  s.resize(v.vertices.size());
  bool any_in_front = false;
  for (std::size_t i = 0; i < v.vertices.size(); ++i) {
    const dvec3& q = v.vertices[i];
    s[i] = q.z - sc.depth(p, q.x, q.y) + lift;  // > 0: behind the plane
    any_in_front = any_in_front || s[i] < 0;
  }
  if (!any_in_front) return false;
  thread_local std::vector<dvec2> pts;
  pts.clear();
  for (std::size_t i = 0; i < v.vertices.size(); ++i)
    if (s[i] <= 0)
      pts.emplace_back(v.vertices[i].x, v.vertices[i].y);  // its line of sight meets the plane
  for (const auto& [a, b] : v.edges)
    if ((s[a] < 0 && s[b] > 0) || (s[a] > 0 && s[b] < 0)) {  // the edge crosses the plane
      const double t = s[a] / (s[a] - s[b]);
      const dvec3 q = v.vertices[a] + (v.vertices[b] - v.vertices[a]) * t;
      pts.emplace_back(q.x, q.y);
    }
  convexHull(pts, hull);
  return hull.size() >= 3 && hullArea(hull) > kTiny;
}

// The stretch [t0, t1] of segment a->b strictly inside the convex polygon (kInside in).
bool insideStretch(dvec2 a, dvec2 b, const std::vector<dvec2>& hull, double* t0, double* t1) {
  double lo = 0, hi = 1;
  const dvec2 d = b - a;
  for (std::size_t i = 0; i < hull.size() && lo < hi; ++i) {
    const dvec2 p = hull[i], e = hull[(i + 1) % hull.size()] - p;
    const double c0 = cross(e, a - p), c1 = cross(e, d), m = kInside * glm::length(e);
    // inside: c0 + c1 t > m
    if (c1 == 0) {
      if (c0 <= m) return false;
    } else if (c1 > 0) {
      lo = std::max(lo, (m - c0) / c1);
    } else {
      hi = std::min(hi, (m - c0) / c1);
    }
  }
  if (!(hi - lo > 0)) return false;
  *t0 = lo, *t1 = hi;
  return true;
}

// The stretch of the line p + u d (all u) within the convex polygon, edges included.
bool lineInConvex(dvec2 p, dvec2 d, const std::vector<dvec2>& poly, double* u0, double* u1) {
  // Orientation of the piece: make the test sign-independent.
  const double orient = hullArea(poly) > 0 ? 1.0 : -1.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const dvec2 q = poly[i], e = poly[(i + 1) % poly.size()] - q;
    const double c0 = orient * cross(e, p - q), c1 = orient * cross(e, d);
    if (c1 == 0) {
      if (c0 < 0) return false;
    } else if (c1 > 0) {
      *u0 = std::max(*u0, -c0 / c1);
    } else {
      *u1 = std::min(*u1, -c0 / c1);
    }
  }
  return *u1 > *u0;
}

// Screen cells holding the volumes whose boxes reach them.
class Cells {
 public:
  Cells(const std::vector<Volume>& vols, int width, int height) {
    const double n = std::max<double>(1.0, static_cast<double>(vols.size()));
    side_ = std::max(8.0, std::sqrt(static_cast<double>(width) * height / n) * 2) * kGrid;
    cols_ = std::max(1, static_cast<int>(std::ceil(width * kGrid / side_)) + 1);
    rows_ = std::max(1, static_cast<int>(std::ceil(height * kGrid / side_)) + 1);
    cells_.resize(static_cast<std::size_t>(cols_) * rows_);
    for (std::uint32_t i = 0; i < vols.size(); ++i)
      forCells(vols[i].x0, vols[i].y0, vols[i].x1, vols[i].y1,
               [&](std::vector<std::uint32_t>& c) { c.push_back(i); });
  }
  template <class Fn>
  void forCells(double x0, double y0, double x1, double y1, Fn&& fn) {
    for (int r = row(y0); r <= row(y1); ++r)
      for (int c = col(x0); c <= col(x1); ++c) fn(cells_[static_cast<std::size_t>(r) * cols_ + c]);
  }

 private:
  int col(double x) const {
    return std::clamp(static_cast<int>(std::floor((x + kGrid) / side_)), 0, cols_ - 1);
  }
  int row(double y) const {
    return std::clamp(static_cast<int>(std::floor((y + kGrid) / side_)), 0, rows_ - 1);
  }
  double side_ = 1;
  int cols_ = 1, rows_ = 1;
  std::vector<std::vector<std::uint32_t>> cells_;
};

template <class T>
void boxOf(T& t, const std::vector<dvec3>& pts) {
  t.x0 = t.y0 = t.zmin = INFINITY;
  t.x1 = t.y1 = t.zmax = -INFINITY;
  for (const dvec3& q : pts) {
    t.x0 = std::min(t.x0, q.x), t.x1 = std::max(t.x1, q.x);
    t.y0 = std::min(t.y0, q.y), t.y1 = std::max(t.y1, q.y);
    t.zmin = std::min(t.zmin, q.z), t.zmax = std::max(t.zmax, q.z);
  }
}

bool ringConvex(const std::vector<dvec2>& p) {
  int turns = 0;
  for (std::size_t i = 0, n = p.size(); i < n; ++i) {
    const double t = cross(p[(i + 1) % n] - p[i], p[(i + 2) % n] - p[(i + 1) % n]);
    const int sign = (t > 0) - (t < 0);
    if (sign != 0 && turns != 0 && sign != turns) return false;
    if (sign != 0) turns = sign;
  }
  return turns != 0;
}

// The section snapped to the grid from inside: each corner off the grid moved to a grid point
// within the section (dropped when none of the four around it is), so that what is removed is
// never more than the section. What rounding leaves of a hidden face (within a grid unit of
// the section's border) is then painted under the depth test, which settles it as the
// z-buffer would; removing too much would leave a hole.
GridRing snappedInside(const std::vector<dvec2>& hull) {
  auto inside = [&](double x, double y) {
    for (std::size_t i = 0; i < hull.size(); ++i)
      if (cross(hull[(i + 1) % hull.size()] - hull[i], dvec2(x, y) - hull[i]) < 0) return false;
    return true;
  };
  std::vector<dvec2> pts;
  for (const dvec2& q : hull) {
    if (q.x == std::floor(q.x) && q.y == std::floor(q.y)) {
      pts.push_back(q);
      continue;
    }
    for (const double x : {std::floor(q.x), std::ceil(q.x)})
      for (const double y : {std::floor(q.y), std::ceil(q.y)})
        if (inside(x, y)) pts.emplace_back(x, y);
  }
  std::vector<dvec2> h;
  convexHull(pts, h);
  GridRing ring;
  for (const dvec2& q : h)
    ring.push_back({static_cast<std::int64_t>(q.x), static_cast<std::int64_t>(q.y)});
  return ring;
}

bool shareCorner(const Face& f, const Face& g) {
  for (const GridPoint& p : f.ring)
    if (std::find(g.ring.begin(), g.ring.end(), p) != g.ring.end()) return true;
  return false;
}

TraceOutline outlineOf(const std::vector<dvec2>& ring) {
  TraceOutline o;
  for (const dvec2& q : ring)
    o.emplace_back(static_cast<float>(q.x / kGrid), static_cast<float>(q.y / kGrid));
  return o;
}

constexpr std::string_view kStepSolids = "solids";
constexpr std::string_view kStepBackFaces = "back faces";
constexpr std::string_view kStepFace = "face";
constexpr std::string_view kStepDone = "done";

// One run of Roberts' algorithm over the pipeline's window polygons: what its steps share, and
// the steps as member functions in the notes' order (run() reads as the list at the top of
// this file).
class RobertsRun {
 public:
  RobertsRun(const Scene& scene, const std::vector<WindowPolygon>& polygons, int width, int height,
             Frame* frame, Trace* trace, bool hidden_parts, const Deadline* deadline)
      : scene_(scene),
        polygons_(polygons),
        frame_(frame),
        trace_(trace && frame ? trace : nullptr),
        hidden_parts_(hidden_parts),
        deadline_(deadline),
        xmax_(width - 0.5),
        ymax_(height - 0.5) {
    out_.width = width, out_.height = height;
    sc_.zs = kGrid * std::max(width, height);
  }

  RobertsDrawing run() {
    findSolids();       // 1.
    removeBackFaces();  // 2., keeping the faces and volumes the tests use
    makeVolumes();
    traceSolidsAndBackFaces();
    sectionFaces();  // 3. the sections of each face's plane by the volumes in front
    listEdges();
    findJunctionLines();  // 4.
    // 3. (the edges) and 5., face by face in id order (the z-buffer's order among equal
    // depths): the visible segments of the face's edges and junction lines, then what the
    // sections leave of the face, filled through the shared routine.
    std::vector<std::uint32_t> by_id(faces_.size());
    for (std::uint32_t i = 0; i < faces_.size(); ++i) by_id[i] = i;
    std::stable_sort(by_id.begin(), by_id.end(), [&](std::uint32_t l, std::uint32_t r) {
      return faces_[l].w->id < faces_[r].w->id;
    });
    if (frame_) fb_.emplace(*frame_);
    std::uint64_t step = 0;
    for (std::uint32_t fi : by_id) {
      checkDeadline(deadline_, checked_++);
      const bool show = trace_ && trace_->wants(kStepFace, step++, faces_.size());
      if (hidden_whole_[fi]) {
        hideFace(fi, show);
        continue;
      }
      std::vector<TraceOutline> o;
      keepVisibleEdges(fi, show ? &o : nullptr);
      if (fb_) fillVisiblePart(fi, show, std::move(o));
    }
    // The edges only back faces share: hidden whole (their solid's front faces hide them)
    for (const auto& [key, ids] : back_edges_)
      addHidden({key[1], key[2]}, {key[4], key[5]}, ids.first, kNoPolygon, ids.second, false);
    if (frame_) {
      frame_->stats.fragments_tested += fragments_.tested;
      frame_->stats.fragments_written += fragments_.written;
    }
    return std::move(out_);
  }

 private:
  using EdgeKey = std::array<double, 7>;  // object, then the ends in order
  struct EdgeRef {
    std::uint32_t face;
    PolygonId other;
    PolygonId neighbour = kNoPolygon;  // the other polygon on the edge, visible or not
  };
  struct BackFace {  // kept for their edges when the hidden parts are asked for
    PolygonId id;
    std::uint32_t object;
    std::vector<dvec3> v;
  };
  struct Junction {
    dvec2 a, b;
    std::uint32_t g;
  };

  // ---- 1. Solids: which objects are convex polyhedra, and whole in the view.
  void findSolids() {
    const std::size_t n = scene_.objects.size();
    std::vector<std::vector<const WindowPolygon*>> by_object(n);
    for (const WindowPolygon& w : polygons_)
      if (!w.transparent) by_object[scene_.object(w.id)].push_back(&w);
    solid_of_.assign(n, -1), outward_of_.assign(n, 0);
    for (std::uint32_t o = 0; o < n; ++o) {
      if (by_object[o].empty()) continue;
      int outward = 0, closed = 0;
      std::string why = notConvexReason(scene_, scene_.objects[o], &outward, &closed);
      // Whole in the view: every face present once and untouched by the clipper. (A face that
      // is missing is culled, edge-on, or wholly outside the view: its neighbours would show the
      // cut. The solid's shadow in the view is that of the front faces there.)
      bool cut = false;
      std::vector<std::uint8_t> seen(scene_.objects[o].polygon_count, 0);
      for (const WindowPolygon* w : by_object[o]) {
        cut = cut || seen[w->id - scene_.objects[o].first_polygon]++ || w->piece != 0;
        for (const dvec3& q : w->vertices)
          cut = cut ||
                !(q.x > kMin && q.x < xmax_ && q.y > kMin && q.y < ymax_ && q.z > 0 && q.z < 1);
      }
      if (why.empty() && cut) why = "cut by the view volume";
      RobertsObject& ro = out_.objects.emplace_back();
      ro.object = o;
      ro.solid = why.empty();
      ro.reason = why;
      if (ro.solid) {
        solid_of_[o] = static_cast<int>(out_.solids++);
        outward_of_[o] = outward;
      } else if (closed != 0 && !cut) {
        // A closed object the view does not cut is seen from outside (an eye inside it would
        // have it cut by the view volume all round): its back faces are hidden by its own front
        // faces, convex or not, and go as a solid's do; the rest is taken face by face.
        outward_of_[o] = closed;
      }
    }
  }

  // ---- 2. Back faces: each face snapped to the grid, and dropped when its outward normal
  // points away from the eye; the others become the faces whose edges are tested, and the
  // volumes that test them (a solid's faces one volume, every other face a flat volume of
  // its own per convex piece).
  void removeBackFaces() {
    volumes_.resize(out_.solids);
    for (const WindowPolygon& w : polygons_) {
      if (w.transparent) continue;
      const std::uint32_t o = scene_.object(w.id);
      Face f;
      f.w = &w;
      f.object = o;
      f.solid = solid_of_[o];
      std::vector<dvec2> xy;
      for (const dvec3& q : w.vertices) {
        const GridPoint g{std::llrint(q.x * kGrid), std::llrint(q.y * kGrid)};
        if (!f.ring.empty() && (f.ring.back() == g)) continue;
        f.ring.push_back(g);
        f.v.emplace_back(static_cast<double>(g.x), static_cast<double>(g.y), q.z * sc_.zs);
        xy.emplace_back(static_cast<double>(g.x), static_cast<double>(g.y));
      }
      while (f.ring.size() > 1 && f.ring.front() == f.ring.back())
        f.ring.pop_back(), f.v.pop_back(), xy.pop_back();
      if (f.ring.size() < 3) continue;
      if (trace_) all_outlines_.push_back(outlineOf(xy));
      // The notes' test after the perspective transformation, as the pipeline's facing: the
      // outward normal points at the eye when the snapped outline turns counter-clockwise seen
      // from the eye (negative area with y down), for outward counter-clockwise windings.
      std::int64_t twice_area = 0;
      for (std::size_t i = 0; i < f.ring.size(); ++i) {
        const GridPoint p = f.ring[i], q = f.ring[(i + 1) % f.ring.size()];
        twice_area += p.x * q.y - q.x * p.y;
      }
      if (outward_of_[o] != 0 && (twice_area < 0 ? 1 : -1) * outward_of_[o] <= 0) {
        out_.back_faces++;  // its outward normal points away from the eye
        if (trace_) back_outlines_.push_back(outlineOf(xy));
        if (hidden_parts_) back_faces_.push_back({w.id, o, std::move(f.v)});
        continue;
      }
      boxOf(f, f.v);
      if (ringConvex(xy)) {
        f.pieces.push_back(xy);
      } else {
        std::vector<std::array<std::uint32_t, 3>> tris;
        triangulate2d(xy, tris);
        for (const auto& t : tris) f.pieces.push_back({xy[t[0]], xy[t[1]], xy[t[2]]});
      }
      addToVolumes(f, static_cast<std::uint32_t>(faces_.size()));
      faces_.push_back(std::move(f));
    }
  }

  void addToVolumes(const Face& f, std::uint32_t fi) {
    if (f.solid >= 0) {
      Volume& vol = volumes_[f.solid];
      const std::uint32_t base = static_cast<std::uint32_t>(vol.vertices.size());
      for (std::size_t i = 0; i < f.v.size(); ++i) {
        vol.vertices.push_back(f.v[i]);
        vol.edges.emplace_back(base + i, base + (i + 1) % f.v.size());
      }
      vol.faces.push_back(fi);
      vol.object = f.object, vol.solid = f.solid;
      return;
    }
    // Each piece of a flat face takes its corners' depths from the face's plane (the same
    // plane its section tests use): a triangle of a concave face then lies exactly in it.
    for (const std::vector<dvec2>& piece : f.pieces) {
      Volume& vol = volumes_.emplace_back();
      for (const dvec2& q : piece)
        vol.vertices.emplace_back(q.x, q.y, sc_.depth(f.w->depth, q.x, q.y));
      for (std::uint32_t i = 0; i < piece.size(); ++i)
        vol.edges.emplace_back(i, (i + 1) % piece.size());
      vol.faces.push_back(fi);
      vol.object = f.object, vol.face = static_cast<int>(fi);
    }
  }

  // The volumes finished: a solid lists each corner once and each edge once (its faces share
  // them); each volume's box and screen outline.
  void makeVolumes() {
    const auto less = [](const dvec3& l, const dvec3& r) {
      return std::tie(l.x, l.y, l.z) < std::tie(r.x, r.y, r.z);
    };
    for (Volume& v : volumes_) {
      if (v.solid >= 0) {
        std::vector<dvec3> corners = v.vertices;
        std::sort(corners.begin(), corners.end(), less);
        corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
        auto index = [&](const dvec3& q) {
          return static_cast<std::uint32_t>(
              std::lower_bound(corners.begin(), corners.end(), q, less) - corners.begin());
        };
        for (auto& [a, b] : v.edges) {
          std::uint32_t ia = index(v.vertices[a]), ib = index(v.vertices[b]);
          a = std::min(ia, ib), b = std::max(ia, ib);
        }
        std::sort(v.edges.begin(), v.edges.end());
        v.edges.erase(std::unique(v.edges.begin(), v.edges.end()), v.edges.end());
        v.vertices = std::move(corners);
      }
      boxOf(v, v.vertices);
      std::vector<dvec2> xy;
      for (const dvec3& q : v.vertices) xy.emplace_back(q.x, q.y);
      convexHull(xy, v.outline);
    }
    std::erase_if(volumes_, [](const Volume& v) { return v.vertices.empty(); });
    out_.faces = faces_.size();
    out_.volumes = volumes_.size();
  }

  void traceSolidsAndBackFaces() {
    if (trace_ && trace_->wants(kStepSolids, 0, 1)) {
      std::string caption = "Solids: " + std::to_string(out_.solids) + " of the " +
                            std::to_string(out_.objects.size()) +
                            " objects in view are convex polyhedra";
      for (const RobertsObject& ro : out_.objects)
        if (!ro.solid)
          caption += "; \"" + scene_.objects[ro.object].name + "\" is taken face by face (" +
                     ro.reason + ")";
      trace_->record({kStepSolids, caption + ".", frame_, std::move(all_outlines_)});
    }
    if (trace_ && trace_->wants(kStepBackFaces, 0, 1))
      trace_->record(
          {kStepBackFaces,
           "Remove the back faces of each solid (outlined: " + std::to_string(out_.back_faces) +
               "), whose outward normal points away from the eye: the solid's own front faces hide "
               "them.",
           frame_, back_outlines_});
  }

  // ---- 3. Sections of each face's plane by the volumes that may hide some of it, found
  // through a grid of screen cells; the largest first.
  void sectionFaces() {
    Cells cells(volumes_, out_.width, out_.height);
    sections_.resize(faces_.size());
    hidden_whole_.assign(faces_.size(), 0);
    std::vector<std::uint32_t> seen(volumes_.size(), 0);
    std::uint32_t stamp = 0;
    std::vector<double> s;
    for (std::uint32_t fi = 0; fi < faces_.size(); ++fi) {
      checkDeadline(deadline_, fi);
      const Face& f = faces_[fi];
      ++stamp;
      cells.forCells(f.x0, f.y0, f.x1, f.y1, [&](const std::vector<std::uint32_t>& cell) {
        for (std::uint32_t vi : cell) {
          if (hidden_whole_[fi]) return;
          if (seen[vi] == stamp) continue;
          seen[vi] = stamp;
          const Volume& v = volumes_[vi];
          if ((v.solid >= 0 && v.solid == f.solid) || v.face == static_cast<int>(fi))
            continue;  // its own solid
          if (v.x1 <= f.x0 || v.x0 >= f.x1 || v.y1 <= f.y0 || v.y0 >= f.y1 || v.zmin >= f.zmax)
            continue;
          out_.tests++;
          Section sec;
          sec.volume = vi;
          if (!section(f, v, sc_, 0.0, s, sec.hull)) continue;
          // For the picture, what lies within a grid unit's change of depth of the plane (or
          // its rounding) does not count as in front: the section by the plane moved that much
          // towards the eye is never more than what the volume hides, and what it leaves (where
          // the two are as good as equal in depth) goes to the depth test, as in the z-buffer.
          const DepthPlane& p = f.w->depth;
          const double lift =
              sc_.zs * 1e-12 + sc_.zs * (std::abs(p.dzdx) + std::abs(p.dzdy)) / kGrid;
          section(f, v, sc_, lift, s, sec.shown);
          // A face that one section covers with room to spare (its corners inside the section
          // taken for the picture) is hidden whole: nothing more is asked of it.
          if (covers(sec.shown, f.ring)) {
            hidden_whole_[fi] = 1;
            sections_[fi].clear();
            return;
          }
          sec.area = hullArea(sec.hull);
          sec.x0 = sec.y0 = INFINITY, sec.x1 = sec.y1 = -INFINITY;
          for (const dvec2& q : sec.hull)
            sec.x0 = std::min(sec.x0, q.x), sec.x1 = std::max(sec.x1, q.x),
            sec.y0 = std::min(sec.y0, q.y), sec.y1 = std::max(sec.y1, q.y);
          sections_[fi].push_back(std::move(sec));
        }
      });
      std::stable_sort(sections_[fi].begin(), sections_[fi].end(),
                       [](const Section& l, const Section& r) { return l.area > r.area; });
    }
  }

  static bool covers(const std::vector<dvec2>& hull, const GridRing& ring) {
    if (hull.size() < 3) return false;
    for (const GridPoint& g : ring)
      for (std::size_t i = 0; i < hull.size(); ++i)
        if (cross(hull[(i + 1) % hull.size()] - hull[i], dvec2(g.x, g.y) - hull[i]) <= 0)
          return false;
    return true;
  }

  // The edges of polygon vertices `v` of `object`, each as its key, those along the view's
  // border left out (the clipper's cut, not an edge).
  template <class F>
  void forEdges(std::uint32_t object, const std::vector<dvec3>& v, F&& f) const {
    const double bx0 = kMin * kGrid, bx1 = xmax_ * kGrid, by0 = kMin * kGrid, by1 = ymax_ * kGrid;
    auto near = [](double u, double w) { return std::abs(u - w) <= 1.0; };
    auto onBorder = [&](dvec2 a, dvec2 b) {
      return (near(a.x, bx0) && near(b.x, bx0)) || (near(a.x, bx1) && near(b.x, bx1)) ||
             (near(a.y, by0) && near(b.y, by0)) || (near(a.y, by1) && near(b.y, by1));
    };
    for (std::size_t i = 0; i < v.size(); ++i) {
      dvec3 a = v[i], b = v[(i + 1) % v.size()];
      if (onBorder({a.x, a.y}, {b.x, b.y})) continue;
      if (std::tie(b.x, b.y, b.z) < std::tie(a.x, a.y, a.z)) std::swap(a, b);
      f(EdgeKey{static_cast<double>(object), a.x, a.y, a.z, b.x, b.y, b.z});
    }
  }

  // The edges, each once (two faces of one object that share it give one segment with both
  // ids), listed by the face that tests them; and the back faces' edges: a silhouette's
  // neighbour, or hidden whole (once each).
  void listEdges() {
    std::map<EdgeKey, EdgeRef> edges;
    for (std::uint32_t fi = 0; fi < faces_.size(); ++fi) {
      checkDeadline(deadline_, fi);
      const Face& f = faces_[fi];
      forEdges(f.object, f.v, [&](const EdgeKey& key) {
        auto [it, inserted] = edges.try_emplace(key, EdgeRef{fi, kNoPolygon});
        if (inserted || it->second.neighbour != kNoPolygon) return;
        it->second.neighbour = f.w->id;
        if (faces_[it->second.face].w->id != f.w->id) it->second.other = f.w->id;
      });
    }
    for (const BackFace& bf : back_faces_)
      forEdges(bf.object, bf.v, [&](const EdgeKey& key) {
        if (auto it = edges.find(key); it != edges.end()) {
          if (it->second.neighbour == kNoPolygon) it->second.neighbour = bf.id;
          return;
        }
        auto [it, inserted] = back_edges_.try_emplace(key, bf.id, kNoPolygon);
        if (!inserted && it->second.second == kNoPolygon) it->second.second = bf.id;
      });
    edges_of_.resize(faces_.size());
    for (const auto& [key, ref] : edges) edges_of_[ref.face].emplace_back(key, ref);
  }

  // ---- 4. Junction lines: face f of one object through face g of another, or through a face
  // of its own object that it shares no corner with (neighbours in a mesh meet on an edge).
  // Faces that cross each have a section by the other's volume (each comes in front of the
  // other's plane), so the pairs are found among the sections; each is taken once.
  void findJunctionLines() {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (std::uint32_t fi = 0; fi < faces_.size(); ++fi)
      for (const Section& sec : sections_[fi])
        for (std::uint32_t gi : volumes_[sec.volume].faces)
          if (!hidden_whole_[gi] &&
              (faces_[gi].object != faces_[fi].object || !shareCorner(faces_[fi], faces_[gi])))
            pairs.emplace_back(std::min(fi, gi), std::max(fi, gi));
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    junctions_.resize(faces_.size());
    for (const auto& [fi, gi] : pairs) {
      checkDeadline(deadline_, checked_++);
      const Face &f = faces_[fi], &g = faces_[gi];
      // Where the planes meet: depth(f) - depth(g) = 0, a line in x, y (grid units).
      const DepthPlane &pf = f.w->depth, &pg = g.w->depth;
      const double A = (pf.dzdx - pg.dzdx) / kGrid, B = (pf.dzdy - pg.dzdy) / kGrid,
                   C = pf.z0 - pg.z0;
      const double norm = std::hypot(A, B);
      if (!(norm > 0) || !std::isfinite(norm)) continue;  // parallel planes
      const dvec2 p0(-A * C / (norm * norm), -B * C / (norm * norm)), d(-B / norm, A / norm);
      for (const std::vector<dvec2>& fp : f.pieces)
        for (const std::vector<dvec2>& gp : g.pieces) {
          double u0 = -INFINITY, u1 = INFINITY;
          if (!lineInConvex(p0, d, fp, &u0, &u1) || !lineInConvex(p0, d, gp, &u0, &u1)) continue;
          if (u1 - u0 <= kTiny) continue;
          out_.junctions++;
          junctions_[fi].push_back({p0 + d * u0, p0 + d * u1, gi});
        }
    }
  }

  // ---- 3. (the edges) A face that one section hides whole: its edges and junction lines all
  // hidden.
  void hideFace(std::uint32_t fi, bool show) {
    const Face& f = faces_[fi];
    out_.edges += edges_of_[fi].size();
    if (hidden_parts_) {
      for (const auto& [key, ref] : edges_of_[fi])
        addHidden({key[1], key[2]}, {key[4], key[5]}, f.w->id, ref.other, ref.neighbour, false);
      for (const Junction& j : junctions_[fi])
        addHidden(j.a, j.b, f.w->id, faces_[j.g].w->id, kNoPolygon, true);
    }
    if (show)
      trace_->record(
          {kStepFace,
           "Face " + std::to_string(f.w->id) +
               " lies wholly inside the section of a volume in front of it: hidden, edges and all.",
           frame_,
           {}});
  }

  // ---- 3. (the edges) The visible segments of a face's edges and junction lines: what no
  // section of its plane covers (outlined into `o` when given).
  void keepVisibleEdges(std::uint32_t fi, std::vector<TraceOutline>* o) {
    for (const auto& [key, ref] : edges_of_[fi])
      addVisible({key[1], key[2]}, {key[4], key[5]}, fi, ref.other, ref.neighbour, -1, o);
    for (const Junction& j : junctions_[fi])
      addVisible(j.a, j.b, fi, faces_[j.g].w->id, kNoPolygon, static_cast<int>(j.g), o);
  }

  void addHidden(dvec2 a, dvec2 b, PolygonId face, PolygonId other, PolygonId neighbour,
                 bool junction) {
    out_.hidden.push_back(
        {a.x / kGrid, a.y / kGrid, b.x / kGrid, b.y / kGrid, face, other, junction, neighbour});
  }

  // Segment ab of face fi: the stretches the sections hide taken out, the rest kept. `meets`:
  // for a junction line, the face g it lies on too: g's own volume is not tested (the line is
  // on its section's border, where g's plane and f's meet).
  void addVisible(dvec2 a, dvec2 b, std::uint32_t fi, PolygonId other, PolygonId neighbour,
                  int meets, std::vector<TraceOutline>* o) {
    const bool junction = meets >= 0;
    out_.edges += !junction;
    std::vector<std::pair<double, double>>& hidden = hidden_stretches_;
    hidden.clear();
    const PolygonId id = faces_[fi].w->id;
    const double x0 = std::min(a.x, b.x), x1 = std::max(a.x, b.x), y0 = std::min(a.y, b.y),
                 y1 = std::max(a.y, b.y);
    for (const Section& sec : sections_[fi]) {  // the largest first: most often one hides it all
      if (sec.x1 <= x0 || sec.x0 >= x1 || sec.y1 <= y0 || sec.y0 >= y1) {
        if (!(x0 == x1 && sec.x0 < x0 && x0 < sec.x1) && !(y0 == y1 && sec.y0 < y0 && y0 < sec.y1))
          continue;
      }
      const std::vector<std::uint32_t>& of = volumes_[sec.volume].faces;
      if (junction &&
          std::find(of.begin(), of.end(), static_cast<std::uint32_t>(meets)) != of.end())
        continue;
      double t0, t1;
      if (!insideStretch(a, b, sec.hull, &t0, &t1)) continue;
      if (t0 <= 0 && t1 >= 1) {  // hidden all along
        if (hidden_parts_) addHidden(a, b, id, other, neighbour, junction);
        return;
      }
      hidden.emplace_back(t0, t1);
    }
    std::sort(hidden.begin(), hidden.end());
    const double len = glm::length(b - a);
    double t = 0;
    auto emit = [&](double u0, double u1, bool shown) {
      if ((u1 - u0) * len <= kTiny) return;
      const dvec2 p = a + (b - a) * u0, q = a + (b - a) * u1;
      if (!shown) return addHidden(p, q, id, other, neighbour, junction);
      out_.segments.push_back(
          {p.x / kGrid, p.y / kGrid, q.x / kGrid, q.y / kGrid, id, other, junction, neighbour});
      if (o) o->push_back(outlineOf({p, q}));
    };
    for (const auto& [h0, h1] : hidden) {
      if (h0 > t) emit(t, h0, true);
      t = std::max(t, h1);
    }
    if (t < 1) emit(t, 1, true);
    if (!hidden_parts_) return;
    double run0 = 0, run1 = -1;  // the hidden runs: the union of the stretches, within the edge
    for (const auto& [h0, h1] : hidden) {
      const double u0 = std::max(h0, 0.0), u1 = std::min(h1, 1.0);
      if (u1 <= u0) continue;
      if (u0 > run1) {
        if (run1 > run0) emit(run0, run1, false);
        run0 = u0;
      }
      run1 = std::max(run1, u1);
    }
    if (run1 > run0) emit(run0, run1, false);
  }

  // ---- 5. Faces, for the picture: what the sections leave of the face, filled through the
  // shared routine; `o` holds its visible segments for the step's picture.
  void fillVisiblePart(std::uint32_t fi, bool show, std::vector<TraceOutline> o) {
    const Face& f = faces_[fi];
    ExactRegion region;
    const GridRegion whole{{f.ring, {}}};
    if (invalidRegionReason(whole).empty()) {
      region = exactRegion(whole);
    } else {  // snapping folded it (a sliver): its fan, as the Weiler-Atherton list takes it
      for (std::size_t k = 1; k + 1 < f.ring.size(); ++k) {
        const GridRegion tri{{{f.ring[0], f.ring[k], f.ring[k + 1]}, {}}};
        if (invalidRegionReason(tri).empty())
          region = booleanOp(region, exactRegion(tri), BooleanOp::Union);
      }
    }
    for (const Section& sec : sections_[fi]) {
      if (region.empty()) break;
      if (sec.shown.empty()) continue;
      const GridRing ring = snappedInside(sec.shown);
      const GridRegion covered{{ring, {}}};
      if (ring.size() < 3 || !invalidRegionReason(covered).empty()) continue;
      region = booleanOp(region, exactRegion(covered), BooleanOp::AMinusB);
    }
    paintExactRegion(region, f.w->depth, f.w->id, f.w->rgba, *fb_, fragments_, DepthFunc::Less);
    if (!show) return;
    const std::size_t kept = o.size();
    for (const Section& sec : sections_[fi]) o.push_back(outlineOf(sec.hull));
    trace_->record(
        {kStepFace,
         "Face " + std::to_string(f.w->id) + ": " + std::to_string(sections_[fi].size()) +
             " volumes come in front of its plane; each hides the section of its shadow by the "
             "plane (outlined). Its edges keep " +
             std::to_string(kept) +
             " visible segments (outlined), and what the sections leave of the face is filled.",
         frame_, std::move(o)});
  }

  static constexpr double kMin = -0.5;  // the view's left and top border (pixel-centre coordinates)

  const Scene& scene_;
  const std::vector<WindowPolygon>& polygons_;
  Frame* frame_;
  Trace* trace_;  // null unless explained with a frame
  const bool hidden_parts_;
  const Deadline* deadline_;
  const double xmax_, ymax_;  // the view's right and bottom border
  RobertsDrawing out_;
  Scaled sc_;
  std::vector<int> solid_of_, outward_of_;  // per object
  std::vector<Face> faces_;
  std::vector<Volume> volumes_;
  std::vector<BackFace> back_faces_;
  std::vector<TraceOutline> back_outlines_, all_outlines_;
  std::vector<std::vector<Section>> sections_;                      // per face
  std::vector<std::uint8_t> hidden_whole_;                          // per face
  std::vector<std::vector<std::pair<EdgeKey, EdgeRef>>> edges_of_;  // per face
  std::map<EdgeKey, std::pair<PolygonId, PolygonId>> back_edges_;
  std::vector<std::vector<Junction>> junctions_;  // per face: the lines it meets others on
  std::vector<std::pair<double, double>> hidden_stretches_;  // addVisible's scratch
  std::uint64_t checked_ = 0;  // steps of the later loops, for the deadline
  std::optional<FrameView> fb_;
  FragmentCounts fragments_;
};

}  // namespace

RobertsDrawing robertsDrawingOf(const Scene& scene, const std::vector<WindowPolygon>& polygons,
                                int width, int height, Frame* frame, Trace* trace,
                                bool hidden_parts, const Deadline* deadline) {
  return RobertsRun(scene, polygons, width, height, frame, trace, hidden_parts, deadline).run();
}

void drawRoberts(const AlgorithmInput& in, Frame& frame) {
  detail::Stopwatch watch;
  const RobertsDrawing d =
      robertsDrawingOf(in.scene, in.prepared.polygons, frame.width, frame.height, &frame, in.trace);
  const double edges_ms = watch.lap();
  const FrameView fb(frame);
  FragmentCounts fragments;
  // See-through polygons over the finished picture, in submission order, as the z-buffer.
  for (const WindowPolygon& w : in.prepared.polygons)
    if (w.transparent) fillPolygon(w, fb, DepthFunc::Less, true, fragments);
  const PixelBox viewport{0, 0, frame.width - 1, frame.height - 1};
  for (const ScreenLine& o : in.prepared.outline) drawOutlinePen(o, viewport, fb);
  if (in.trace && in.trace->wants(kStepDone, 0, 1)) {
    std::vector<TraceOutline> lines;
    for (const RobertsSegment& sg : d.segments)
      lines.push_back({{static_cast<float>(sg.x0), static_cast<float>(sg.y0)},
                       {static_cast<float>(sg.x1), static_cast<float>(sg.y1)}});
    in.trace->record({kStepDone,
                      "Done: " + std::to_string(d.segments.size()) +
                          " visible segments (outlined) of " + std::to_string(d.edges) +
                          " edges and " + std::to_string(d.junctions) + " junction lines, after " +
                          std::to_string(d.tests) + " tests of a face against a volume.",
                      &frame, std::move(lines)});
  }
  frame.stats.fragments_tested += fragments.tested;
  frame.stats.fragments_written += fragments.written;
  frame.stats.state_bytes += frameBufferBytes(frame);
  std::uint64_t decomposed = 0;
  for (const RobertsObject& o : d.objects) decomposed += !o.solid;
  frame.stats.addCounter("roberts: convex solids", d.solids);
  frame.stats.addCounter("roberts: objects taken face by face", decomposed);
  frame.stats.addCounter("roberts: back faces removed", d.back_faces);
  frame.stats.addCounter("roberts: faces", d.faces);
  frame.stats.addCounter("roberts: volumes", d.volumes);
  frame.stats.addCounter("roberts: face-volume tests", d.tests);
  frame.stats.addCounter("roberts: edges", d.edges);
  frame.stats.addCounter("roberts: junction lines", d.junctions);
  frame.stats.addCounter("roberts: visible segments", d.segments.size());
  frame.stats.addStage("edges and faces", edges_ms);
  frame.stats.addStage("see-through, outline", watch.ms());
}

}  // namespace hsr::detail

namespace hsr {

RobertsDrawing robertsDrawing(const Scene& scene, const Camera& camera,
                              const RenderOptions& options, bool hidden_parts) {
  if (options.polygon_mode != PolygonMode::Fill)
    throw Error("robertsDrawing: the polygon mode must be fill");
  const detail::PreparedScene ps =
      detail::prepare(scene, camera, options, {.window_polygons = true});
  return detail::robertsDrawingOf(scene, ps.polygons, ps.width, ps.height, nullptr, nullptr,
                                  hidden_parts);
}

}  // namespace hsr
