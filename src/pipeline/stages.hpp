#pragma once
// What the pipeline's stages share while prepare() runs them (internal to src/pipeline/).
// One file per stage: transform.cpp (objects and vertices to clip space), shade.cpp (facing,
// shading, the depth plane), clip.cpp (homogeneous clipping of triangles and polygons),
// project.cpp (divide, viewport, snap, screen triangles), outline.cpp (silhouette edges),
// polygons.cpp (the window-polygon product); prepare.cpp runs them.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "geometry/clip.hpp"
#include "geometry/polygon.hpp"
#include "pipeline/pipeline.hpp"

namespace hsr::detail {

// ---- project: divide by w, viewport, snap

struct Viewport {
  float sx, tx, sy, ty;  // window = ndc * s + t (y down)
};
Viewport viewportOf(const Camera& camera);

struct WindowVertex {
  float x, y, z;        // float window coords, pixel centres at integers, y down
  std::int64_t fx, fy;  // snapped to 24.8 fixed point
  bool ok;              // finite and within 2^22 pixels (false: drop the primitive)
};
WindowVertex toWindow(const glm::vec4& clip, const Viewport& vp);

// ---- transform: objects culled by their bounds, vertices to clip space

inline constexpr unsigned kNonFinite = 1u << 16;  // beside the outcode bits
// A transformed vertex: its outcode and, for a vertex inside the view volume, its window
// position as toWindow gives it, kept in 24 bytes (the array is rewritten every frame: 3
// million vertices for a soup of a million triangles).
struct VertexOut {
  float x, y, z;        // valid when !(code & (kMustClip | kNonFinite))
  std::int32_t fx, fy;  // snapped; toWindow bounds them by 2^30
  unsigned code;        // outcode, plus kNonFinite
  WindowVertex window() const { return {x, y, z, fx, fy, true}; }
};
static_assert(sizeof(VertexOut) == 24);

// Per-vertex arrays of a million entries and more, rewritten every frame: no zero fill on
// resize, huge pages when large (core/large_pages.hpp).
template <class T>
using FrameArray = std::vector<T, DefaultInitAllocator<T, LargePageAllocator<T>>>;
using ClipVertices = FrameArray<glm::vec4>;
using VertexOuts = FrameArray<VertexOut>;

enum ObjectState : std::uint8_t { kObjectCulled = 0, kObjectInside = 1, kObjectCrosses = 2 };
void cullObjects(const Scene& scene, const glm::mat4& mvp, const ClipSetup& cs, bool frustum_cull,
                 std::vector<std::uint8_t>& state);
void transformVertices(const Scene& scene, const glm::mat4& mvp, const ClipSetup& cs,
                       const Viewport& vp, const std::vector<std::uint8_t>& object_state,
                       ClipVertices& clip, VertexOuts& verts);
// The vertices [first, end) of one object, one at a time (the readable sibling), and four at a
// time with SSE2 (what transformVertices runs where it is built): the same IEEE operations in
// the same order, so the same clip positions, outcodes and window positions, bit for bit
// (tests/pipeline/transform_test.cpp). A vertex's window fields are written, and equal, where
// its code has neither kMustClip nor kNonFinite.
void transformVertexRange(const Scene& scene, const glm::mat4& mvp, const ClipSetup& cs,
                          const Viewport& vp, std::uint32_t first, std::uint32_t end,
                          glm::vec4* clip, VertexOut* verts);
#if defined(__SSE2__) && !defined(HSR_NO_SIMD)
void transformVertexRangeSse2(const Scene& scene, const glm::mat4& mvp, const ClipSetup& cs,
                              const Viewport& vp, std::uint32_t first, std::uint32_t end,
                              glm::vec4* clip, VertexOut* verts);
#endif

// ---- everything a stage may read

struct Context {
  const Scene& scene;
  const Camera& camera;
  const RenderOptions& options;
  glm::mat4 mvp;  // world -> clip, as the vertices are transformed (float)
  ClipSetup cs;
  Viewport vp;
  glm::dvec3 view_dir;                            // unit, eye -> target
  glm::dmat4 device_plane_from_world_plane;       // planes: world -> device (depth planes)
  glm::dmat4 device_from_world;                   // points: world -> homogeneous device coordinates
  glm::dmat4 eye_from_world;                      // points: world -> eye
  const ClipVertices& clip;                       // clip-space vertex positions
  const VertexOuts& verts;                        // per-vertex outcodes and window positions
  const std::vector<std::uint8_t>& object_state;  // ObjectState per object
  std::vector<glm::vec3> material_rgb;            // per material: rgb clamped to [0,1], NaN 0
  std::vector<std::uint32_t> material_alpha;      // per material: alpha byte << 24
                                                  // (both: the default material's last)
  int box_margin = 0;  // makeScreenTriangle's margin (PrepareRequest::samples)
};

// ---- shade: facing, colour and depth plane of a polygon

struct PolygonInfo {
  bool degenerate = true;   // zero area or non-finite: dropped
  int eye_orientation = 0;  // +1 CCW seen from the eye, -1 CW, 0 edge-on
  std::uint32_t rgba = 0;
  bool transparent = false;
  bool planar = true;  // false: each triangle gets the plane of its own vertices
  // The vertices whose plane is the depth plane: the polygon's, or (own_triangle set) one
  // triangle of a non-planar polygon.
  std::span<const std::uint32_t> vertices;
  std::uint32_t triangle[3] = {0, 0, 0};
  bool own_triangle = false;
  bool depth_known = false;  // computed lazily: only for what is drawn
  DepthPlane depth{};
};
// The polygon `id` with the given (absolute) vertex indices.
PolygonInfo describePolygon(const Context& ctx, PolygonId id, std::span<const std::uint32_t> vi);

// info's depth plane (THE depth, raster/depth.hpp), computed on first use, the same whichever
// path asks: for a triangle wholly inside the view volume, the plane through its three
// projected vertices (the notes' A, B, C by a cross product in device coordinates), taken from
// its topmost vertex so that any rotation or reversal of it gives the same bits; otherwise
// the polygon's canonical world-space plane (geometry/polygon.hpp) carried into device space.
const DepthPlane& depthPlaneOf(const Context& ctx, PolygonInfo& info);
// The same polygon with the plane of one of its triangles (a non-planar polygon's triangle).
PolygonInfo forTriangle(const PolygonInfo& polygon, const std::uint32_t (&triangle)[3]);

// Normal by the right-hand rule: a cross product for a triangle, Newell's method for a larger
// polygon (even a non-planar one).
glm::dvec3 polygonNormal(const Scene& scene, std::span<const std::uint32_t> vi);
// A triangle's: (v1 - v0) x (v2 - v0) in double.
inline glm::dvec3 triangleNormal(const Scene& scene, std::uint32_t v0, std::uint32_t v1,
                                 std::uint32_t v2) {
  const glm::dvec3 p0(scene.position(v0));
  return glm::cross(glm::dvec3(scene.position(v1)) - p0, glm::dvec3(scene.position(v2)) - p0);
}
// The notes' facing test N . (eye - P) > 0: +1 CCW seen from the eye, -1 CW, 0 edge-on.
inline int eyeOrientation(const glm::dvec3& normal, const glm::dvec3& p0, const Camera& camera,
                          const glm::dvec3& view_dir) {
  // V = eye - P (the reversed view direction for a parallel projection).
  const glm::dvec3 v = camera.ortho ? -view_dir : glm::dvec3(camera.eye) - p0;
  const double d = glm::dot(normal, v);
  return d > 0.0 ? 1 : (d < 0.0 ? -1 : 0);
}

// Which facings survive the cull mode; `front` is the polygon's facing under the rule.
inline bool culled(CullMode mode, bool front) {
  switch (mode) {
    case CullMode::None:
      return false;
    case CullMode::Back:
      return !front;
    case CullMode::Front:
      return front;
    case CullMode::FrontAndBack:
      return true;
  }
  return false;
}
// The facing rule: OpenGL's window-area orientation of the snapped triangle, or the notes'
// eye-space test.
inline bool isFront(const Context& ctx, int window_orientation, int eye_orientation) {
  const bool ccw_front = ctx.options.front_face == FrontFace::Ccw;
  return ctx.options.facing_test == FacingTest::WindowArea ? (window_orientation > 0) == ccw_front
                                                           : (eye_orientation > 0) == ccw_front;
}

// Shaded colour: rgb in [0, 1] scaled by the Lambert factor in [0, 1], each channel rounded
// half up to a byte.
inline std::uint32_t shadeRgba(const glm::vec3& rgb, std::uint32_t alpha_bits, float lambert) {
  auto q = [&](float c) { return static_cast<std::uint32_t>(c * lambert * 255.0f + 0.5f); };
  return q(rgb.r) | (q(rgb.g) << 8) | (q(rgb.b) << 16) | alpha_bits;
}

// Headlight Lambert, two-sided: light along the view axis, 20% ambient (1 when not shading).
// First the factor from the cosine |N . L| / |N| (computed lane-wise by ShadeBatch, or below).
inline float lambertOfCosine(double cosine) {
  // Any overflow (inf/inf) or 0/0 reads as facing the light.
  const float lambert = cosine >= 0.0 && cosine <= 1.0 ? static_cast<float>(cosine) : 1.0f;
  return 0.2f + 0.8f * lambert;
}
inline float lambertOf(const RenderOptions& options, const glm::dvec3& n, double len2,
                       const glm::dvec3& view_dir) {
  if (!options.shade) return 1.0f;
  return lambertOfCosine(std::abs(glm::dot(n, view_dir)) / std::sqrt(len2));
}

// Which of three vertices (with float x, y members) is the topmost, then leftmost one.
template <class Vertex>
inline int topmostVertex(const Vertex* const w[3]) {
  int first = 0;
  for (int k = 1; k < 3; ++k)
    if (w[k]->y < w[first]->y || (w[k]->y == w[first]->y && w[k]->x < w[first]->x)) first = k;
  return first;
}
// The plane through three projected vertices, from the topmost (then leftmost) one in the
// given winding. Reversing the winding negates the determinant and both numerators exactly,
// so the quotients are the same bits.
inline bool windowPlane(const WindowVertex* w[3], DepthPlane* out) {
  const int first = topmostVertex(w);
  const WindowVertex& a = *w[first];
  const WindowVertex& b = *w[(first + 1) % 3];
  const WindowVertex& c = *w[(first + 2) % 3];
  const double dx1 = double(b.x) - a.x, dy1 = double(b.y) - a.y, dz1 = double(b.z) - a.z;
  const double dx2 = double(c.x) - a.x, dy2 = double(c.y) - a.y, dz2 = double(c.z) - a.z;
  // The normal (A, B, C) = (b - a) x (c - a); then -A/C, -B/C, and the plane at pixel (0, 0).
  const double nx = dy1 * dz2 - dz1 * dy2, ny = dz1 * dx2 - dx1 * dz2, nz = dx1 * dy2 - dy1 * dx2;
  return depthPlaneFromDevicePlane(nx, ny, nz, -(nx * a.x + ny * a.y + nz * a.z), out);
}

// The depth plane of a triangle whose vertices are all inside the view volume: the plane
// through its projected vertices, or, for one seen edge-on, its nearest vertex's depth.
inline DepthPlane insideTrianglePlane(const VertexOut& a, const VertexOut& b, const VertexOut& c) {
  const WindowVertex w[3] = {a.window(), b.window(), c.window()};
  const WindowVertex* pw[3] = {&w[0], &w[1], &w[2]};
  DepthPlane plane;
  if (!windowPlane(pw, &plane)) plane = flatDepthPlane(std::min({a.z, b.z, c.z}));
  return plane;
}

// A polygon's normal is usable (not zero, not overflowed) when its squared length is.
inline bool usableNormal(double len2) { return len2 > 0.0 && std::isfinite(len2); }

// Polygon id's shaded colour with the given Lambert factor: its material's rgb and alpha (the
// last entries, the default material's, for a polygon that names none).
inline std::uint32_t polygonRgbaLit(const Context& ctx, PolygonId id, float lambert) {
  const std::size_t m = std::min<std::size_t>(ctx.scene.material(id), ctx.material_rgb.size() - 1);
  return shadeRgba(ctx.material_rgb[m], ctx.material_alpha[m], lambert);
}
// ... and with the Lambert factor of its normal n (squared length len2), as describePolygon
// and the fast triangle path (through ShadeBatch) both give it.
inline std::uint32_t polygonRgba(const Context& ctx, PolygonId id, const glm::dvec3& n,
                                 double len2) {
  return polygonRgbaLit(ctx, id, lambertOf(ctx.options, n, len2, ctx.view_dir));
}

// ---- the output of one chunk of polygons

// Stores a triangle with streaming stores where the processor has them (a whole cache line,
// not read first and kept out of the cache): a million triangles are 64 MiB, read again only
// after the whole stage. The caller ends its writes with finishStreaming().
// The four 16-byte stores are built from the fields (in registers where the triangle was just
// made), not loaded back from a copy in memory: that copy's narrower stores cannot be
// forwarded to a 16-byte load, which then waits for them to reach the cache.
inline void streamTriangle(ScreenTriangle* dst, const ScreenTriangle& t) {
#if defined(__SSE2__)
  static_assert(offsetof(ScreenTriangle, x0) == 24 && offsetof(ScreenTriangle, depth) == 32 &&
                offsetof(ScreenTriangle, id) == 56 && offsetof(ScreenTriangle, rgba) == 60);
  if ((reinterpret_cast<std::uintptr_t>(dst) & 15) == 0) {
    auto pair = [](std::int16_t lo, std::int16_t hi) {
      return static_cast<int>(static_cast<std::uint16_t>(lo) |
                              (static_cast<std::uint32_t>(static_cast<std::uint16_t>(hi)) << 16));
    };
    auto* to = reinterpret_cast<__m128i*>(dst);
    _mm_stream_si128(to, _mm_setr_epi32(t.x[0], t.x[1], t.x[2], t.y[0]));
    _mm_stream_si128(to + 1, _mm_setr_epi32(t.y[1], t.y[2], pair(t.x0, t.y0), pair(t.x1, t.y1)));
    _mm_stream_si128(to + 2, _mm_castpd_si128(_mm_setr_pd(t.depth.dzdx, t.depth.dzdy)));
    _mm_stream_si128(to + 3, _mm_unpacklo_epi64(_mm_castpd_si128(_mm_set_sd(t.depth.z0)),
                                                _mm_setr_epi32(static_cast<int>(t.id),
                                                               static_cast<int>(t.rgba), 0, 0)));
    return;
  }
#endif
  *dst = t;
}
// Orders the streaming stores before whatever the thread does next (another thread reads them).
inline void finishStreaming() {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

// Where a chunk's screen triangles go: its own slot of the pipeline's output, with room for as
// many triangles as the chunk's polygons have, or, once clipping makes more than that, a
// vector of its own that takes over (what the slot held first, then the rest).
class TriangleSink {
 public:
  void reset(ScreenTriangle* slot, std::size_t capacity) {
    slot_ = slot;
    capacity_ = capacity;
    count_ = 0;
    spilled_ = false;
    spill_.clear();
  }
  [[gnu::always_inline]] void push(const ScreenTriangle& t) {
    if (!spilled_ && count_ < capacity_) [[likely]] {
      streamTriangle(slot_ + count_++, t);
      return;
    }
    spill(t);
  }
  std::span<const ScreenTriangle> made() const {
    return spilled_ ? std::span<const ScreenTriangle>(spill_)
                    : std::span<const ScreenTriangle>(slot_, count_);
  }

 private:
  [[gnu::noinline]] void spill(const ScreenTriangle& t) {
    if (!spilled_) {
      spill_.assign(slot_, slot_ + count_);
      spilled_ = true;
    }
    spill_.push_back(t);
  }
  ScreenTriangle* slot_ = nullptr;
  std::size_t capacity_ = 0, count_ = 0;
  bool spilled_ = false;
  ScreenTriangles spill_;
};

// ---- shade, four triangles at a time

// The lane-wise part of finishing four triangles: for each lane, the plane through its window
// vertices a, b, c (a the topmost, as windowPlane orders them) and the cosine |N . L| / |N| of
// its normal with the light. The same IEEE double operations in the same order as windowPlane
// and lambertOf, so the same bits (tests/pipeline/shade_batch_test.cpp). `ok` is false where
// windowPlane would fail (a triangle seen edge-on, or too steep).
struct ShadeLanes {
  static constexpr int kLanes = 4;
  alignas(16) double ax[kLanes], ay[kLanes], az[kLanes];
  alignas(16) double bx[kLanes], by[kLanes], bz[kLanes];
  alignas(16) double cx[kLanes], cy[kLanes], cz[kLanes];
  alignas(16) double nx[kLanes], ny[kLanes], nz[kLanes], len2[kLanes];
};
struct ShadedLanes {
  alignas(16) double dzdx[ShadeLanes::kLanes], dzdy[ShadeLanes::kLanes], z0[ShadeLanes::kLanes];
  alignas(16) double cosine[ShadeLanes::kLanes];
  bool ok[ShadeLanes::kLanes];
};
// One lane at a time through windowPlane (the readable reference) ...
void shadeLanesScalar(const ShadeLanes& in, const glm::dvec3& light, ShadedLanes& out);
#if defined(__SSE2__) && !defined(HSR_NO_SIMD)
// ... two lanes per SSE2 operation ...
void shadeLanesSse2(const ShadeLanes& in, const glm::dvec3& light, ShadedLanes& out);
#endif
#if defined(__x86_64__) && !defined(HSR_NO_SIMD)
// ... and four per AVX operation, where the processor has AVX2 (shadeLanesAvx2Available).
void shadeLanesAvx2(const ShadeLanes& in, const glm::dvec3& light, ShadedLanes& out);
bool shadeLanesAvx2Available();
#endif
// The widest of them this processor runs (what ShadeBatch uses).
void shadeLanes(const ShadeLanes& in, const glm::dvec3& light, ShadedLanes& out);

// Triangles of the fast path that were kept wait here, four at a time, for their depth planes
// and colours (ShadeLanes: three divisions, a square root and one more division per triangle,
// whose long latencies one triangle at a time leave the processor waiting on), and then go to
// the sink in the order they came. Whatever else writes to the sink flushes the batch first.
class ShadeBatch {
 public:
  void begin(const Context& ctx) {
    ctx_ = &ctx;
    count_ = 0;
  }
  // Where the next triangle is made (in place: copying a triangle just written field by
  // field would wait for those stores to reach the cache).
  ScreenTriangle& slot() { return waiting_[count_].t; }
  // Adds the triangle made in slot(), with its vertices, box and id set; a, b, c are its window
  // vertices in any rotation.
  void add(const VertexOut& a, const VertexOut& b, const VertexOut& c, const glm::dvec3& n,
           double len2, TriangleSink& sink) {
    const VertexOut* w[3] = {&a, &b, &c};
    const int first = topmostVertex(w);
    const VertexOut& p = *w[first];
    const VertexOut& q = *w[(first + 1) % 3];
    const VertexOut& r = *w[(first + 2) % 3];
    const int i = count_;
    lanes_.ax[i] = p.x, lanes_.ay[i] = p.y, lanes_.az[i] = p.z;
    lanes_.bx[i] = q.x, lanes_.by[i] = q.y, lanes_.bz[i] = q.z;
    lanes_.cx[i] = r.x, lanes_.cy[i] = r.y, lanes_.cz[i] = r.z;
    lanes_.nx[i] = n.x, lanes_.ny[i] = n.y, lanes_.nz[i] = n.z, lanes_.len2[i] = len2;
    waiting_[i].min_z = std::min({a.z, b.z, c.z});
    if (++count_ == ShadeLanes::kLanes) flush(sink);
  }
  void flush(TriangleSink& sink);

 private:
  struct Waiting {
    ScreenTriangle t;
    float min_z;  // the flat plane's depth, for a triangle seen edge-on
  };
  const Context* ctx_ = nullptr;
  int count_ = 0;
  ShadeLanes lanes_;
  Waiting waiting_[ShadeLanes::kLanes];
};

struct ChunkOut {
  TriangleSink triangles;
  ShadeBatch batch;  // the fast path's kept triangles on their way to `triangles`
  std::vector<ScreenLine> lines, points;
  std::vector<WindowPolygon> polygons;
  std::vector<WindowVertex> window_scratch;  // a clipped polygon's projected vertices
  ClipPolygon poly, tmp;                     // clipping's working memory
  Stats counts;                              // where every triangle went
  void reset();
};

// ---- project (continued): a snapped triangle through facing and culling into the output

// Facing, culling and the screen triangle of one snapped triangle, in that order (each drop
// counted where it happens); its colour and depth plane are made only when it is kept.
// The triangle is made in place in `slot()`, and `emit(t)` gives it (vertices, box and id set)
// its depth plane and colour and stores it.
template <class Slot, class Emit>
inline void cullAndEmitWith(const Context& ctx, const std::int64_t (&fx)[3],
                            const std::int64_t (&fy)[3], PolygonId id, int eye_orientation,
                            Slot slot, Emit emit, ChunkOut& out) {
  const int orientation = windowOrientation(fx, fy);
  if (orientation == 0) {  // zero area after snapping: draws nothing, as in GL
    out.counts.zero_area++;
    return;
  }
  if (culled(ctx.options.cull, isFront(ctx, orientation, eye_orientation))) {
    out.counts.culled_backface++;
    return;
  }
  ScreenTriangle& t = slot();
  const TriangleFate fate = makeScreenTriangle(fx, fy, orientation, ctx.camera.width,
                                               ctx.camera.height, DepthPlane{}, &t, ctx.box_margin);
  if (fate == TriangleFate::kMissesPixelCentres) {
    out.counts.missed_pixel_centres++;
    return;
  }
  t.id = id;
  emit(t);
  out.counts.triangles_rasterized++;
}
// The same for a triangle of the polygon `info` describes (the depth plane computed once per
// polygon, for what is drawn).
void cullAndEmit(const Context& ctx, const WindowVertex (&w)[3], PolygonId id, PolygonInfo& info,
                 ChunkOut& out);

// ---- clip: one triangle of a polygon (clipped if it must be, then cullAndEmit per piece);
// one polygon whole, for LINE/POINT mode and the window-polygon product

void clipAndEmitTriangle(const Context& ctx, const glm::vec4 (&c)[3], PolygonId id,
                         PolygonInfo& info, ChunkOut& out);
// Clips the polygon with these vertex indices, whole, into out.poly.
enum class WholeClip {
  kInside,      // untouched
  kClipped,     // cut by some plane; out.poly holds what is left
  kOutside,     // entirely outside one plane
  kClippedAway  // cut to nothing
};
WholeClip clipWholePolygon(const Context& ctx, std::span<const std::uint32_t> vi, ChunkOut& out);

// ---- polygons: the window polygon of out.poly (clipped), appended to out.polygons

void emitWindowPolygon(const Context& ctx, PolygonId id, std::span<const std::uint32_t> vi,
                       PolygonInfo& info, ChunkOut& out);

// ---- outline: silhouette and border edges

void findOutline(const Context& ctx, PreparedScene& out);

}  // namespace hsr::detail
