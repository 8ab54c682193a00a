// Transform: view-frustum culling of whole objects by their bounds, then every vertex of the
// objects that remain from world to clip space (the model transforms are baked into the
// scene), once per vertex however many polygons share it.

#include <cmath>

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

void transformVertices(const Scene& scene, const glm::mat4& mvp, const ClipSetup& cs,
                       const Viewport& vp, const std::vector<std::uint8_t>& object_state,
                       ClipVertices& clip, VertexOuts& verts) {
  clip.resize(scene.vertexCount());
  verts.resize(scene.vertexCount());
  tbb::parallel_for(std::size_t(0), scene.objects.size(), [&](std::size_t o) {
    if (object_state[o] == kObjectCulled) return;
    const Object& obj = scene.objects[o];
    for (std::uint32_t v = obj.first_vertex; v < obj.first_vertex + obj.vertex_count; ++v) {
      const glm::vec3& p = scene.position(v);
      clip[v] = mvp * glm::vec4(p, 1.0f);
      VertexOut& out = verts[v];
      out.code = outcode(clip[v], cs);
      // Non-finite input, or finite input the transform took beyond float's range: such a
      // vertex is never projected (its polygons are dropped as degenerate).
      const glm::vec4& c = clip[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) ||
          !std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(c.w))
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
  });
}

}  // namespace hsr::detail
