// The shared front end of every visibility algorithm: cull, clip, project, snap.
// Guarantee: the output depends only on the scene, camera and options (never on the thread
// count): work is split into fixed chunks of polygons whose outputs are joined in order.

#include "pipeline/pipeline.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <cmath>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "pipeline/triangulate.hpp"

namespace hsr::detail {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

constexpr std::size_t kChunk = 2048;  // polygons per work item (fixed: determinism)

enum ClipBit : unsigned {
  kLeft = 1, kRight = 2, kBottom = 4, kTop = 8, kNear = 16, kFar = 32,  // view volume
  kGuardX0 = 64, kGuardX1 = 128, kGuardY0 = 256, kGuardY1 = 512,       // x/y clip band
};
constexpr unsigned kMustClip = kNear | kFar | kGuardX0 | kGuardX1 | kGuardY0 | kGuardY1;

// Where x and y are clipped, in NDC units: |x| <= gx w, |y| <= gy w. A guard band (g > 1)
// would leave more triangles unclipped; we clip at the viewport (g = 1) as llvmpipe does, so
// clipped edges snap exactly as Mesa's, and snapped coordinates stay within the viewport.
struct ClipSetup {
  float gx, gy;
};

unsigned outcode(const glm::vec4& v, const ClipSetup& cs) {
  unsigned c = 0;
  if (!(v.x >= -v.w)) c |= kLeft;
  if (!(v.x <= v.w)) c |= kRight;
  if (!(v.y >= -v.w)) c |= kBottom;
  if (!(v.y <= v.w)) c |= kTop;
  if (!(v.z >= -v.w)) c |= kNear;
  if (!(v.z <= v.w)) c |= kFar;
  if (!(v.x >= -cs.gx * v.w)) c |= kGuardX0;
  if (!(v.x <= cs.gx * v.w)) c |= kGuardX1;
  if (!(v.y >= -cs.gy * v.w)) c |= kGuardY0;
  if (!(v.y <= cs.gy * v.w)) c |= kGuardY1;
  return c;
}

// Signed distance of a clip-space point to clip plane k (>= 0 inside), in the order and with
// the arithmetic of Mesa's clipper (draw_pipe_clip: right, left, top, bottom, near, far), so
// that clipped vertices come out bit-identical to llvmpipe's.
float planeDistance(const glm::vec4& v, int k, const ClipSetup& cs) {
  switch (k) {
    case 0: return cs.gx * v.w - v.x;    // right
    case 1: return cs.gx * v.w + v.x;    // left
    case 2: return cs.gy * v.w - v.y;    // top
    case 3: return cs.gy * v.w + v.y;    // bottom
    case 4: return v.z + v.w;            // near
    default: return v.w - v.z;           // far
  }
}
constexpr unsigned kPlaneBit[6] = {kGuardX1, kGuardX0, kGuardY1, kGuardY0, kNear, kFar};

// Where the edge from `near` (distance dnear to plane k) to `far` (dfar) crosses plane k.
// Ordinary edges use Mesa's float arithmetic, so clipped vertices stay bit-identical to
// llvmpipe's. An edge with an endpoint more than 2^12 viewports away (|x|, |y| or |z| beyond
// 4096 |w|) is computed in double instead: in float, w - x loses w entirely once |x| >> |w|,
// and a triangle spanning 1e10 units clipped up to 32 pixels off (TESTING.md row 14; the test
// Degenerate.HugeCoordinatesClipCorrectly).
glm::vec4 clipIntersection(const glm::vec4& near_p, const glm::vec4& far_p, float dnear,
                           float dfar, int k, const ClipSetup& cs) {
  constexpr float kFar = 4096.0f;
  const auto huge = [&](const glm::vec4& p) {
    const float m = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    return !(m <= kFar * std::abs(p.w));
  };
  if (!huge(near_p) && !huge(far_p)) {
    const float t = dnear / (dnear - dfar);
    return near_p + t * (far_p - near_p);
  }
  const glm::dvec4 a(near_p), b(far_p);
  const auto dist = [&](const glm::dvec4& v) {
    const double gx = cs.gx, gy = cs.gy;
    switch (k) {
      case 0: return gx * v.w - v.x;
      case 1: return gx * v.w + v.x;
      case 2: return gy * v.w - v.y;
      case 3: return gy * v.w + v.y;
      case 4: return v.z + v.w;
      default: return v.w - v.z;
    }
  };
  const double da = dist(a), db = dist(b);
  const double t = da / (da - db);
  glm::dvec4 v = a + t * (b - a);
  // Exactly on the plane (the interpolation may miss it by a rounding step)
  switch (k) {
    case 0: v.x = cs.gx * v.w; break;
    case 1: v.x = -cs.gx * v.w; break;
    case 2: v.y = cs.gy * v.w; break;
    case 3: v.y = -cs.gy * v.w; break;
    case 4: v.z = -v.w; break;
    default: v.z = v.w; break;
  }
  return glm::vec4(v);
}

// A clip-space vertex plus whether the edge leaving it is an original polygon edge (GL's
// edge flag: edges made by clipping are not drawn in LINE mode).
struct ClipVertex {
  glm::vec4 p;
  bool edge;
  bool original = true;  // an input vertex, not one made by clipping (POINT mode draws these)
};
using ClipPolygon = std::vector<ClipVertex>;

// Sutherland-Hodgman against the planes the polygon crosses, in homogeneous coordinates
// (before the divide, so parts behind the eye are cut away, never inverted).
void clipPolygon(ClipPolygon& poly, unsigned planes, const ClipSetup& cs, ClipPolygon& tmp) {
  for (int k = 0; k < 6 && !poly.empty(); ++k) {
    if (!(planes & kPlaneBit[k])) continue;
    tmp.clear();
    const std::size_t n = poly.size();
    for (std::size_t i = 0; i < n; ++i) {
      const ClipVertex& a = poly[i];
      const ClipVertex& b = poly[(i + 1) % n];
      const float da = planeDistance(a.p, k, cs), db = planeDistance(b.p, k, cs);
      const bool ina = da >= 0.0f, inb = db >= 0.0f;
      if (ina) tmp.push_back(a);
      if (ina != inb) {
        // Interpolate from the endpoint nearer the plane (the inside one on a tie), as Mesa's
        // clipper does: independent of edge direction, and bit-identical to llvmpipe.
        const bool from_a = std::abs(da) < std::abs(db) || (std::abs(da) == std::abs(db) && ina);
        const ClipVertex& near_v = from_a ? a : b;
        const ClipVertex& far_v = from_a ? b : a;
        ClipVertex v{clipIntersection(near_v.p, far_v.p, from_a ? da : db, from_a ? db : da, k, cs),
                     false, false};
        // Entering the inside keeps the original edge's flag; the new edge along the plane
        // (from the exit point to the next entry) is not an original edge.
        v.edge = ina ? false : a.edge;
        if (ina) tmp.back().edge = a.edge;
        tmp.push_back(v);
      }
    }
    poly.swap(tmp);
  }
}

struct Viewport {
  float sx, tx, sy, ty;  // window = ndc * s + t (y down)
};

struct WindowVertex {
  float x, y, z;          // float window coords, pixel centres at integers, y down
  std::int64_t fx, fy;    // snapped
  bool ok;                // finite and within 2^22 pixels (false: drop the primitive)
};

WindowVertex toWindow(const glm::vec4& c, const Viewport& vp) {
  // As Mesa's draw module: multiply by 1/w, then scale and translate; z to [0,1].
  const float iw = 1.0f / c.w;
  WindowVertex v;
  const float xw = (c.x * iw) * vp.sx + vp.tx;
  const float yw = (c.y * iw) * vp.sy + vp.ty;
  v.z = (c.z * iw) * 0.5f + 0.5f;
  // Pixel centres at integers (GL samples at x + 0.5), then 8 sub-pixel bits, round to nearest.
  v.x = xw - 0.5f;
  v.y = yw - 0.5f;
  // Only finite, bounded values are converted to integers (anything else would be undefined
  // behaviour); clipping keeps real primitives far inside this bound.
  constexpr float kLimit = 4194304.0f;  // 2^22 pixels
  v.ok = std::abs(v.x) < kLimit && std::abs(v.y) < kLimit && std::isfinite(v.z);
  v.fx = v.ok ? std::lrint(v.x * static_cast<float>(kSubpixelOne)) : 0;
  v.fy = v.ok ? std::lrint(v.y * static_cast<float>(kSubpixelOne)) : 0;
  return v;
}

// Per-vertex results of the transform stage, shared by every triangle that uses the vertex.
constexpr unsigned kNonFinite = 1u << 16;
struct VertexOut {
  WindowVertex w;  // valid when !(code & kMustClip)
  unsigned code;   // outcode, plus kNonFinite
};

struct PolygonInfo {
  int eye_orientation;  // +1 CCW seen from the eye, -1 CW, 0 edge-on/degenerate
  std::uint32_t rgba;
  bool transparent;
  bool degenerate;
};

std::uint32_t packColor(glm::vec3 c, float alpha) {
  auto q = [](float v) {
    v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
    return static_cast<std::uint32_t>(v * 255.0f + 0.5f);  // round half up; v is in [0,1]
  };
  return q(c.r) | (q(c.g) << 8) | (q(c.b) << 16) | (q(alpha) << 24);
}

PolygonInfo polygonInfo(const Scene& scene, PolygonId id, const Camera& camera,
                        const glm::vec3& view_dir, bool shade) {
  PolygonInfo info{0, 0, false, true};
  const std::span<const std::uint32_t> poly = scene.polygon(id);
  for (std::uint32_t v : poly) {
    const glm::vec3& p = scene.position(v);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return info;
  }
  // Normal by the right-hand rule: a cross product for triangles, Newell's method otherwise
  // (any polygon, even a non-planar one). Any point of a planar polygon serves as P.
  const glm::dvec3 p0(scene.position(poly[0]));
  glm::dvec3 n;
  if (poly.size() == 3) {
    n = glm::cross(glm::dvec3(scene.position(poly[1])) - p0, glm::dvec3(scene.position(poly[2])) - p0);
  } else {
    n = newellNormal(scene, poly);
  }
  const double len2 = glm::dot(n, n);
  if (!(len2 > 0.0) || !std::isfinite(len2)) return info;  // zero area
  info.degenerate = false;
  // The notes' test: V = eye - P (or the reversed view direction for parallel projection).
  const glm::dvec3 v = camera.ortho ? -glm::dvec3(view_dir) : glm::dvec3(camera.eye) - p0;
  const double d = glm::dot(n, v);
  info.eye_orientation = d > 0.0 ? 1 : (d < 0.0 ? -1 : 0);
  const std::uint32_t m = scene.material(id);
  const Material mat = m < scene.materials.size() ? scene.materials[m] : Material{};
  // Headlight Lambert, two-sided: light from the eye, 20% ambient.
  float lambert = 1.0f;
  if (shade) {
    const double vl2 = glm::dot(v, v);
    const double cosine = std::abs(d) / std::sqrt(len2 * vl2);
    lambert = cosine >= 0.0 && cosine <= 1.0 ? static_cast<float>(cosine) : 1.0f;
    lambert = 0.2f + 0.8f * lambert;
  }
  info.rgba = packColor(mat.color * lambert, mat.alpha);
  info.transparent = mat.alpha < 1.0f;
  return info;
}

// Which facings survive the cull mode. `front` is the polygon's facing under the rule.
bool culled(CullMode mode, bool front) {
  switch (mode) {
    case CullMode::None: return false;
    case CullMode::Back: return !front;
    case CullMode::Front: return front;
    case CullMode::FrontAndBack: return true;
  }
  return false;
}

// Output of one chunk of polygons.
struct ChunkOut {
  std::vector<ScreenTriangle> triangles;
  std::vector<WindowVertex> window_scratch;  // a clipped polygon's projected vertices
  std::vector<ScreenLine> lines, points;
  std::uint64_t degenerate = 0, culled_frustum = 0, culled_backface = 0, clipped = 0,
                clipped_away = 0, triangles_in = 0;
};

struct Context {
  const Scene& scene;
  const Camera& camera;
  const RenderOptions& options;
  glm::mat4 mvp;
  glm::vec3 view_dir;
  ClipSetup cs;
  Viewport vp;
  const std::vector<glm::vec4>& clip;            // clip-space vertex positions
  const std::vector<VertexOut>& verts;           // per-vertex outcodes and window positions
  const std::vector<std::uint8_t>& object_state;  // 0 culled, 1 inside, 2 crosses
  std::vector<glm::vec3> material_rgb;           // per material: rgb * 255, clamped
  std::vector<std::uint32_t> material_alpha;     // per material: alpha byte << 24
};

// Facing and culling of one window-space triangle; then emitTriangle.
void cullAndEmit(const Context& ctx, const WindowVertex (&w)[3], PolygonId id,
                 const PolygonInfo& info, ChunkOut& out);

void emitTriangle(const Context& ctx, const WindowVertex (&w)[3], PolygonId id,
                  const PolygonInfo& info, ChunkOut& out, int orientation, bool front) {
  const std::int64_t fx[3] = {w[0].fx, w[1].fx, w[2].fx};
  const std::int64_t fy[3] = {w[0].fy, w[1].fy, w[2].fy};
  // Order the vertices so the y-down area is positive (every edge function > 0 inside).
  int o[3] = {0, 1, 2};
  if (orientation > 0) std::swap(o[1], o[2]);  // CCW in y-up is negative area in y-down
  // Start the cycle at the topmost, then leftmost snapped vertex, so the depth plane below is
  // computed from the same reference vertex in the same order however the triangle was
  // submitted: identical triangles get bit-identical depths and the depth test's tie rule
  // (first submitted wins under LESS) holds for them in any vertex order (TESTING.md row 6).
  {
    int first = 0;
    for (int k = 1; k < 3; ++k) {
      if (fy[o[k]] < fy[o[first]] || (fy[o[k]] == fy[o[first]] && fx[o[k]] < fx[o[first]]))
        first = k;
    }
    std::rotate(o, o + first, o + 3);
  }
  ScreenTriangle t;
  for (int k = 0; k < 3; ++k) {
    t.x[k] = static_cast<std::int32_t>(fx[o[k]]);
    t.y[k] = static_cast<std::int32_t>(fy[o[k]]);
  }
  // Pixel bounding box (pixel centres are at multiples of 256), clamped to the viewport;
  // a triangle between pixel centres or off screen covers nothing.
  const std::int64_t bx0 = std::max<std::int64_t>(0, -((-std::min({fx[0], fx[1], fx[2]})) >> kSubpixelBits));
  const std::int64_t by0 = std::max<std::int64_t>(0, -((-std::min({fy[0], fy[1], fy[2]})) >> kSubpixelBits));
  const std::int64_t bx1 = std::min<std::int64_t>(ctx.camera.width - 1, std::max({fx[0], fx[1], fx[2]}) >> kSubpixelBits);
  const std::int64_t by1 = std::min<std::int64_t>(ctx.camera.height - 1, std::max({fy[0], fy[1], fy[2]}) >> kSubpixelBits);
  if (bx0 > bx1 || by0 > by1) return;
  t.x0 = static_cast<std::int16_t>(bx0);
  t.y0 = static_cast<std::int16_t>(by0);
  t.x1 = static_cast<std::int16_t>(bx1);
  t.y1 = static_cast<std::int16_t>(by1);
  // Depth plane through the three float window positions (z is affine in window space).
  const WindowVertex& a = w[o[0]];
  const WindowVertex& b = w[o[1]];
  const WindowVertex& c = w[o[2]];
  const double dx1 = double(b.x) - a.x, dy1 = double(b.y) - a.y, dz1 = double(b.z) - a.z;
  const double dx2 = double(c.x) - a.x, dy2 = double(c.y) - a.y, dz2 = double(c.z) - a.z;
  const double det = dx1 * dy2 - dx2 * dy1;
  t.xr = a.x;
  t.yr = a.y;
  t.z0 = a.z;
  if (det != 0.0) {
    const double inv = 1.0 / det;
    t.dzdx = static_cast<float>((dz1 * dy2 - dz2 * dy1) * inv);
    t.dzdy = static_cast<float>((dx1 * dz2 - dx2 * dz1) * inv);
  } else {
    t.dzdx = t.dzdy = 0.0f;
  }
  if (!std::isfinite(t.dzdx) || !std::isfinite(t.dzdy)) t.dzdx = t.dzdy = 0.0f;
  t.id = id;
  t.rgba = info.rgba;
  t.front = front ? 1 : 0;
  t.transparent = info.transparent ? 1 : 0;
  out.triangles.push_back(t);
}

void cullAndEmit(const Context& ctx, const WindowVertex (&w)[3], PolygonId id,
                 const PolygonInfo& info, ChunkOut& out) {
  const std::int64_t fx[3] = {w[0].fx, w[1].fx, w[2].fx};
  const std::int64_t fy[3] = {w[0].fy, w[1].fy, w[2].fy};
  const int orientation = windowOrientation(fx, fy);
  if (orientation == 0) return;  // zero area after snapping: draws nothing, as GL
  const bool ccw_front = ctx.options.front_face == FrontFace::Ccw;
  const bool front = ctx.options.facing_test == FacingTest::WindowArea
                         ? (orientation > 0) == ccw_front
                         : (info.eye_orientation > 0) == ccw_front;
  if (culled(ctx.options.cull, front)) {
    out.culled_backface++;
    return;
  }
  emitTriangle(ctx, w, id, info, out, orientation, front);
}

// The common case, kept lean: a triangle in FILL mode that needs no clipping. Per-vertex work
// (outcodes, projection, snapping) was done once per vertex in the transform stage.
// Returns false when the triangle needs the general path (clipping).
bool fastTriangle(const Context& ctx, PolygonId id, std::span<const std::uint32_t> vi,
                  ChunkOut& out) {
  const VertexOut& a = ctx.verts[vi[0]];
  const VertexOut& b = ctx.verts[vi[1]];
  const VertexOut& c = ctx.verts[vi[2]];
  const unsigned any = a.code | b.code | c.code;
  if (any & (kMustClip | kNonFinite)) return false;
  // Zero-area triangles in world space are degenerate data: dropped and counted. In double,
  // so that no finite float triangle over- or underflows into "degenerate" (as polygonInfo).
  const glm::dvec3 p0(ctx.scene.position(vi[0]));
  const glm::dvec3 n = glm::cross(glm::dvec3(ctx.scene.position(vi[1])) - p0,
                                  glm::dvec3(ctx.scene.position(vi[2])) - p0);
  const double len2 = glm::dot(n, n);
  if (!(len2 > 0.0) || !std::isfinite(len2)) {
    out.degenerate++;
    return true;
  }
  if (a.code & b.code & c.code & (kLeft | kRight | kBottom | kTop)) {
    out.clipped_away++;
    return true;
  }
  // Facing: OpenGL's window-space area, or the notes' N . (eye - P).
  const glm::dvec3 v = ctx.camera.ortho ? -glm::dvec3(ctx.view_dir) : glm::dvec3(ctx.camera.eye) - p0;
  const double d = glm::dot(n, v);
  const std::int64_t fx[3] = {a.w.fx, b.w.fx, c.w.fx};
  const std::int64_t fy[3] = {a.w.fy, b.w.fy, c.w.fy};
  const int orientation = windowOrientation(fx, fy);
  if (orientation == 0) return true;  // zero area after snapping: draws nothing, as GL
  const bool ccw_front = ctx.options.front_face == FrontFace::Ccw;
  const bool front = ctx.options.facing_test == FacingTest::WindowArea
                         ? (orientation > 0) == ccw_front
                         : (d > 0.0) == ccw_front;
  if (culled(ctx.options.cull, front)) {
    out.culled_backface++;
    return true;
  }
  // Headlight Lambert, two-sided, 20% ambient (as polygonInfo).
  const std::uint32_t m = ctx.scene.material(id);
  const bool known = m < ctx.material_rgb.size();
  const glm::vec3 rgb255 = known ? ctx.material_rgb[m] : glm::vec3(0.8f * 255.0f);
  const std::uint32_t alpha = known ? ctx.material_alpha[m] : 0xFF000000u;
  float lambert = 1.0f;
  if (ctx.options.shade) {
    const double vl2 = glm::dot(v, v);
    const double cosine = std::abs(d) / std::sqrt(len2 * vl2);
    // Any overflow (inf/inf) or 0/0 reads as facing the light.
    lambert = cosine >= 0.0 && cosine <= 1.0 ? static_cast<float>(cosine) : 1.0f;
    lambert = 0.2f + 0.8f * lambert;
  }
  // Both factors lie in [0, 1], so each channel lies in [0, 255]: round half up.
  const std::uint32_t rgba = static_cast<std::uint32_t>(rgb255.r * lambert + 0.5f) |
                             (static_cast<std::uint32_t>(rgb255.g * lambert + 0.5f) << 8) |
                             (static_cast<std::uint32_t>(rgb255.b * lambert + 0.5f) << 16) | alpha;
  const PolygonInfo info{d > 0.0 ? 1 : -1, rgba, alpha != 0xFF000000u, false};
  const WindowVertex w[3] = {a.w, b.w, c.w};
  emitTriangle(ctx, w, id, info, out, orientation, front);
  return true;
}

void processPolygon(const Context& ctx, PolygonId id, ChunkOut& out,
                    std::vector<Triangle>& tris, ClipPolygon& poly, ClipPolygon& tmp) {
  const Scene& scene = ctx.scene;
  const std::uint8_t state = ctx.object_state[scene.object(id)];
  const std::span<const std::uint32_t> vi = scene.polygon(id);
  out.triangles_in += vi.size() >= 3 ? vi.size() - 2 : 0;
  if (state == 0) {
    out.culled_frustum++;
    return;
  }
  if (vi.size() == 3 && ctx.options.polygon_mode == PolygonMode::Fill &&
      fastTriangle(ctx, id, vi, out))
    return;
  for (std::uint32_t v : vi) {
    if (ctx.verts[v].code & kNonFinite) {
      out.degenerate++;
      return;
    }
  }
  const PolygonInfo info = polygonInfo(scene, id, ctx.camera, ctx.view_dir, ctx.options.shade);
  if (info.degenerate) {
    out.degenerate++;
    return;
  }
  if (ctx.options.facing_test == FacingTest::EyePlane) {
    const bool front = (info.eye_orientation > 0) == (ctx.options.front_face == FrontFace::Ccw);
    if (culled(ctx.options.cull, front)) {
      out.culled_backface += vi.size() - 2;
      return;
    }
  }

  const PolygonMode mode = ctx.options.polygon_mode;
  if (mode != PolygonMode::Fill) {
    // LINE and POINT: the polygon's own edges / vertices, culled by the polygon's facing
    // (window area of the whole polygon after projection, or the eye test).
    poly.clear();
    unsigned all = ~0u, any = 0;
    for (std::uint32_t v : vi) {
      poly.push_back({ctx.clip[v], true});
      const unsigned c = outcode(ctx.clip[v], ctx.cs);
      all &= c;
      any |= c;
    }
    if (all & (kLeft | kRight | kBottom | kTop | kNear | kFar)) {
      out.clipped_away++;
      return;
    }
    if (any & kMustClip) {
      out.clipped++;
      clipPolygon(poly, any & kMustClip, ctx.cs, tmp);
    }
    if (poly.size() < 3) {
      out.clipped_away++;
      return;
    }
    std::vector<WindowVertex> wv(poly.size());
    for (std::size_t i = 0; i < poly.size(); ++i) {
      wv[i] = toWindow(poly[i].p, ctx.vp);
      if (!wv[i].ok) {
        out.clipped_away++;
        return;
      }
    }
    if (ctx.options.facing_test == FacingTest::WindowArea && ctx.options.cull != CullMode::None) {
      std::int64_t area = 0;  // doubled y-down area (shoelace)
      for (std::size_t i = 0; i < wv.size(); ++i) {
        const WindowVertex& a = wv[i];
        const WindowVertex& b = wv[(i + 1) % wv.size()];
        area += a.fx * b.fy - b.fx * a.fy;
      }
      const bool front = (area < 0) == (ctx.options.front_face == FrontFace::Ccw);
      if (area == 0 || culled(ctx.options.cull, front)) {
        out.culled_backface++;
        return;
      }
    }
    for (std::size_t i = 0; i < wv.size(); ++i) {
      const WindowVertex& a = wv[i];
      const WindowVertex& b = wv[(i + 1) % wv.size()];
      if (mode == PolygonMode::Line) {
        if (poly[i].edge) out.lines.push_back({a.x, a.y, a.z, b.x, b.y, b.z, id, info.rgba});
      } else if (poly[i].original) {
        out.points.push_back({a.x, a.y, a.z, a.x, a.y, a.z, id, info.rgba});
      }
    }
    return;
  }

  // FILL: triangulate, then per triangle: trivial reject, clip if needed, project, emit.
  tris.clear();
  triangulatePolygon(scene, id, tris);
  for (const Triangle& t : tris) {
    const glm::vec4 c[3] = {ctx.clip[t.v[0]], ctx.clip[t.v[1]], ctx.clip[t.v[2]]};
    unsigned codes[3];
    for (int k = 0; k < 3; ++k) codes[k] = outcode(c[k], ctx.cs);
    if (codes[0] & codes[1] & codes[2] & (kLeft | kRight | kBottom | kTop | kNear | kFar)) {
      out.clipped_away++;
      continue;
    }
    const unsigned crossing = (codes[0] | codes[1] | codes[2]) & kMustClip;
    if (!crossing) {
      const WindowVertex w[3] = {toWindow(c[0], ctx.vp), toWindow(c[1], ctx.vp),
                                 toWindow(c[2], ctx.vp)};
      if (w[0].ok && w[1].ok && w[2].ok) cullAndEmit(ctx, w, id, info, out);
      else out.clipped_away++;
      continue;
    }
    out.clipped++;
    poly.assign({{c[0], true}, {c[1], true}, {c[2], true}});
    clipPolygon(poly, crossing, ctx.cs, tmp);
    if (poly.size() < 3) {
      out.clipped_away++;
      continue;
    }
    // The clipped polygon is convex: a fan from its first vertex, as GL's clipper emits.
    std::vector<WindowVertex>& wv = out.window_scratch;
    wv.clear();
    bool ok = true;
    for (const ClipVertex& cv : poly) {
      wv.push_back(toWindow(cv.p, ctx.vp));
      ok = ok && wv.back().ok;
    }
    if (!ok) {
      out.clipped_away++;
      continue;
    }
    for (std::size_t k = 2; k < wv.size(); ++k) {
      const WindowVertex w[3] = {wv[0], wv[k - 1], wv[k]};
      cullAndEmit(ctx, w, id, info, out);
    }
  }
}

// Silhouette edges: edges shared by a front-facing and a back-facing polygon (eye test),
// plus border edges of open surfaces. Vertices are welded by position so unshared meshes
// (STL) still find their neighbours.
void findOutline(const Context& ctx, PreparedScene& out) {
  const Scene& scene = ctx.scene;
  // Keyed on the exact position (with -0 read as +0), so equal positions always weld.
  struct Key {
    std::uint32_t b[3];
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      return (std::uint64_t(k.b[0]) * 0x9E3779B97F4A7C15ull) ^
             (std::uint64_t(k.b[1]) * 0xC2B2AE3D27D4EB4Full) ^
             (std::uint64_t(k.b[2]) * 0x165667B19E3779F9ull);
    }
  };
  std::unordered_map<Key, std::uint32_t, KeyHash> weld;
  std::vector<std::uint32_t> canon(scene.vertexCount());
  for (std::uint32_t v = 0; v < scene.vertexCount(); ++v) {
    const glm::vec3 p = scene.position(v) + glm::vec3(0.0f);  // -0 + 0 = +0
    Key key;
    std::memcpy(key.b, &p, sizeof key.b);
    canon[v] = weld.try_emplace(key, v).first->second;
  }
  struct EdgeUse {
    PolygonId first;
    int facing;
    std::uint32_t a, b;  // original vertices of the first use
    int count;
    bool mixed;
    PolygonId other;
  };
  std::unordered_map<std::uint64_t, EdgeUse> edges;
  for (PolygonId id = 0; id < scene.polygonCount(); ++id) {
    if (ctx.object_state[scene.object(id)] == 0) continue;
    const int o = eyeSpaceOrientation(scene, id, ctx.camera);
    if (o == 0) continue;
    const std::span<const std::uint32_t> poly = scene.polygon(id);
    for (std::size_t i = 0; i < poly.size(); ++i) {
      std::uint32_t a = canon[poly[i]], b = canon[poly[(i + 1) % poly.size()]];
      if (a == b) continue;
      const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      auto [it, fresh] = edges.try_emplace(key, EdgeUse{id, o, poly[i], poly[(i + 1) % poly.size()], 1, false, id});
      if (!fresh) {
        it->second.count++;
        if (it->second.facing != o) {
          it->second.mixed = true;
          it->second.other = id;
        }
      }
    }
  }
  std::vector<std::pair<PolygonId, std::uint64_t>> order;
  for (const auto& [key, e] : edges)
    if (e.mixed || e.count == 1) order.push_back({e.first, key});
  std::sort(order.begin(), order.end());  // deterministic output order
  ClipPolygon seg, tmp;
  for (const auto& [pid, key] : order) {
    const EdgeUse& e = edges.at(key);
    if ((ctx.verts[e.a].code | ctx.verts[e.b].code) & kNonFinite) continue;
    // Clip the segment against near, far and the x/y band.
    glm::vec4 pa = ctx.clip[e.a], pb = ctx.clip[e.b];
    const unsigned ca = outcode(pa, ctx.cs), cb = outcode(pb, ctx.cs);
    if (ca & cb & (kLeft | kRight | kBottom | kTop | kNear | kFar)) continue;
    bool visible = true;
    for (int k = 0; k < 6 && visible; ++k) {
      if (!((ca | cb) & kPlaneBit[k])) continue;
      const float da = planeDistance(pa, k, ctx.cs), db = planeDistance(pb, k, ctx.cs);
      if (da < 0.0f && db < 0.0f) visible = false;
      else if (da < 0.0f) pa = pa + (da / (da - db)) * (pb - pa);
      else if (db < 0.0f) pb = pb + (db / (db - da)) * (pa - pb);
    }
    if (!visible) continue;
    const WindowVertex a = toWindow(pa, ctx.vp), b = toWindow(pb, ctx.vp);
    if (!a.ok || !b.ok) continue;
    out.outline.push_back({a.x, a.y, a.z, b.x, b.y, b.z, pid, 0xFF000000u, e.other});
  }
}

}  // namespace

int windowOrientation(const std::int64_t x[3], const std::int64_t y_down[3]) {
  const std::int64_t area =
      (x[1] - x[0]) * (y_down[2] - y_down[0]) - (y_down[1] - y_down[0]) * (x[2] - x[0]);
  // y-down flips the sign: negative y-down area is counter-clockwise in GL's y-up window.
  return area < 0 ? 1 : (area > 0 ? -1 : 0);
}

int eyeSpaceOrientation(const Scene& scene, PolygonId id, const Camera& camera) {
  const glm::vec3 dir = glm::normalize(camera.target - camera.eye);
  return polygonInfo(scene, id, camera, dir, false).eye_orientation;
}


struct PipelineScratch {
  std::vector<std::uint8_t> object_state;
  std::vector<glm::vec4> clip;
  std::vector<VertexOut> verts;
  std::vector<ChunkOut> parts;
};

void prepare(const Scene& scene, const Camera& camera, const RenderOptions& options,
             PreparedScene& out) {
  if (!out.scratch) out.scratch = std::make_shared<PipelineScratch>();
  PipelineScratch& scratch = *out.scratch;
  out.width = camera.width;
  out.height = camera.height;
  out.triangles.clear();
  out.lines.clear();
  out.points.clear();
  out.outline.clear();
  out.stats = Stats{};
  out.stats.polygons_in = scene.polygonCount();

  // Transform: world -> eye -> clip for every vertex of an object not culled by its bounds.
  auto t0 = Clock::now();
  const glm::mat4 mvp = camera.projection() * camera.view();
  std::vector<std::uint8_t>& object_state = scratch.object_state;
  object_state.assign(scene.objects.size(), 1);
  // No guard band: x/y are clipped at the viewport, as llvmpipe does (its draw module runs
  // with guard_band_xy off), so edges of clipped triangles snap exactly as Mesa's do.
  const ClipSetup cs{1.0f, 1.0f};
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    const Bounds& b = scene.objects[o].bounds;
    if (b.empty()) continue;
    unsigned all = ~0u, any = 0;
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 corner((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y,
                             (k & 4) ? b.hi.z : b.lo.z);
      const unsigned c = outcode(mvp * glm::vec4(corner, 1.0f), cs);
      all &= c;
      any |= c;
    }
    if (options.frustum_cull && (all & (kLeft | kRight | kBottom | kTop | kNear | kFar)))
      object_state[o] = 0;
    else
      object_state[o] = (any & kMustClip) ? 2 : 1;
  }
  const float w = static_cast<float>(camera.width), h = static_cast<float>(camera.height);
  const Viewport vp{w * 0.5f, w * 0.5f, -h * 0.5f, h * 0.5f};
  std::vector<glm::vec4>& clip = scratch.clip;
  std::vector<VertexOut>& verts = scratch.verts;
  clip.resize(scene.vertexCount());
  verts.resize(scene.vertexCount());
  tbb::parallel_for(std::size_t(0), scene.objects.size(), [&](std::size_t o) {
    if (object_state[o] == 0) return;
    const Object& obj = scene.objects[o];
    for (std::uint32_t v = obj.first_vertex; v < obj.first_vertex + obj.vertex_count; ++v) {
      const glm::vec3& p = scene.position(v);
      clip[v] = mvp * glm::vec4(p, 1.0f);
      VertexOut& out_v = verts[v];
      out_v.code = outcode(clip[v], cs);
      // Non-finite input, or finite input the transform took beyond float's range: such a
      // vertex is never projected (its polygons are dropped as degenerate).
      const glm::vec4& c = clip[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) ||
          !std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(c.w))
        out_v.code |= kNonFinite;
      if (!(out_v.code & (kMustClip | kNonFinite))) {
        out_v.w = toWindow(clip[v], vp);
        if (!out_v.w.ok) out_v.code |= kNonFinite;
      }
    }
  });
  out.stats.addStage("transform", msSince(t0));

  // Cull, clip, project and snap, in fixed chunks of polygons joined in order.
  t0 = Clock::now();
  Context ctx{scene, camera, options, mvp, glm::normalize(camera.target - camera.eye), cs,
              vp, clip, verts, object_state, {}, {}};
  for (const Material& m : scene.materials) {
    const std::uint32_t rgba = packColor(m.color, m.alpha);  // clamps, and NaN -> 0
    ctx.material_rgb.push_back(glm::vec3(rgba & 0xFF, (rgba >> 8) & 0xFF, (rgba >> 16) & 0xFF));
    ctx.material_alpha.push_back(rgba & 0xFF000000u);
  }
  const std::size_t n = scene.polygonCount();
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<ChunkOut>& parts = scratch.parts;
  parts.resize(chunks);
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    ChunkOut& part = parts[c];
    part.triangles.clear();
    part.lines.clear();
    part.points.clear();
    part.degenerate = part.culled_frustum = part.culled_backface = part.clipped = 0;
    part.clipped_away = part.triangles_in = 0;
    std::vector<Triangle> tris;
    ClipPolygon poly, tmp;
    const std::size_t end = std::min(n, (c + 1) * kChunk);
    std::size_t expected = 0;
    for (std::size_t id = c * kChunk; id < end; ++id) {
      const std::size_t k = scene.polygon(static_cast<PolygonId>(id)).size();
      expected += k >= 3 ? k - 2 : 0;
    }
    part.triangles.reserve(expected);
    for (std::size_t id = c * kChunk; id < end; ++id)
      processPolygon(ctx, static_cast<PolygonId>(id), part, tris, poly, tmp);
  });
  std::vector<std::size_t> offset(chunks + 1, 0);
  for (std::size_t c = 0; c < chunks; ++c) offset[c + 1] = offset[c] + parts[c].triangles.size();
  out.triangles.resize(offset[chunks]);
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    std::copy(parts[c].triangles.begin(), parts[c].triangles.end(), out.triangles.begin() + offset[c]);
  });
  for (ChunkOut& p : parts) {
    out.lines.insert(out.lines.end(), p.lines.begin(), p.lines.end());
    out.points.insert(out.points.end(), p.points.begin(), p.points.end());
    out.stats.degenerate_dropped += p.degenerate;
    out.stats.culled_frustum += p.culled_frustum;
    out.stats.culled_backface += p.culled_backface;
    out.stats.clipped += p.clipped;
    out.stats.clipped_away += p.clipped_away;
    out.stats.triangles_in += p.triangles_in;
  }
  out.stats.triangles_rasterized = out.triangles.size() + out.lines.size() + out.points.size();
  out.stats.addStage("cull+clip+project", msSince(t0));

  if (options.outline) {
    t0 = Clock::now();
    findOutline(ctx, out);
    out.stats.addStage("outline", msSince(t0));
  }
}

}  // namespace hsr::detail
