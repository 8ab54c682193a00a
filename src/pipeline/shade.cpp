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

#if defined(__x86_64__) && !defined(HSR_NO_SIMD)
#include <immintrin.h>
#elif defined(__SSE2__) && !defined(HSR_NO_SIMD)
#include <emmintrin.h>
#endif

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

void shadeLanesScalar(const ShadeLanes& in, const glm::dvec3& light, ShadedLanes& out) {
  for (int i = 0; i < ShadeLanes::kLanes; ++i) {
    // The lanes hold floats widened to double: narrowing them back is exact.
    auto vertex = [](double x, double y, double z) {
      return WindowVertex{
          static_cast<float>(x), static_cast<float>(y), static_cast<float>(z), 0, 0, true};
    };
    const WindowVertex w[3] = {vertex(in.ax[i], in.ay[i], in.az[i]),
                               vertex(in.bx[i], in.by[i], in.bz[i]),
                               vertex(in.cx[i], in.cy[i], in.cz[i])};
    const WindowVertex* pw[3] = {&w[0], &w[1], &w[2]};
    DepthPlane plane{};
    out.ok[i] = windowPlane(pw, &plane);
    out.dzdx[i] = plane.dzdx;
    out.dzdy[i] = plane.dzdy;
    out.z0[i] = plane.z0;
    const glm::dvec3 n(in.nx[i], in.ny[i], in.nz[i]);
    out.cosine[i] = std::abs(glm::dot(n, light)) / std::sqrt(in.len2[i]);
  }
}

#if defined(__SSE2__) && !defined(HSR_NO_SIMD)
void shadeLanesSse2(const ShadeLanes& in, const glm::dvec3& light, ShadedLanes& out) {
  const __m128d sign = _mm_set1_pd(-0.0), limit = _mm_set1_pd(1e30);
  const __m128d lx = _mm_set1_pd(light.x), ly = _mm_set1_pd(light.y), lz = _mm_set1_pd(light.z);
  auto add = [](__m128d a, __m128d b) { return _mm_add_pd(a, b); };
  auto sub = [](__m128d a, __m128d b) { return _mm_sub_pd(a, b); };
  auto mul = [](__m128d a, __m128d b) { return _mm_mul_pd(a, b); };
  auto inLimit = [&](__m128d v) { return _mm_cmple_pd(_mm_andnot_pd(sign, v), limit); };
  for (int i = 0; i < ShadeLanes::kLanes; i += 2) {
    // Each lane's own 8-byte load: the lanes were stored one double at a time just before, and a
    // 16-byte load of two such stores would wait for them to reach the cache.
    auto ld = [i](const double* lane) { return _mm_loadh_pd(_mm_load_sd(lane + i), lane + i + 1); };
    const __m128d ax = ld(in.ax), ay = ld(in.ay), az = ld(in.az);
    // windowPlane: (b - a) x (c - a), then depthPlaneFromDevicePlane's quotients.
    const __m128d dx1 = sub(ld(in.bx), ax), dy1 = sub(ld(in.by), ay), dz1 = sub(ld(in.bz), az);
    const __m128d dx2 = sub(ld(in.cx), ax), dy2 = sub(ld(in.cy), ay), dz2 = sub(ld(in.cz), az);
    const __m128d nx = sub(mul(dy1, dz2), mul(dz1, dy2));
    const __m128d ny = sub(mul(dz1, dx2), mul(dx1, dz2));
    const __m128d nz = sub(mul(dx1, dy2), mul(dy1, dx2));
    // D = -(nx ax + ny ay + nz az), so -D / C is the sum over C.
    const __m128d minus_d = add(add(mul(nx, ax), mul(ny, ay)), mul(nz, az));
    const __m128d dzdx = _mm_div_pd(_mm_xor_pd(nx, sign), nz);
    const __m128d dzdy = _mm_div_pd(_mm_xor_pd(ny, sign), nz);
    const __m128d z0 = _mm_div_pd(minus_d, nz);
    const __m128d ok = _mm_and_pd(_mm_and_pd(_mm_cmpneq_pd(nz, _mm_setzero_pd()), inLimit(dzdx)),
                                  _mm_and_pd(inLimit(dzdy), inLimit(z0)));
    _mm_store_pd(out.dzdx + i, dzdx);
    _mm_store_pd(out.dzdy + i, dzdy);
    _mm_store_pd(out.z0 + i, z0);
    const int mask = _mm_movemask_pd(ok);
    out.ok[i] = (mask & 1) != 0;
    out.ok[i + 1] = (mask & 2) != 0;
    // lambertOf's cosine: |N . L| / sqrt(N . N).
    const __m128d dot = add(add(mul(ld(in.nx), lx), mul(ld(in.ny), ly)), mul(ld(in.nz), lz));
    _mm_store_pd(out.cosine + i, _mm_div_pd(_mm_andnot_pd(sign, dot), _mm_sqrt_pd(ld(in.len2))));
  }
}
#endif

#if defined(__x86_64__) && !defined(HSR_NO_SIMD)
// Four lanes per AVX operation (compiled for AVX2 alone, chosen at run time).
namespace {
#define HSR_AVX2 __attribute__((target("avx2"), always_inline)) inline
// Each lane's own 8-byte load, as in shadeLanesSse2.
HSR_AVX2 __m256d lanes4(const double* l) { return _mm256_setr_pd(l[0], l[1], l[2], l[3]); }
HSR_AVX2 __m256d inLimit4(__m256d v) {
  return _mm256_cmp_pd(_mm256_andnot_pd(_mm256_set1_pd(-0.0), v), _mm256_set1_pd(1e30), _CMP_LE_OQ);
}
#undef HSR_AVX2
}  // namespace

__attribute__((target("avx2"))) void shadeLanesAvx2(const ShadeLanes& in, const glm::dvec3& light,
                                                    ShadedLanes& out) {
  const __m256d sign = _mm256_set1_pd(-0.0);
  const __m256d ax = lanes4(in.ax), ay = lanes4(in.ay), az = lanes4(in.az);
  const __m256d dx1 = _mm256_sub_pd(lanes4(in.bx), ax), dy1 = _mm256_sub_pd(lanes4(in.by), ay),
                dz1 = _mm256_sub_pd(lanes4(in.bz), az);
  const __m256d dx2 = _mm256_sub_pd(lanes4(in.cx), ax), dy2 = _mm256_sub_pd(lanes4(in.cy), ay),
                dz2 = _mm256_sub_pd(lanes4(in.cz), az);
  const __m256d nx = _mm256_sub_pd(_mm256_mul_pd(dy1, dz2), _mm256_mul_pd(dz1, dy2));
  const __m256d ny = _mm256_sub_pd(_mm256_mul_pd(dz1, dx2), _mm256_mul_pd(dx1, dz2));
  const __m256d nz = _mm256_sub_pd(_mm256_mul_pd(dx1, dy2), _mm256_mul_pd(dy1, dx2));
  const __m256d minus_d = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(nx, ax), _mm256_mul_pd(ny, ay)),
                                        _mm256_mul_pd(nz, az));
  const __m256d dzdx = _mm256_div_pd(_mm256_xor_pd(nx, sign), nz);
  const __m256d dzdy = _mm256_div_pd(_mm256_xor_pd(ny, sign), nz);
  const __m256d z0 = _mm256_div_pd(minus_d, nz);
  // C != 0 as C++ compares it: true for NaN (unordered), as _mm_cmpneq_pd.
  const __m256d nonzero = _mm256_cmp_pd(nz, _mm256_setzero_pd(), _CMP_NEQ_UQ);
  const __m256d ok = _mm256_and_pd(_mm256_and_pd(nonzero, inLimit4(dzdx)),
                                   _mm256_and_pd(inLimit4(dzdy), inLimit4(z0)));
  _mm256_storeu_pd(out.dzdx, dzdx);
  _mm256_storeu_pd(out.dzdy, dzdy);
  _mm256_storeu_pd(out.z0, z0);
  const int mask = _mm256_movemask_pd(ok);
  for (int i = 0; i < ShadeLanes::kLanes; ++i) out.ok[i] = ((mask >> i) & 1) != 0;
  const __m256d dot =
      _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(lanes4(in.nx), _mm256_set1_pd(light.x)),
                                  _mm256_mul_pd(lanes4(in.ny), _mm256_set1_pd(light.y))),
                    _mm256_mul_pd(lanes4(in.nz), _mm256_set1_pd(light.z)));
  _mm256_storeu_pd(out.cosine,
                   _mm256_div_pd(_mm256_andnot_pd(sign, dot), _mm256_sqrt_pd(lanes4(in.len2))));
}

bool shadeLanesAvx2Available() { return __builtin_cpu_supports("avx2"); }
#endif

void shadeLanes(const ShadeLanes& in, const glm::dvec3& light, ShadedLanes& out) {
#if defined(__x86_64__) && !defined(HSR_NO_SIMD)
  static const bool avx2 = shadeLanesAvx2Available();
  if (avx2) return shadeLanesAvx2(in, light, out);
#endif
#if defined(__SSE2__) && !defined(HSR_NO_SIMD)
  shadeLanesSse2(in, light, out);
#else
  shadeLanesScalar(in, light, out);
#endif
}

void ShadeBatch::flush(TriangleSink& sink) {
  if (count_ == 0) return;
  for (int i = count_; i < ShadeLanes::kLanes; ++i) {  // unused lanes: copies of the first
    lanes_.ax[i] = lanes_.ax[0], lanes_.ay[i] = lanes_.ay[0], lanes_.az[i] = lanes_.az[0];
    lanes_.bx[i] = lanes_.bx[0], lanes_.by[i] = lanes_.by[0], lanes_.bz[i] = lanes_.bz[0];
    lanes_.cx[i] = lanes_.cx[0], lanes_.cy[i] = lanes_.cy[0], lanes_.cz[i] = lanes_.cz[0];
    lanes_.nx[i] = lanes_.nx[0], lanes_.ny[i] = lanes_.ny[0], lanes_.nz[i] = lanes_.nz[0];
    lanes_.len2[i] = lanes_.len2[0];
  }
  ShadedLanes shaded;
  shadeLanes(lanes_, ctx_->view_dir, shaded);
  for (int i = 0; i < count_; ++i) {
    Waiting& w = waiting_[i];
    w.t.depth = shaded.ok[i] ? DepthPlane{shaded.dzdx[i], shaded.dzdy[i], shaded.z0[i]}
                             : flatDepthPlane(w.min_z);
    const float lambert = ctx_->options.shade ? lambertOfCosine(shaded.cosine[i]) : 1.0f;
    w.t.rgba = polygonRgbaLit(*ctx_, w.t.id, lambert);
    sink.push(w.t);
  }
  count_ = 0;
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
