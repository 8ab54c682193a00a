#pragma once
// The shared pipeline, as in DESIGN.md: transform (model baked into the scene) -> eye -> clip,
// view-frustum culling of objects by their bounds, back-face culling, homogeneous clipping
// against near/far and a guard band, division by w, viewport mapping, and snapping of x,y to
// fixed point with 8 sub-pixel bits (as Mesa). Every visibility algorithm starts from its
// output, so all of them see exactly the same triangles.

#include <cstdint>
#include <memory>
#include <vector>

#include "hsr/camera.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace hsr::detail {

inline constexpr int kSubpixelBits = 8;  // 8 sub-pixel bits, as Mesa's llvmpipe
inline constexpr int kSubpixelOne = 1 << kSubpixelBits;

// A triangle in window space. Coordinates are y-DOWN (row 0 = top row of the image, the
// layout of every buffer) and measured from pixel centres: pixel (i, j) is sampled at fixed
// point (i << 8, j << 8). Vertices are ordered so the doubled signed area is positive, i.e.
// every edge function is > 0 inside.
struct ScreenTriangle {
  std::int32_t x[3], y[3];  // 24.8 fixed point
  std::int16_t x0, y0, x1, y1;  // inclusive pixel bounding box, clamped to the viewport
  float xr, yr;             // float position of vertex 0 (pixel-centre coords), for depth
  float z0, dzdx, dzdy;     // depth plane: z(i, j) = z0 + dzdx*(i - xr) + dzdy*(j - yr)
  PolygonId id;
  std::uint32_t rgba;       // shaded colour, R in the low byte
  std::uint8_t front;       // 1 when front-facing under the current front-face rule
  std::uint8_t transparent; // 1 when alpha < 1 (drawn in a second, blended pass)
};

// A line segment or point in the same window space, float coordinates (pixel centres at
// integers), for polygon mode LINE/POINT and outline drawing.
struct ScreenLine {
  float x0, y0, z0, x1, y1, z1;
  PolygonId id;
  std::uint32_t rgba;
  PolygonId other = kNoPolygon;  // outline: the polygon on the other side of the edge
};

struct PipelineScratch;  // prepare()'s working memory, reused between calls

struct PreparedScene {
  int width = 0, height = 0;
  std::vector<ScreenTriangle> triangles;  // polygon-id order (submission order), FILL mode
  std::vector<ScreenLine> lines;          // LINE mode: visible polygon edges
  std::vector<ScreenLine> points;         // POINT mode: x1 == x0
  std::vector<ScreenLine> outline;        // silhouette edges, drawn over the fill
  Stats stats;
  std::shared_ptr<PipelineScratch> scratch;
};

// Fills `out`, reusing the memory it holds from an earlier call.
void prepare(const Scene& scene, const Camera& camera, const RenderOptions& options,
             PreparedScene& out);
inline PreparedScene prepare(const Scene& scene, const Camera& camera,
                             const RenderOptions& options) {
  PreparedScene out;
  prepare(scene, camera, options, out);
  return out;
}

// Facing of one polygon by the notes' eye-space test: N . (eye - P) > 0 with N by the right-hand
// rule of the vertex order (Newell's normal) -> counter-clockwise as seen from the eye.
// Returns +1 (CCW seen from the eye), -1 (CW) or 0 (edge-on or degenerate).
int eyeSpaceOrientation(const Scene& scene, PolygonId id, const Camera& camera);

// Facing of one window-space triangle by OpenGL's rule: the sign of its area in window
// coordinates (y up). +1 CCW, -1 CW, 0 zero area after snapping.
int windowOrientation(const std::int64_t x[3], const std::int64_t y_down[3]);

}  // namespace hsr::detail
