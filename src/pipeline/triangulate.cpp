// Polygon triangulation: a fan for convex polygons, ear clipping (Meisters 1975) in the
// polygon's own plane for concave ones. Deterministic; every triangle keeps its polygon id.

#include "pipeline/triangulate.hpp"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace hsr::detail {
namespace {

double cross2(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

bool pointInTriangle(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b,
                     const glm::dvec2& c) {
  return cross2(a, b, p) >= 0.0 && cross2(b, c, p) >= 0.0 && cross2(c, a, p) >= 0.0;
}

}  // namespace

glm::dvec3 newellNormal(const Scene& scene, std::span<const std::uint32_t> poly) {
  glm::dvec3 n(0.0);
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec3 a(scene.position(poly[i]));
    const glm::dvec3 b(scene.position(poly[(i + 1) % poly.size()]));
    n.x += (a.y - b.y) * (a.z + b.z);
    n.y += (a.z - b.z) * (a.x + b.x);
    n.z += (a.x - b.x) * (a.y + b.y);
  }
  return n;
}

void triangulatePolygon(const Scene& scene, PolygonId id, std::vector<Triangle>& out) {
  const std::span<const std::uint32_t> poly = scene.polygon(id);
  const std::size_t n = poly.size();
  if (n < 3) return;
  for (std::uint32_t v : poly) {
    const glm::vec3& p = scene.position(v);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return;
  }
  if (n == 3) {
    out.push_back({{poly[0], poly[1], poly[2]}, id});
    return;
  }

  // Project onto the plane of the polygon's dominant normal axis, keeping orientation.
  const glm::dvec3 normal = newellNormal(scene, poly);
  const glm::dvec3 an = glm::abs(normal);
  const int axis = (an.x >= an.y && an.x >= an.z) ? 0 : (an.y >= an.z ? 1 : 2);
  const int u = (axis + 1) % 3, w = (axis + 2) % 3;
  const double sign = normal[axis] >= 0.0 ? 1.0 : -1.0;
  std::vector<glm::dvec2> p2(n);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3& p = scene.position(poly[i]);
    p2[i] = glm::dvec2(p[u], p[w] * sign);  // CCW in 2D when the normal points along +axis
  }

  // Convex (every turn to the left or straight): a fan from the first vertex.
  bool convex = true;
  for (std::size_t i = 0; i < n && convex; ++i)
    convex = cross2(p2[i], p2[(i + 1) % n], p2[(i + 2) % n]) >= 0.0;
  if (convex) {
    for (std::size_t i = 1; i + 1 < n; ++i) out.push_back({{poly[0], poly[i], poly[i + 1]}, id});
    return;
  }

  // Ear clipping: repeatedly cut off a convex corner with no other vertex inside it.
  std::vector<std::size_t> ring(n);
  for (std::size_t i = 0; i < n; ++i) ring[i] = i;
  std::size_t guard = 0;
  std::size_t i = 0;
  while (ring.size() > 3 && guard < 2 * n * n) {
    ++guard;
    const std::size_t m = ring.size();
    const std::size_t a = ring[(i + m - 1) % m], b = ring[i % m], c = ring[(i + 1) % m];
    bool ear = cross2(p2[a], p2[b], p2[c]) > 0.0;
    for (std::size_t k = 0; ear && k < m; ++k) {
      const std::size_t q = ring[k];
      if (q == a || q == b || q == c) continue;
      if (pointInTriangle(p2[q], p2[a], p2[b], p2[c])) ear = false;
    }
    if (ear) {
      out.push_back({{poly[a], poly[b], poly[c]}, id});
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i % m));
      i = i % ring.size();
    } else {
      i = (i + 1) % m;
    }
  }
  // Self-intersecting or otherwise hopeless leftovers: close with a fan so nothing vanishes.
  for (std::size_t k = 1; k + 1 < ring.size(); ++k)
    out.push_back({{poly[ring[0]], poly[ring[k]], poly[ring[k + 1]]}, id});
}

std::vector<Triangle> triangulate(const Scene& scene) {
  std::vector<Triangle> out;
  out.reserve(scene.triangleCount());
  for (PolygonId id = 0; id < scene.polygonCount(); ++id) triangulatePolygon(scene, id, out);
  return out;
}

}  // namespace hsr::detail
