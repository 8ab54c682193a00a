// What the two ray casters share (raycast_hits.hpp).

#include "visibility/raycast_hits.hpp"

#include <cmath>

#include "core/frame.hpp"
#include "raster/depth.hpp"
#include "raster/fragment.hpp"
#include "raster/lines.hpp"
#include "raster/triangle.hpp"

namespace hsr::detail {

bool raySidesFor(const RenderOptions& o, HitSides* sides) {
  const bool ccw_front = o.front_face == FrontFace::Ccw;
  switch (o.cull) {
    case CullMode::None:
      *sides = HitSides::kBoth;
      return true;
    case CullMode::Back:  // only front faces remain
      *sides = ccw_front ? HitSides::kCounterClockwiseOnly : HitSides::kClockwiseOnly;
      return true;
    case CullMode::Front:
      *sides = ccw_front ? HitSides::kClockwiseOnly : HitSides::kCounterClockwiseOnly;
      return true;
    case CullMode::FrontAndBack:
      break;
  }
  return false;  // nothing can be hit
}

float rayBandLimit(const void* context, float t) {
  const RayDepthBand& b = *static_cast<const RayDepthBand*>(context);
  const double z = b.ortho ? t : (t * b.far - b.near) / (t * (b.far - b.near));
  float z_end = static_cast<float>(z);
  for (int i = 0; i < kRayTieSteps; ++i) z_end = std::nextafter(z_end, 2.0f);
  if (b.ortho) return std::max(t, z_end);
  const double denominator = b.far - static_cast<double>(z_end) * (b.far - b.near);
  if (!(denominator > 0.0)) return INFINITY;
  return std::max(t, std::nextafter(static_cast<float>(b.near / denominator), INFINITY));
}

void PolygonLooks::build(const Scene& scene, const ScreenTriangles& tris) {
  plane_.resize(scene.polygonCount());
  colour_.resize(scene.polygonCount());
  state_.assign(scene.polygonCount(), 0);
  for (const ScreenTriangle& t : tris) {
    if (t.id >= state_.size()) continue;
    std::uint8_t& st = state_[t.id];
    if (!(st & kKnown)) {
      st = kKnown | kOnePlane, plane_[t.id] = t.depth, colour_[t.id] = t.rgba;
    } else if (plane_[t.id].dzdx != t.depth.dzdx || plane_[t.id].dzdy != t.depth.dzdy ||
               plane_[t.id].z0 != t.depth.z0) {
      st &= static_cast<std::uint8_t>(~kOnePlane);  // a non-planar polygon: a plane per triangle
    }
  }
}

bool PolygonLooks::settle(const AlgorithmInput& in, const FrameView& fb, int x, int y,
                          const std::vector<PolygonId>& polygon_of, const BvhCandidates& hits,
                          std::uint64_t* unshaded) const {
  if (hits.count == 0) return false;
  const Camera& cam = in.camera;
  const double near = cam.near, far = cam.far;
  // Of the hits, the nearest fragment depth wins; of equal floats, the polygon submitted first
  const std::size_t k = fb.index(x, y);
  PolygonId id = kNoPolygon;
  float z = INFINITY;
  for (int i = 0; i < hits.count; ++i) {
    const BvhHit& h = hits.hit[i];
    const PolygonId p = polygon_of[h.triangle];
    const double t = h.t;
    const float zi =
        (state_[p] & kOnePlane)
            ? fragmentDepth(plane_[p], x, y)
            : static_cast<float>(cam.ortho ? t : (t * far - near) / (t * (far - near)));
    if (zi < z || (zi == z && p < id)) z = zi, id = p;
  }
  if (!(z < fb.depth[k])) return false;  // LESS against the cleared depth
  fb.depth[k] = z;
  fb.ids[k] = id;
  if (state_[id] & kKnown) {
    fb.rgba[k] = colour_[id];
  } else {  // no snapped triangle of it made a pixel: shaded as the pipeline would
    fb.rgba[k] = shadedColour(in.scene, cam, in.options, id);
    ++*unshaded;
  }
  fb.overdraw[k] = 1;
  return true;
}

void rayFinishFrame(const AlgorithmInput& in, const FrameView& fb, FragmentCounts& counts) {
  const PixelBox viewport{0, 0, fb.width - 1, fb.height - 1};
  const RasterPath path = rasterPath(DepthFunc::Less);
  for (const ScreenTriangle& t : in.prepared.triangles)
    if (t.transparent()) rasterTriangle<DepthFunc::Less>(t, viewport, fb, true, path, counts);
  for (const ScreenLine& o : in.prepared.outline) drawOutlinePen(o, viewport, fb);
}

}  // namespace hsr::detail
