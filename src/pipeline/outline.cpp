// Outline: silhouette edges, those shared by a front-facing and a back-facing polygon (by the
// notes' eye-space test), plus the border edges of open surfaces. Vertices are welded by
// exact position so unshared meshes (STL) still find their neighbours. Each edge is clipped
// to the view volume and projected like the polygons' vertices.

#include <algorithm>
#include <cstring>
#include <unordered_map>

#include "pipeline/stages.hpp"

namespace hsr::detail {

void findOutline(const Context& ctx, PreparedScene& out) {
  const Scene& scene = ctx.scene;
  // Keyed on the exact position (with -0 read as +0), so equal positions always weld.
  struct Key {
    std::uint32_t b[3];
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      return (std::uint64_t(k.b[0]) * 0x9E3779B97F4A7C15ull) ^
             (std::uint64_t(k.b[1]) * 0xC2B2AE3D27D4EB4Full) ^
             (std::uint64_t(k.b[2]) * 0x165667B19E3779F9ull);
    }
  };
  std::unordered_map<Key, std::uint32_t, KeyHash> weld;
  std::vector<std::uint32_t> canon(scene.vertexCount());
  for (std::uint32_t v = 0; v < scene.vertexCount(); ++v) {
    const glm::vec3 p = scene.position(v) + glm::vec3(0.0f);  // -0 + 0 = +0
    Key key;
    std::memcpy(key.b, &p, sizeof key.b);
    canon[v] = weld.try_emplace(key, v).first->second;
  }
  struct EdgeUse {
    PolygonId first;
    int facing;
    std::uint32_t a, b;  // original vertices of the first use
    int count;
    bool mixed;
    PolygonId other;
  };
  std::unordered_map<std::uint64_t, EdgeUse> edges;
  for (PolygonId id = 0; id < scene.polygonCount(); ++id) {
    if (ctx.object_state[scene.object(id)] == kObjectCulled) continue;
    const int o = eyeSpaceOrientation(scene, id, ctx.camera);
    if (o == 0) continue;
    const std::span<const std::uint32_t> poly = scene.polygon(id);
    for (std::size_t i = 0; i < poly.size(); ++i) {
      std::uint32_t a = canon[poly[i]], b = canon[poly[(i + 1) % poly.size()]];
      if (a == b) continue;
      const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      auto [it, fresh] = edges.try_emplace(
          key, EdgeUse{id, o, poly[i], poly[(i + 1) % poly.size()], 1, false, id});
      if (!fresh) {
        it->second.count++;
        if (it->second.facing != o) {
          it->second.mixed = true;
          it->second.other = id;
        }
      }
    }
  }
  std::vector<std::pair<PolygonId, std::uint64_t>> order;
  for (const auto& [key, e] : edges)
    if (e.mixed || e.count == 1) order.push_back({e.first, key});
  std::sort(order.begin(), order.end());  // deterministic output order
  for (const auto& [pid, key] : order) {
    const EdgeUse& e = edges.at(key);
    if ((ctx.verts[e.a].code | ctx.verts[e.b].code) & kNonFinite) continue;
    // Clip the segment against the view volume.
    glm::vec4 pa = ctx.clip[e.a], pb = ctx.clip[e.b];
    const unsigned ca = outcode(pa, ctx.cs), cb = outcode(pb, ctx.cs);
    if (ca & cb & kViewVolume) continue;
    bool visible = true;
    for (int k = 0; k < kClipPlanes && visible; ++k) {
      if (!((ca | cb) & kPlaneBit[k])) continue;
      const float da = planeDistance(pa, k, ctx.cs), db = planeDistance(pb, k, ctx.cs);
      if (da < 0.0f && db < 0.0f)
        visible = false;
      else if (da < 0.0f)
        pa = pa + (da / (da - db)) * (pb - pa);
      else if (db < 0.0f)
        pb = pb + (db / (db - da)) * (pa - pb);
    }
    if (!visible) continue;
    const WindowVertex a = toWindow(pa, ctx.vp), b = toWindow(pb, ctx.vp);
    if (!a.ok || !b.ok) continue;
    out.outline.push_back({a.x, a.y, a.z, b.x, b.y, b.z, pid, 0xFF000000u, e.other});
  }
  out.stats.outline_edges = out.outline.size();
}

}  // namespace hsr::detail
