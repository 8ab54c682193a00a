#pragma once
// Polygon clipping.
//   - Homogeneous (clip space, before the divide by w), against the six planes of the view
//     volume: Sutherland-Hodgman, in Mesa's plane order and with its arithmetic, so parts
//     behind the eye are cut away (never inverted) and clipped vertices come out
//     bit-identical to llvmpipe's.
//   - 2D, against a half-plane a x + b y + c >= 0.

#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

namespace hsr::detail {

enum ClipBit : unsigned {
  kLeft = 1,
  kRight = 2,
  kBottom = 4,
  kTop = 8,
  kNear = 16,
  kFar = 32,  // view volume
  kGuardX0 = 64,
  kGuardX1 = 128,
  kGuardY0 = 256,
  kGuardY1 = 512,  // x/y clip band
};
inline constexpr unsigned kViewVolume = kLeft | kRight | kBottom | kTop | kNear | kFar;
inline constexpr unsigned kMustClip = kNear | kFar | kGuardX0 | kGuardX1 | kGuardY0 | kGuardY1;

// Where x and y are clipped, in NDC units: |x| <= gx w, |y| <= gy w. A guard band (g > 1)
// would leave more triangles unclipped; hsr clips at the viewport (g = 1) as llvmpipe does,
// so clipped edges snap exactly as Mesa's and snapped coordinates stay within the viewport.
struct ClipSetup {
  float gx = 1.0f, gy = 1.0f;
};

// The planes a clip-space point lies outside of.
inline unsigned outcode(const glm::vec4& v, const ClipSetup& cs) {
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

// The clip planes in Mesa's order (draw_pipe_clip: right, left, top, bottom, near, far) and
// the outcode bit of each.
inline constexpr int kClipPlanes = 6;
inline constexpr unsigned kPlaneBit[kClipPlanes] = {kGuardX1, kGuardX0, kGuardY1,
                                                    kGuardY0, kNear,    kFar};

// Signed distance of a clip-space point to clip plane k (>= 0 inside), with Mesa's arithmetic.
inline float planeDistance(const glm::vec4& v, int k, const ClipSetup& cs) {
  switch (k) {
    case 0:
      return cs.gx * v.w - v.x;  // right
    case 1:
      return cs.gx * v.w + v.x;  // left
    case 2:
      return cs.gy * v.w - v.y;  // top
    case 3:
      return cs.gy * v.w + v.y;  // bottom
    case 4:
      return v.z + v.w;  // near
    default:
      return v.w - v.z;  // far
  }
}

// Where the edge from `near_p` (distance dnear to plane k) to `far_p` (dfar) crosses plane k.
glm::vec4 clipIntersection(const glm::vec4& near_p, const glm::vec4& far_p, float dnear, float dfar,
                           int k, const ClipSetup& cs);

// A clip-space vertex, with whether the edge leaving it is an original polygon edge (GL's
// edge flag: edges made by clipping are not drawn in LINE mode) and whether it is an input
// vertex (POINT mode draws only those).
struct ClipVertex {
  glm::vec4 p;
  bool edge = true;
  bool original = true;
};
using ClipPolygon = std::vector<ClipVertex>;

// Clips `poly` in place against the planes whose bits are set in `planes`; `tmp` is working
// memory. A polygon left with fewer than 3 vertices is entirely outside.
void clipPolygon(ClipPolygon& poly, unsigned planes, const ClipSetup& cs, ClipPolygon& tmp);

// Sutherland-Hodgman in 2D: the part of `poly` where a x + b y + c >= 0, in place.
void clipToHalfPlane(std::vector<glm::dvec2>& poly, double a, double b, double c);

}  // namespace hsr::detail
