#pragma once
// The shared pipeline (docs/architecture.md): transform (model baked into the scene) -> eye ->
// clip, view-frustum culling of objects by their bounds, back-face culling, homogeneous clipping
// against the view volume, division by w, viewport mapping, and snapping of x,y to fixed
// point with 8 sub-pixel bits (as Mesa). Every visibility algorithm starts from its output,
// so all of them see exactly the same primitives.
//
// Two products: screen primitives (always), and on request clipped window-space polygons in
// double with their planes, for the object-precision algorithms.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "core/material.hpp"
#include "hsr/camera.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"
#include "geometry/polygon.hpp"
#include "raster/primitives.hpp"

namespace hsr::detail {

// A polygon clipped to the view volume, in window space: pixel-centre coordinates, y down,
// z window depth. Coordinates are the pipeline's own float window positions, so snapping them
// gives exactly the vertices of its screen triangles.
struct WindowPolygon {
  std::vector<glm::dvec3> vertices;  // in the polygon's own winding
  PolygonId id = kNoPolygon;
  std::uint32_t material = 0;  // index into Scene::materials
  std::uint32_t rgba = 0;      // shaded colour, as its screen triangles
  bool transparent = false;
  bool front = true;          // front-facing under the front-face rule
  glm::dvec4 eye_plane{0.0};  // a x + b y + c z + d = 0 in eye space; (a, b, c) is
                              // Newell's normal of the winding, not normalised
  DepthPlane depth{};         // the depth plane its screen triangles use
  std::uint32_t piece = 0;    // a non-planar polygon comes as its triangles
                              // (triangulatePolygon's order): which one this is
};

struct PipelineScratch;  // prepare()'s working memory, reused between calls

struct PreparedScene {
  int width = 0, height = 0;
  ScreenTriangles triangles;            // polygon-id order (submission order), FILL mode
  std::vector<ScreenLine> lines;        // LINE mode: visible polygon edges
  std::vector<ScreenLine> points;       // POINT mode: x1 == x0
  std::vector<ScreenLine> outline;      // silhouette edges, drawn over the fill
  std::vector<WindowPolygon> polygons;  // on request: clipped polygons, id order, FILL mode
  Stats stats;
  std::shared_ptr<PipelineScratch> scratch;
};

struct PrepareRequest {
  bool window_polygons = false;  // also fill PreparedScene::polygons
  bool samples = false;          // screen triangles' boxes reach every sub-pixel sample, and
                                 // triangles between pixel centres are kept (the A-buffer)
  bool triangles = true;         // the screen triangles too; off for callers that need the
                                 // window polygons alone (line drawings), whose stats then
                                 // count no triangles
};

// Fills `out`, reusing the memory it holds from an earlier call.
void prepare(const Scene& scene, const Camera& camera, const RenderOptions& options,
             const PrepareRequest& request, PreparedScene& out);
inline PreparedScene prepare(const Scene& scene, const Camera& camera, const RenderOptions& options,
                             const PrepareRequest& request = {}) {
  PreparedScene out;
  prepare(scene, camera, options, request, out);
  return out;
}

// Facing of one polygon by the notes' eye-space test: N . (eye - P) > 0 with N by the
// right-hand rule of the vertex order (Newell's normal) -> counter-clockwise as seen from the
// eye. Returns +1 (CCW seen from the eye), -1 (CW) or 0 (edge-on or degenerate).
int eyeSpaceOrientation(const Scene& scene, PolygonId id, const Camera& camera);

// The shaded colour prepare() gives polygon `id` (its material, lit by the headlight when
// options.shade), for an algorithm that finds a polygon without the pipeline's triangles (the
// ray caster, for a polygon hit between the snapped triangles' pixels).
std::uint32_t shadedColour(const Scene& scene, const Camera& camera, const RenderOptions& options,
                           PolygonId id);

// World -> homogeneous device coordinates (x, y in pixels with centres at integers, y down; z
// window depth; w the clip w, > 0 in front of the eye), as prepare() projects.
glm::dmat4 deviceFromWorld(const Camera& camera);

// The ray through pixel (x, y)'s centre (device coordinates: top row 0), as the ray caster
// casts it: in perspective from the eye to the far plane's point, t = near / far at the near
// plane and 1 at the far plane (a hit's eye depth is t * far); in parallel from the near
// plane's point to the far plane's, t from 0 to 1 (the window depth). Rays hit for
// tmin < t < tmax; tmax is one float step past 1, so the far plane is included, as clipping does.
struct PixelRay {
  glm::vec3 org, dir;
  float tmin, tmax;
};
class PixelRays {
 public:
  explicit PixelRays(const Camera& camera);
  PixelRay at(double x,
              double y) const;  // x, y: device coordinates (a pixel's centre is an integer)

 private:
  glm::dmat4 world_from_device_;
  glm::dvec3 eye_;
  bool ortho_;
  float tmin_;
};

// Whether the box [lo, hi] lies wholly outside one plane of the view frustum (in clip space:
// -w <= x, y, z <= w), for skipping a part of a tree (BSP, octree) the eye cannot see.
bool boxOutsideFrustum(const glm::dmat4& clip_from_world, const glm::dvec3& lo,
                       const glm::dvec3& hi);

// Whether the polygon with vertices `vi` lies in `plane` within float's precision: the
// pipeline's test (a non-planar polygon is drawn as its triangles, each with its own plane).
bool isPlanar(const Scene& scene, std::span<const std::uint32_t> vi, const Plane& plane);

}  // namespace hsr::detail
