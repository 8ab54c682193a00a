#pragma once
// The differential oracle of docs/testing.md rows 4 and 5: a deliberately simple z-buffer in double
// precision that shares no code with src/. It builds the camera's matrices itself (gluLookAt,
// gluPerspective / glOrtho) from the Camera's fields, projects every polygon, and tests EVERY
// pixel centre of each polygon's bounding box against the polygon's edges: no clipping, no
// snapping, no incremental stepping, depth from the polygon's plane in window space (window z
// is affine in window x, y for a planar polygon). Depth test LESS; on a tie (|dz| <= kTie) the
// first submitted polygon stays.
//
// It also marks each pixel AMBIGUOUS where a correct renderer may legitimately disagree (the
// three-valued verifier of dEQP, with a 1-pixel kernel). With F the reference's front polygon
// at the pixel centre c, a pixel is ambiguous when some polygon P covers c or comes within
// 1 px of it, and
//   - P is F and c is within 1 px of F's boundary (F's coverage is uncertain), or
//   - nothing covers c and c is within 1 px of P's boundary, or
//   - P's plane at c is in front of F's (P would win wherever it covers c) and c is within
//     1 px of P's boundary (P's coverage is uncertain), or
//   - the depth gap z_P(c) - z_F(c) is below kRelativeGap relative to the depth (a tie), or
//   - the zero line of the gap plane (the intersection line of P and F in window space) lies
//     within 1 px of c: |gap| / |grad gap| < 1.
// Edges of polygons that lie clearly BEHIND the front surface do not make a pixel ambiguous:
// whether they cover c or not, F wins. This keeps the unambiguous set large on dense scenes
// while staying sound (every way the answer can flip is covered above).
//
// Scenes must lie in front of the eye and between the near and far planes (the reference does
// not clip at near/far); `valid` is false otherwise. Off-screen parts need no clipping: only
// pixel centres inside the viewport are tested.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "hsr/camera.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace hsr::testing {

struct RefVec3 {
  double x, y, z;
};

// Why a pixel is ambiguous (bits; a pixel may have several).
enum RefAmbiguity : std::uint8_t {
  kRefEdge = 1,          // within 1 px of the boundary of a polygon that matters there
  kRefTie = 2,           // front-two depth gap below kRelativeGap
  kRefIntersection = 4,  // within 1 px of an intersection line with the front polygon
};

struct ReferenceFrame {
  int width = 0, height = 0;
  // All TOP ROW FIRST, as hsr::Frame: GL window pixel (x, y) is element (height-1-y)*width+x.
  std::vector<PolygonId> ids;           // kNoPolygon where nothing covers the centre
  std::vector<double> depth;            // window z of the front polygon; 1.0 where none
  std::vector<std::uint8_t> ambiguous;  // RefAmbiguity bits; 0 = unambiguous
  bool valid = true;
  std::string problem;  // why not valid (a vertex behind the eye or outside near/far)

  std::size_t index(int x, int y_up) const {
    return static_cast<std::size_t>(height - 1 - y_up) * width + x;
  }
};

// The camera as the reference sees it: world -> window (x, y up from the bottom-left corner,
// pixel centres at +0.5; z in [0,1]) in double, built from the Camera's fields.
class RefProjection {
 public:
  explicit RefProjection(const Camera& c) : cam_(c) {
    const RefVec3 eye{c.eye.x, c.eye.y, c.eye.z};
    const RefVec3 dir{c.target.x - eye.x, c.target.y - eye.y, c.target.z - eye.z};
    f_ = normalize(dir);
    s_ = normalize(cross(f_, RefVec3{c.up.x, c.up.y, c.up.z}));
    u_ = cross(s_, f_);
    eye_ = eye;
  }

  // Clip coordinates of a world point: gluLookAt, then gluPerspective or glOrtho.
  void clip(const glm::vec3& p, double out[4]) const {
    const RefVec3 d{double(p.x) - eye_.x, double(p.y) - eye_.y, double(p.z) - eye_.z};
    const double ex = dot(s_, d), ey = dot(u_, d), ez = -dot(f_, d);  // eye space
    const double n = cam_.near, f = cam_.far;
    const double aspect = double(cam_.width) / double(cam_.height);
    if (cam_.ortho) {
      const double h = cam_.ortho_half_height;
      out[0] = ex / (h * aspect);
      out[1] = ey / h;
      out[2] = -2.0 / (f - n) * ez - (f + n) / (f - n);
      out[3] = 1.0;
    } else {
      const double t = 1.0 / std::tan(double(cam_.fov_deg) * 3.14159265358979323846 / 360.0);
      out[0] = t / aspect * ex;
      out[1] = t * ey;
      out[2] = (f + n) / (n - f) * ez + 2.0 * f * n / (n - f);
      out[3] = -ez;
    }
  }

  // Window coordinates; false when the point is behind the eye or outside near/far.
  bool window(const glm::vec3& p, RefVec3* w) const {
    double c[4];
    clip(p, c);
    if (!(c[3] > 0.0) || !(c[2] > -c[3]) || !(c[2] < c[3])) return false;
    w->x = (c[0] / c[3] + 1.0) * 0.5 * cam_.width;
    w->y = (c[1] / c[3] + 1.0) * 0.5 * cam_.height;
    w->z = (c[2] / c[3] + 1.0) * 0.5;
    return true;
  }

 private:
  static double dot(const RefVec3& a, const RefVec3& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
  }
  static RefVec3 cross(const RefVec3& a, const RefVec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  }
  static RefVec3 normalize(const RefVec3& a) {
    const double l = std::sqrt(dot(a, a));
    return {a.x / l, a.y / l, a.z / l};
  }
  Camera cam_;
  RefVec3 eye_{}, f_{}, s_{}, u_{};
};

// One projected polygon: counter-clockwise window vertices and its depth plane.
struct RefPolygon {
  std::vector<RefVec3> v;                             // window space, CCW (y up)
  double x0 = 0, y0 = 0, z0 = 0, dzdx = 0, dzdy = 0;  // z(x,y) = z0 + dzdx (x-x0) + dzdy (y-y0)
  double lo_x = 0, lo_y = 0, hi_x = 0, hi_y = 0;      // bounds
  bool degenerate = false;  // (nearly) zero window area: covers nothing, only its edges count

  double depthAt(double x, double y) const { return z0 + dzdx * (x - x0) + dzdy * (y - y0); }

  // Inside (boundary included) by the edge functions of the CCW polygon.
  bool contains(double x, double y) const {
    const std::size_t n = v.size();
    for (std::size_t i = 0; i < n; ++i) {
      const RefVec3& a = v[i];
      const RefVec3& b = v[(i + 1) % n];
      if ((b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x) < 0.0) return false;
    }
    return true;
  }

  // Distance from (x, y) to the nearest point of the boundary (the edges as segments).
  double boundaryDistance(double x, double y) const {
    double best = std::numeric_limits<double>::infinity();
    const std::size_t n = v.size();
    for (std::size_t i = 0; i < n; ++i) {
      const RefVec3& a = v[i];
      const RefVec3& b = v[(i + 1) % n];
      const double ex = b.x - a.x, ey = b.y - a.y;
      const double len2 = ex * ex + ey * ey;
      double t = len2 > 0.0 ? ((x - a.x) * ex + (y - a.y) * ey) / len2 : 0.0;
      t = std::clamp(t, 0.0, 1.0);
      const double dx = x - (a.x + t * ex), dy = y - (a.y + t * ey);
      best = std::min(best, std::sqrt(dx * dx + dy * dy));
    }
    return best;
  }
};

// Two surfaces closer than this in window depth are a tie in the reference's depth test (the
// first submitted stays): coplanar polygons evaluate their planes with rounding of ~1e-16.
inline constexpr double kRefTieDepth = 1e-12;
// A front-two depth gap below this fraction of the depth is ambiguous (docs/testing.md row 4).
inline constexpr double kRefRelativeGap = 1e-6;
// The pixel kernel of the ambiguity rules.
inline constexpr double kRefKernelPx = 1.0;

inline bool projectPolygon(const Scene& scene, PolygonId id, const RefProjection& proj,
                           RefPolygon* out, std::string* problem) {
  const std::span<const std::uint32_t> idx = scene.polygon(id);
  out->v.clear();
  for (std::uint32_t k : idx) {
    RefVec3 w;
    if (!proj.window(scene.position(k), &w)) {
      *problem = "polygon " + std::to_string(id) +
                 " has a vertex behind the eye or outside "
                 "near/far; the reference does not clip";
      return false;
    }
    out->v.push_back(w);
  }
  // Orientation by the shoelace formula; make it counter-clockwise.
  double area2 = 0.0;
  const std::size_t n = out->v.size();
  for (std::size_t i = 0; i < n; ++i) {
    const RefVec3& a = out->v[i];
    const RefVec3& b = out->v[(i + 1) % n];
    area2 += a.x * b.y - b.x * a.y;
  }
  if (area2 < 0.0) std::reverse(out->v.begin(), out->v.end());
  out->lo_x = out->hi_x = out->v[0].x;
  out->lo_y = out->hi_y = out->v[0].y;
  for (const RefVec3& p : out->v) {
    out->lo_x = std::min(out->lo_x, p.x);
    out->hi_x = std::max(out->hi_x, p.x);
    out->lo_y = std::min(out->lo_y, p.y);
    out->hi_y = std::max(out->hi_y, p.y);
  }
  // The depth plane through the fan triangle (0, i, i+1) of largest area (the polygon is
  // planar, so any would do up to rounding).
  std::size_t best = 1;
  double best_det = 0.0;
  const RefVec3& p0 = out->v[0];
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const RefVec3& a = out->v[i];
    const RefVec3& b = out->v[i + 1];
    const double det = (a.x - p0.x) * (b.y - p0.y) - (b.x - p0.x) * (a.y - p0.y);
    if (std::abs(det) > std::abs(best_det)) {
      best_det = det;
      best = i;
    }
  }
  out->degenerate = !(std::abs(area2) > 1e-6) || !(std::abs(best_det) > 1e-9);
  out->x0 = p0.x;
  out->y0 = p0.y;
  out->z0 = p0.z;
  out->dzdx = out->dzdy = 0.0;
  if (!out->degenerate) {
    const RefVec3& a = out->v[best];
    const RefVec3& b = out->v[best + 1];
    const double dx1 = a.x - p0.x, dy1 = a.y - p0.y, dz1 = a.z - p0.z;
    const double dx2 = b.x - p0.x, dy2 = b.y - p0.y, dz2 = b.z - p0.z;
    out->dzdx = (dz1 * dy2 - dz2 * dy1) / best_det;
    out->dzdy = (dx1 * dz2 - dx2 * dz1) / best_det;
  }
  return true;
}

// Pixel-centre columns (or rows) whose centre c + 0.5 lies in [lo - margin, hi + margin],
// clamped to [0, size).
inline void pixelRange(double lo, double hi, double margin, int size, int* first, int* last) {
  const double a = std::ceil(lo - margin - 0.5), b = std::floor(hi + margin - 0.5);
  *first = static_cast<int>(std::max(a, 0.0));
  *last = static_cast<int>(std::min(b, double(size - 1)));
}

inline ReferenceFrame referenceZBuffer(const Scene& scene, const Camera& camera) {
  ReferenceFrame r;
  r.width = camera.width;
  r.height = camera.height;
  const std::size_t pixels = static_cast<std::size_t>(r.width) * r.height;
  r.ids.assign(pixels, kNoPolygon);
  r.depth.assign(pixels, 1.0);
  r.ambiguous.assign(pixels, 0);
  const RefProjection proj(camera);
  std::vector<RefPolygon> polys(scene.polygonCount());
  for (PolygonId id = 0; id < scene.polygonCount(); ++id) {
    if (!projectPolygon(scene, id, proj, &polys[id], &r.problem)) {
      r.valid = false;
      return r;
    }
  }

  // Pass 1: the depth test at every covered pixel centre, in submission order.
  for (PolygonId id = 0; id < polys.size(); ++id) {
    const RefPolygon& p = polys[id];
    if (p.degenerate) continue;
    int x0, x1, y0, y1;
    pixelRange(p.lo_x, p.hi_x, 0.0, r.width, &x0, &x1);
    pixelRange(p.lo_y, p.hi_y, 0.0, r.height, &y0, &y1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double cx = x + 0.5, cy = y + 0.5;
        if (!p.contains(cx, cy)) continue;
        const double z = p.depthAt(cx, cy);
        const std::size_t k = r.index(x, y);
        if (z < r.depth[k] - kRefTieDepth) {
          r.depth[k] = z;
          r.ids[k] = id;
        }
      }
  }

  // Pass 2: ambiguity, from every polygon that covers or nearly covers each pixel centre.
  for (PolygonId id = 0; id < polys.size(); ++id) {
    const RefPolygon& p = polys[id];
    int x0, x1, y0, y1;
    pixelRange(p.lo_x, p.hi_x, kRefKernelPx, r.width, &x0, &x1);
    pixelRange(p.lo_y, p.hi_y, kRefKernelPx, r.height, &y0, &y1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double cx = x + 0.5, cy = y + 0.5;
        const bool inside = !p.degenerate && p.contains(cx, cy);
        const bool near_edge = p.boundaryDistance(cx, cy) < kRefKernelPx;
        if (!inside && !near_edge) continue;
        const std::size_t k = r.index(x, y);
        const PolygonId front = r.ids[k];
        if (p.degenerate || front == kNoPolygon || front == id) {
          // Its own coverage decides, or nothing else is there: the edge alone matters.
          if (near_edge) r.ambiguous[k] |= kRefEdge;
          continue;
        }
        const RefPolygon& f = polys[front];
        const double gap = p.depthAt(cx, cy) - f.depthAt(cx, cy);
        const double gx = p.dzdx - f.dzdx, gy = p.dzdy - f.dzdy;
        const double grad = std::sqrt(gx * gx + gy * gy);
        const double scale = std::max(std::abs(p.depthAt(cx, cy)), std::abs(f.depthAt(cx, cy)));
        if (std::abs(gap) < kRefRelativeGap * scale) r.ambiguous[k] |= kRefTie;
        if (std::abs(gap) < grad * kRefKernelPx) r.ambiguous[k] |= kRefIntersection;
        if (near_edge && gap < 0.0) r.ambiguous[k] |= kRefEdge;  // P would win where it covers
      }
  }
  return r;
}

// What the reference knows about one polygon at one pixel centre (for failure messages).
struct RefProbe {
  bool covers = false;
  double depth = 0.0;          // window z of the polygon's plane at the centre
  double edge_distance = 0.0;  // px from the centre to the polygon's boundary
};

inline RefProbe probePolygon(const Scene& scene, const Camera& camera, PolygonId id, int x,
                             int y_up) {
  RefProbe probe;
  RefPolygon p;
  std::string problem;
  if (id >= scene.polygonCount() || !projectPolygon(scene, id, RefProjection(camera), &p, &problem))
    return probe;
  const double cx = x + 0.5, cy = y_up + 0.5;
  probe.covers = !p.degenerate && p.contains(cx, cy);
  probe.depth = p.depthAt(cx, cy);
  probe.edge_distance = p.boundaryDistance(cx, cy);
  return probe;
}

}  // namespace hsr::testing
