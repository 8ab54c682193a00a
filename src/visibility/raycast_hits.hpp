#pragma once
// What the two ray casters share: raycast.cpp (the notes' loop, one ray and one triangle at a
// time) and raycast_fast.cpp (the same answers through a bounding volume hierarchy). Which
// sides a ray may hit, the band of near-ties behind the nearest hit, and how a pixel's hits
// become its fragment: so the two cannot settle a pixel differently.
//
// Tests: tests/cross/textbook_test.cpp pins the two casters together bit for bit.

#include <cstdint>
#include <vector>

#include "geometry/bvh.hpp"
#include "raster/fragment.hpp"
#include "visibility/algorithm.hpp"

namespace hsr::detail {

// The sides of a triangle a ray from the eye may hit under the cull mode and front-face rule
// (the notes' N . V test, as seen from the eye); false where nothing can be hit.
bool raySidesFor(const RenderOptions& options, HitSides* sides);

// Hits whose window depths lie within kRayTieSteps float steps of the nearest one's are settled
// as the z-buffer settles them: by their float depth (THE fragment depth, raster/depth.hpp),
// equal floats going to the polygon submitted first. Far from the eye a float step of window
// depth spans a long way in the scene (2% of the distance on a real model with near 0.05 and
// far 2236), and there the z-buffer cannot tell two surfaces apart: neither can a ray, then.
inline constexpr int kRayTieSteps = 4;

struct RayDepthBand {
  bool ortho;
  double near, far;
};
// The end of the band of ties behind a hit at t: the t whose window depth is kRayTieSteps float
// steps beyond the hit's. `context` is a RayDepthBand (the hierarchy's BvhBandLimit).
float rayBandLimit(const void* context, float t);

// What the pipeline made of each polygon: its colour and depth plane, taken from its screen
// triangles (a polygon none of whose triangles reached the screen is shaded when hit).
class PolygonLooks {
 public:
  void build(const Scene& scene, const ScreenTriangles& tris);
  // The pixel's fragment from its hits (the nearest and its ties, nearest first): of them the
  // nearest fragment depth wins, of equal floats the polygon submitted first; written where it
  // is nearer than the cleared depth. Returns whether it was written.
  bool settle(const AlgorithmInput& in, const FrameView& fb, int x, int y,
              const std::vector<PolygonId>& polygon_of, const BvhCandidates& hits,
              std::uint64_t* unshaded) const;
  std::size_t bytes() const {
    return plane_.capacity() * sizeof(DepthPlane) + colour_.capacity() * 4 + state_.capacity();
  }

 private:
  static constexpr std::uint8_t kKnown = 1, kOnePlane = 2;
  std::vector<DepthPlane> plane_;
  std::vector<std::uint32_t> colour_;
  std::vector<std::uint8_t> state_;  // kKnown, kOnePlane bits
};

// After the opaque picture: see-through polygons blended over it in submission order and the
// outline pen over all, as the z-buffer draws them. Adds the fragments to `counts`.
void rayFinishFrame(const AlgorithmInput& in, const FrameView& fb, FragmentCounts& counts);

}  // namespace hsr::detail
