// Transform: view-frustum culling of whole objects by their bounds, then every vertex of the
// objects that remain from world to clip space (the model transforms are baked into the
// scene), once per vertex however many polygons share it.

#include <cmath>

#if defined(__SSE2__) && !defined(HSR_NO_SIMD)
#include <emmintrin.h>
#endif

#include "core/parallel.hpp"
#include "pipeline/stages.hpp"

namespace hsr::detail {

void cullObjects(const Scene& scene, const glm::mat4& mvp, const ClipSetup& cs, bool frustum_cull,
                 std::vector<std::uint8_t>& state) {
  state.assign(scene.objects.size(), kObjectInside);
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    const Bounds& b = scene.objects[o].bounds;
    if (b.empty()) continue;
    // The 8 corners of the bounds against the clip planes: outside one plane, all culled.
    unsigned all = ~0u, any = 0;
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 corner((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y,
                             (k & 4) ? b.hi.z : b.lo.z);
      const unsigned c = outcode(mvp * glm::vec4(corner, 1.0f), cs);
      all &= c;
      any |= c;
    }
    if (frustum_cull && (all & kViewVolume))
      state[o] = kObjectCulled;
    else
      state[o] = (any & kMustClip) ? kObjectCrosses : kObjectInside;
  }
}

void transformVertexRange(const Scene& scene, const glm::mat4& mvp, const ClipSetup& cs,
                          const Viewport& vp, std::uint32_t first, std::uint32_t end,
                          glm::vec4* clip, VertexOut* verts) {
  for (std::uint32_t v = first; v < end; ++v) {
    const glm::vec3& p = scene.position(v);
    clip[v] = mvp * glm::vec4(p, 1.0f);
    VertexOut& out = verts[v];
    out.code = outcode(clip[v], cs);
    // Non-finite input, or finite input the transform took beyond float's range: such a
    // vertex is never projected (its polygons are dropped as degenerate).
    const glm::vec4& c = clip[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(c.x) ||
        !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(c.w))
      out.code |= kNonFinite;
    // Vertices inside the view volume are projected once here, for every triangle.
    if (!(out.code & (kMustClip | kNonFinite))) {
      const WindowVertex w = toWindow(clip[v], vp);
      if (w.ok) {
        out.x = w.x;
        out.y = w.y;
        out.z = w.z;
        out.fx = static_cast<std::int32_t>(w.fx);
        out.fy = static_cast<std::int32_t>(w.fy);
      } else {
        out.code |= kNonFinite;
      }
    }
  }
}

#if defined(__SSE2__) && !defined(HSR_NO_SIMD)
namespace {

// Lanes where a float is finite (exponent bits not all set).
__m128 finiteLanes(__m128 v) {
  const __m128i exponent = _mm_set1_epi32(0x7f800000);
  const __m128i bits = _mm_and_si128(_mm_castps_si128(v), exponent);
  return _mm_castsi128_ps(_mm_xor_si128(_mm_cmpeq_epi32(bits, exponent), _mm_set1_epi32(-1)));
}
// `bit` in the lanes of `mask`.
__m128i bitWhere(__m128 mask, unsigned bit) {
  return _mm_and_si128(_mm_castps_si128(mask), _mm_set1_epi32(static_cast<int>(bit)));
}

}  // namespace

void transformVertexRangeSse2(const Scene& scene, const glm::mat4& mvp, const ClipSetup& cs,
                              const Viewport& vp, std::uint32_t first, std::uint32_t end,
                              glm::vec4* clip, VertexOut* verts) {
  std::uint32_t v = first;
  const auto at = [&](int col, int row) { return _mm_set1_ps(mvp[col][row]); };
  for (; v + 4 <= end; v += 4) {
    // Four positions as x, y, z lanes
    const glm::vec3* p = &scene.position(v);
    const __m128 px = _mm_setr_ps(p[0].x, p[1].x, p[2].x, p[3].x);
    const __m128 py = _mm_setr_ps(p[0].y, p[1].y, p[2].y, p[3].y);
    const __m128 pz = _mm_setr_ps(p[0].z, p[1].z, p[2].z, p[3].z);
    const __m128 one = _mm_set1_ps(1.0f);
    // GLM's mat4 * vec4: (m[0] x + m[1] y) + (m[2] z + m[3] w), w = 1, per output row
    __m128 c[4];
    for (int r = 0; r < 4; ++r)
      c[r] = _mm_add_ps(_mm_add_ps(_mm_mul_ps(at(0, r), px), _mm_mul_ps(at(1, r), py)),
                        _mm_add_ps(_mm_mul_ps(at(2, r), pz), _mm_mul_ps(at(3, r), one)));
    // outcode(): a bit where the comparison fails (NaN fails every one)
    const __m128 w = c[3], sign = _mm_set1_ps(-0.0f);
    const __m128 neg_w = _mm_xor_ps(w, sign);
    const __m128 gxw = _mm_mul_ps(_mm_set1_ps(-cs.gx), w), gyw = _mm_mul_ps(_mm_set1_ps(-cs.gy), w);
    const __m128 gxw_hi = _mm_mul_ps(_mm_set1_ps(cs.gx), w),
                 gyw_hi = _mm_mul_ps(_mm_set1_ps(cs.gy), w);
    __m128i code = _mm_setzero_si128();
    code = _mm_or_si128(code, bitWhere(_mm_cmpnge_ps(c[0], neg_w), kLeft));
    code = _mm_or_si128(code, bitWhere(_mm_cmpnle_ps(c[0], w), kRight));
    code = _mm_or_si128(code, bitWhere(_mm_cmpnge_ps(c[1], neg_w), kBottom));
    code = _mm_or_si128(code, bitWhere(_mm_cmpnle_ps(c[1], w), kTop));
    code = _mm_or_si128(code, bitWhere(_mm_cmpnge_ps(c[2], neg_w), kNear));
    code = _mm_or_si128(code, bitWhere(_mm_cmpnle_ps(c[2], w), kFar));
    code = _mm_or_si128(code, bitWhere(_mm_cmpnge_ps(c[0], gxw), kGuardX0));
    code = _mm_or_si128(code, bitWhere(_mm_cmpnle_ps(c[0], gxw_hi), kGuardX1));
    code = _mm_or_si128(code, bitWhere(_mm_cmpnge_ps(c[1], gyw), kGuardY0));
    code = _mm_or_si128(code, bitWhere(_mm_cmpnle_ps(c[1], gyw_hi), kGuardY1));
    __m128 finite = _mm_and_ps(_mm_and_ps(finiteLanes(px), finiteLanes(py)), finiteLanes(pz));
    for (int r = 0; r < 4; ++r) finite = _mm_and_ps(finite, finiteLanes(c[r]));
    code = _mm_or_si128(code, _mm_andnot_si128(_mm_castps_si128(finite),
                                               _mm_set1_epi32(static_cast<int>(kNonFinite))));
    // toWindow() in every lane (kept only where no clipping is due): multiply by 1/w, scale and
    // translate, pixel centres at integers, 8 sub-pixel bits rounded to nearest (the rounding
    // mode lrint uses)
    const __m128 iw = _mm_div_ps(one, w);
    const __m128 half = _mm_set1_ps(0.5f);
    const __m128 x = _mm_sub_ps(
        _mm_add_ps(_mm_mul_ps(_mm_mul_ps(c[0], iw), _mm_set1_ps(vp.sx)), _mm_set1_ps(vp.tx)), half);
    const __m128 y = _mm_sub_ps(
        _mm_add_ps(_mm_mul_ps(_mm_mul_ps(c[1], iw), _mm_set1_ps(vp.sy)), _mm_set1_ps(vp.ty)), half);
    const __m128 z = _mm_add_ps(_mm_mul_ps(_mm_mul_ps(c[2], iw), half), half);
    const __m128 limit = _mm_set1_ps(4194304.0f);  // toWindow's 2^22 pixels
    const __m128 ok = _mm_and_ps(_mm_and_ps(_mm_cmplt_ps(_mm_andnot_ps(sign, x), limit),
                                            _mm_cmplt_ps(_mm_andnot_ps(sign, y), limit)),
                                 finiteLanes(z));
    const __m128 sub = _mm_set1_ps(static_cast<float>(kSubpixelOne));
    const __m128i fx = _mm_cvtps_epi32(_mm_mul_ps(x, sub));
    const __m128i fy = _mm_cvtps_epi32(_mm_mul_ps(y, sub));
    // Projected but not representable: kNonFinite, as toWindow's !ok
    const __m128i unclipped = _mm_cmpeq_epi32(
        _mm_and_si128(code, _mm_set1_epi32(static_cast<int>(kMustClip | kNonFinite))),
        _mm_setzero_si128());
    code = _mm_or_si128(code, _mm_and_si128(_mm_andnot_si128(_mm_castps_si128(ok), unclipped),
                                            _mm_set1_epi32(static_cast<int>(kNonFinite))));
    alignas(16) float cl[4][4], wx[4], wy[4], wz[4];
    alignas(16) std::int32_t ifx[4], ify[4];
    alignas(16) unsigned codes[4];
    for (int r = 0; r < 4; ++r) _mm_store_ps(cl[r], c[r]);
    _mm_store_ps(wx, x);
    _mm_store_ps(wy, y);
    _mm_store_ps(wz, z);
    _mm_store_si128(reinterpret_cast<__m128i*>(ifx), fx);
    _mm_store_si128(reinterpret_cast<__m128i*>(ify), fy);
    _mm_store_si128(reinterpret_cast<__m128i*>(codes), code);
    for (int k = 0; k < 4; ++k) {
      clip[v + k] = glm::vec4(cl[0][k], cl[1][k], cl[2][k], cl[3][k]);
      verts[v + k] = {wx[k], wy[k], wz[k], ifx[k], ify[k], codes[k]};
    }
  }
  transformVertexRange(scene, mvp, cs, vp, v, end, clip, verts);
}
#endif

void transformVertices(const Scene& scene, const glm::mat4& mvp, const ClipSetup& cs,
                       const Viewport& vp, const std::vector<std::uint8_t>& object_state,
                       ClipVertices& clip, VertexOuts& verts) {
  clip.resize(scene.vertexCount());
  verts.resize(scene.vertexCount());
  tbb::parallel_for(std::size_t(0), scene.objects.size(), [&](std::size_t o) {
    if (object_state[o] == kObjectCulled) return;
    const Object& obj = scene.objects[o];
#if defined(__SSE2__) && !defined(HSR_NO_SIMD)
    transformVertexRangeSse2(scene, mvp, cs, vp, obj.first_vertex,
                             obj.first_vertex + obj.vertex_count, clip.data(), verts.data());
#else
    transformVertexRange(scene, mvp, cs, vp, obj.first_vertex, obj.first_vertex + obj.vertex_count,
                         clip.data(), verts.data());
#endif
  });
}

}  // namespace hsr::detail
