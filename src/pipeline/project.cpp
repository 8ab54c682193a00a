// Project and snap: divide by w, map to the viewport (y down, pixel centres at integers),
// snap x and y to 24.8 fixed point as Mesa does, and make screen triangles of what survives
// facing and culling.

#include <algorithm>
#include <cmath>

#include "pipeline/stages.hpp"

namespace hsr::detail {

Viewport viewportOf(const Camera& camera) {
  const float w = static_cast<float>(camera.width), h = static_cast<float>(camera.height);
  return {w * 0.5f, w * 0.5f, -h * 0.5f, h * 0.5f};
}

WindowVertex toWindow(const glm::vec4& c, const Viewport& vp) {
  // As Mesa's draw module: multiply by 1/w, then scale and translate; z to [0,1].
  const float iw = 1.0f / c.w;
  WindowVertex v;
  const float xw = (c.x * iw) * vp.sx + vp.tx;
  const float yw = (c.y * iw) * vp.sy + vp.ty;
  v.z = (c.z * iw) * 0.5f + 0.5f;
  // Pixel centres at integers (GL samples at x + 0.5), then 8 sub-pixel bits, round to nearest.
  v.x = xw - 0.5f;
  v.y = yw - 0.5f;
  // Only finite, bounded values are converted to integers (anything else would be undefined
  // behaviour); clipping keeps real primitives far inside this bound.
  constexpr float kLimit = 4194304.0f;  // 2^22 pixels
  v.ok = std::abs(v.x) < kLimit && std::abs(v.y) < kLimit && std::isfinite(v.z);
  v.fx = v.ok ? std::lrint(v.x * static_cast<float>(kSubpixelOne)) : 0;
  v.fy = v.ok ? std::lrint(v.y * static_cast<float>(kSubpixelOne)) : 0;
  return v;
}

void cullAndEmit(const Context& ctx, const WindowVertex (&w)[3], PolygonId id, PolygonInfo& info,
                 ChunkOut& out) {
  const std::int64_t fx[3] = {w[0].fx, w[1].fx, w[2].fx};
  const std::int64_t fy[3] = {w[0].fy, w[1].fy, w[2].fy};
  ScreenTriangle made;
  cullAndEmitWith(
      ctx, fx, fy, id, info.eye_orientation, [&]() -> ScreenTriangle& { return made; },
      [&](ScreenTriangle& t) {
        t.depth = depthPlaneOf(ctx, info);
        t.rgba = info.rgba;
        out.batch.flush(out.triangles);  // the fast path's triangles before it came first
        out.triangles.push(t);
      },
      out);
}

}  // namespace hsr::detail
