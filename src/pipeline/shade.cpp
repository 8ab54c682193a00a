// Facing, shading and the depth plane of a polygon: everything the pipeline decides once per
// polygon, the same for the fast triangle path and the general one.
//   - Facing: the notes' N . (eye - P) with N by the right-hand rule (a cross product for a
//     triangle, Newell's method for larger polygons); OpenGL's window-area rule is applied
//     per snapped triangle (isFront).
//   - Shading: a headlight, one light direction per view (along the view axis), two-sided
//     Lambert with 20% ambient, so a flat face has one colour however it is triangulated.
//   - Depth plane: the polygon's plane carried into device space (raster/depth.hpp), the
//     notes' A x + B y + C z + D = 0 "in device coordinates".

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "pipeline/stages.hpp"

namespace hsr::detail {
namespace {

// Shaded colour: rgb in [0, 1] scaled by the Lambert factor in [0, 1], each channel rounded
// half up to a byte.
std::uint32_t shadeRgba(const glm::vec3& rgb, std::uint32_t alpha_bits, float lambert) {
  auto q = [&](float c) { return static_cast<std::uint32_t>(c * lambert * 255.0f + 0.5f); };
  return q(rgb.r) | (q(rgb.g) << 8) | (q(rgb.b) << 16) | alpha_bits;
}

// Headlight Lambert, two-sided: light along the view axis, 20% ambient (1 when not shading).
float lambertOf(const RenderOptions& options, const glm::dvec3& n, double len2, const glm::dvec3& view_dir) {
  if (!options.shade) return 1.0f;
  const double cosine = std::abs(glm::dot(n, view_dir)) / std::sqrt(len2);
  // Any overflow (inf/inf) or 0/0 reads as facing the light.
  const float lambert = cosine >= 0.0 && cosine <= 1.0 ? static_cast<float>(cosine) : 1.0f;
  return 0.2f + 0.8f * lambert;
}

}  // namespace

std::uint32_t shadedColour(const Scene& scene, const Camera& camera, const RenderOptions& options, PolygonId id) {
  const std::span<const std::uint32_t> vi = scene.polygon(id);
  const glm::dvec3 n = vi.size() >= 3 ? polygonNormal(scene, vi) : glm::dvec3(0.0);
  const double len2 = glm::dot(n, n);
  const glm::dvec3 view_dir = glm::normalize(glm::dvec3(camera.target) - glm::dvec3(camera.eye));
  const std::uint32_t m = scene.material(id);
  const Material material = m < scene.materials.size() ? scene.materials[m] : Material{};
  return shadeRgba(materialRgb(material), m < scene.materials.size() ? materialAlphaBits(material) : 0xFF000000u,
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
  const glm::dvec3 p0(scene.position(vi[0]));
  if (vi.size() == 3)
    return glm::cross(glm::dvec3(scene.position(vi[1])) - p0,
                      glm::dvec3(scene.position(vi[2])) - p0);
  return newellNormal(vi.size(), [&](std::size_t i) { return glm::dvec3(scene.position(vi[i])); });
}

int eyeOrientation(const glm::dvec3& normal, const glm::dvec3& p0, const Camera& camera,
                   const glm::dvec3& view_dir) {
  // The notes' facing test: V = eye - P (the reversed view direction for a parallel projection).
  const glm::dvec3 v = camera.ortho ? -view_dir : glm::dvec3(camera.eye) - p0;
  const double d = glm::dot(normal, v);
  return d > 0.0 ? 1 : (d < 0.0 ? -1 : 0);
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

bool culled(CullMode mode, bool front) {
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

bool isFront(const Context& ctx, int window_orientation, int eye_orientation) {
  const bool ccw_front = ctx.options.front_face == FrontFace::Ccw;
  return ctx.options.facing_test == FacingTest::WindowArea ? (window_orientation > 0) == ccw_front
                                                           : (eye_orientation > 0) == ccw_front;
}

namespace {

// The plane through three projected vertices, from the topmost (then leftmost) one in the
// given winding. Reversing the winding negates the determinant and both numerators exactly,
// so the quotients are the same bits.
bool windowPlane(const WindowVertex* w[3], DepthPlane* out) {
  int first = 0;
  for (int k = 1; k < 3; ++k)
    if (w[k]->y < w[first]->y || (w[k]->y == w[first]->y && w[k]->x < w[first]->x)) first = k;
  const WindowVertex& a = *w[first];
  const WindowVertex& b = *w[(first + 1) % 3];
  const WindowVertex& c = *w[(first + 2) % 3];
  const double dx1 = double(b.x) - a.x, dy1 = double(b.y) - a.y, dz1 = double(b.z) - a.z;
  const double dx2 = double(c.x) - a.x, dy2 = double(c.y) - a.y, dz2 = double(c.z) - a.z;
  // The normal (A, B, C) = (b - a) x (c - a); then -A/C, -B/C, and the plane at pixel (0, 0).
  const double nx = dy1 * dz2 - dz1 * dy2, ny = dz1 * dx2 - dx1 * dz2, nz = dx1 * dy2 - dy1 * dx2;
  return depthPlaneFromDevicePlane(nx, ny, nz, -(nx * a.x + ny * a.y + nz * a.z), out);
}

}  // namespace

const DepthPlane& depthPlaneOf(const Context& ctx, PolygonInfo& info) {
  if (info.depth_known) return info.depth;
  info.depth_known = true;
  const std::span<const std::uint32_t> vi =
      info.own_triangle ? std::span<const std::uint32_t>(info.triangle) : info.vertices;
  if (vi.size() == 3 && !((ctx.verts[vi[0]].code | ctx.verts[vi[1]].code | ctx.verts[vi[2]].code) &
                          (kMustClip | kNonFinite))) {
    const WindowVertex* w[3] = {&ctx.verts[vi[0]].w, &ctx.verts[vi[1]].w, &ctx.verts[vi[2]].w};
    if (!windowPlane(w, &info.depth))
      info.depth = flatDepthPlane(std::min({w[0]->z, w[1]->z, w[2]->z}));
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
  if (!(len2 > 0.0) || !std::isfinite(len2)) return info;  // zero area
  info.degenerate = false;
  info.vertices = vi;
  info.planar = vi.size() == 3 || isPlanar(scene, vi, canonicalPlane(vi.size(), [&](std::size_t i) {
                                             return glm::dvec3(scene.position(vi[i]));
                                           }));
  info.eye_orientation =
      eyeOrientation(n, glm::dvec3(scene.position(vi[0])), ctx.camera, ctx.view_dir);
  const float lambert = lambertOf(ctx.options, n, len2, ctx.view_dir);
  const std::uint32_t m = scene.material(id);
  const bool known = m < ctx.material_rgb.size();
  const glm::vec3 rgb = known ? ctx.material_rgb[m] : Material{}.color;
  const std::uint32_t alpha = known ? ctx.material_alpha[m] : 0xFF000000u;
  info.rgba = shadeRgba(rgb, alpha, lambert);
  info.transparent = alpha != 0xFF000000u;
  return info;
}

}  // namespace hsr::detail
