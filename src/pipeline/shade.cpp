// Facing, shading and the depth plane of a polygon: everything the pipeline decides once per
// polygon, the same for the fast triangle path and the general one.
//   - Facing: the notes' N . (eye - P) with N by the right-hand rule (a cross product for a
//     triangle, Newell's method for larger polygons); OpenGL's window-area rule is applied
//     per snapped triangle (isFront).
//   - Shading: a headlight, one light direction per view (along the view axis), two-sided
//     Lambert with 20% ambient, so a flat face has one colour however it is triangulated.
//   - Depth plane: the polygon's plane carried into device space (raster/depth.hpp), the
//     notes' A x + B y + C z + D = 0 "in device coordinates".
// The per-triangle pieces (facing rule, Lambert, colour, the plane of three projected
// vertices) are inline in stages.hpp, so that the fast triangle path compiles as one piece.

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "pipeline/stages.hpp"

namespace hsr::detail {

std::uint32_t shadedColour(const Scene& scene, const Camera& camera, const RenderOptions& options,
                           PolygonId id) {
  const std::span<const std::uint32_t> vi = scene.polygon(id);
  const glm::dvec3 n = vi.size() >= 3 ? polygonNormal(scene, vi) : glm::dvec3(0.0);
  const double len2 = glm::dot(n, n);
  const glm::dvec3 view_dir = glm::normalize(glm::dvec3(camera.target) - glm::dvec3(camera.eye));
  const std::uint32_t m = scene.material(id);
  const Material material = m < scene.materials.size() ? scene.materials[m] : Material{};
  return shadeRgba(materialRgb(material),
                   m < scene.materials.size() ? materialAlphaBits(material) : 0xFF000000u,
                   lambertOf(options, n, len2, view_dir));
}

// Largest distance of a vertex from the plane, against the tolerance of a planar polygon:
// one part in 10^6 of its extent plus its coordinates' magnitude (float vertices are only
// that exact).
bool isPlanar(const Scene& scene, std::span<const std::uint32_t> vi, const Plane& plane) {
  const double len = glm::length(plane.normal);
  glm::dvec3 lo(scene.position(vi[0])), hi = lo;
  double worst = 0.0;
  for (std::uint32_t v : vi) {
    const glm::dvec3 p(scene.position(v));
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
    worst = std::max(worst, std::abs(plane.value(p)) / len);
  }
  const double magnitude = std::max(glm::length(lo), glm::length(hi));
  return worst <= 1e-6 * (glm::length(hi - lo) + magnitude);
}

glm::dvec3 polygonNormal(const Scene& scene, std::span<const std::uint32_t> vi) {
  if (vi.size() == 3) return triangleNormal(scene, vi[0], vi[1], vi[2]);
  return newellNormal(vi.size(), [&](std::size_t i) { return glm::dvec3(scene.position(vi[i])); });
}

int eyeSpaceOrientation(const Scene& scene, PolygonId id, const Camera& camera) {
  const std::span<const std::uint32_t> vi = scene.polygon(id);
  if (vi.size() < 3) return 0;
  for (std::uint32_t v : vi) {
    const glm::vec3& p = scene.position(v);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return 0;
  }
  const glm::dvec3 n = polygonNormal(scene, vi);
  const double len2 = glm::dot(n, n);
  if (!(len2 > 0.0) || !std::isfinite(len2)) return 0;
  const glm::dvec3 view_dir = glm::normalize(glm::dvec3(camera.target) - glm::dvec3(camera.eye));
  return eyeOrientation(n, glm::dvec3(scene.position(vi[0])), camera, view_dir);
}

const DepthPlane& depthPlaneOf(const Context& ctx, PolygonInfo& info) {
  if (info.depth_known) return info.depth;
  info.depth_known = true;
  const std::span<const std::uint32_t> vi =
      info.own_triangle ? std::span<const std::uint32_t>(info.triangle) : info.vertices;
  if (vi.size() == 3 && !((ctx.verts[vi[0]].code | ctx.verts[vi[1]].code | ctx.verts[vi[2]].code) &
                          (kMustClip | kNonFinite))) {
    info.depth = insideTrianglePlane(ctx.verts[vi[0]], ctx.verts[vi[1]], ctx.verts[vi[2]]);
    return info.depth;
  }
  // A plane (as a 4-vector) maps by the inverse transpose of the point transform.
  const Plane world = canonicalPlane(
      vi.size(), [&](std::size_t i) { return glm::dvec3(ctx.scene.position(vi[i])); });
  const glm::dvec4 device = ctx.device_plane_from_world_plane * glm::dvec4(world.normal, world.d);
  if (!depthPlaneFromDevicePlane(device.x, device.y, device.z, device.w, &info.depth)) {
    // A plane seen edge-on: the depth of its first vertex, where that is in front of the eye.
    const glm::dvec4 h =
        ctx.device_from_world * glm::dvec4(glm::dvec3(ctx.scene.position(vi[0])), 1.0);
    info.depth = flatDepthPlane(h.w > 0.0 ? h.z / h.w : 1.0);
  }
  return info.depth;
}

PolygonInfo forTriangle(const PolygonInfo& polygon, const std::uint32_t (&triangle)[3]) {
  PolygonInfo t = polygon;
  std::copy_n(triangle, 3, t.triangle);
  t.own_triangle = true;
  t.depth_known = false;
  return t;
}

PolygonInfo describePolygon(const Context& ctx, PolygonId id, std::span<const std::uint32_t> vi) {
  PolygonInfo info;
  if (vi.size() < 3) return info;
  for (std::uint32_t v : vi)
    if (ctx.verts[v].code & kNonFinite) return info;
  const Scene& scene = ctx.scene;
  // Normal by the right-hand rule; any point of a planar polygon serves as P.
  const glm::dvec3 n = polygonNormal(scene, vi);
  const double len2 = glm::dot(n, n);
  if (!usableNormal(len2)) return info;  // zero area
  info.degenerate = false;
  info.vertices = vi;
  info.planar = vi.size() == 3 || isPlanar(scene, vi, canonicalPlane(vi.size(), [&](std::size_t i) {
                                             return glm::dvec3(scene.position(vi[i]));
                                           }));
  info.eye_orientation =
      eyeOrientation(n, glm::dvec3(scene.position(vi[0])), ctx.camera, ctx.view_dir);
  info.rgba = polygonRgba(ctx, id, n, len2);
  info.transparent = (info.rgba >> 24) != 0xFFu;
  return info;
}

}  // namespace hsr::detail
