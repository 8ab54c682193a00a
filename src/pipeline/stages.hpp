#pragma once
// What the pipeline's stages share while prepare() runs them (internal to src/pipeline/).
// One file per stage: transform.cpp (objects and vertices to clip space), shade.cpp (facing,
// shading, the depth plane), clip.cpp (homogeneous clipping of triangles and polygons),
// project.cpp (divide, viewport, snap, screen triangles), outline.cpp (silhouette edges),
// polygons.cpp (the window-polygon product); prepare.cpp runs them.

#include <cstdint>
#include <span>
#include <vector>

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
struct VertexOut {
  WindowVertex w;  // valid when !(code & (kMustClip | kNonFinite))
  unsigned code;   // outcode, plus kNonFinite
};

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
  int box_margin = 0;                             // makeScreenTriangle's margin (PrepareRequest::samples)
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
// The notes' facing test N . (eye - P) > 0: +1 CCW seen from the eye, -1 CW, 0 edge-on.
int eyeOrientation(const glm::dvec3& normal, const glm::dvec3& p0, const Camera& camera,
                   const glm::dvec3& view_dir);

// Which facings survive the cull mode; `front` is the polygon's facing under the rule.
bool culled(CullMode mode, bool front);
// The facing rule: OpenGL's window-area orientation of the snapped triangle, or the notes'
// eye-space test.
bool isFront(const Context& ctx, int window_orientation, int eye_orientation);

// ---- the output of one chunk of polygons

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
  void push(const ScreenTriangle& t) {
    if (!spilled_ && count_ < capacity_) {
      slot_[count_++] = t;
      return;
    }
    if (!spilled_) {
      spill_.assign(slot_, slot_ + count_);
      spilled_ = true;
    }
    spill_.push_back(t);
  }
  std::span<const ScreenTriangle> made() const {
    return spilled_ ? std::span<const ScreenTriangle>(spill_) : std::span<const ScreenTriangle>(slot_, count_);
  }

 private:
  ScreenTriangle* slot_ = nullptr;
  std::size_t capacity_ = 0, count_ = 0;
  bool spilled_ = false;
  ScreenTriangles spill_;
};

struct ChunkOut {
  TriangleSink triangles;
  std::vector<ScreenLine> lines, points;
  std::vector<WindowPolygon> polygons;
  std::vector<WindowVertex> window_scratch;  // a clipped polygon's projected vertices
  ClipPolygon poly, tmp;                     // clipping's working memory
  Stats counts;                              // where every triangle went
  void reset();
};

// ---- project (continued): a snapped triangle through facing and culling into the output

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
