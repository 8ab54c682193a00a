// Polygon triangulation: a fan for convex polygons, ear clipping for the others.

#include "geometry/triangulate.hpp"

#include <cmath>

#include <glm/geometric.hpp>

#include "geometry/polygon.hpp"
#include "geometry/predicates.hpp"

namespace hsr::detail {
namespace {

double signedArea2(std::span<const glm::dvec2> p) {
  double a = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const glm::dvec2& u = p[i];
    const glm::dvec2& v = p[(i + 1) % p.size()];
    a += u.x * v.y - v.x * u.y;
  }
  return a;
}

}  // namespace

void triangulate2d(std::span<const glm::dvec2> p, std::vector<std::array<std::uint32_t, 3>>& out) {
  const std::size_t n = p.size();
  if (n < 3) return;
  if (n == 3) {
    out.push_back({0, 1, 2});
    return;
  }
  // Work counter-clockwise; emit each triangle in the polygon's own winding.
  const bool ccw = signedArea2(p) >= 0.0;
  // The ring of vertices without consecutive repeats (a repeated vertex adds no area, and
  // would hide a reflex turn from the convexity test below).
  std::vector<std::uint32_t> ring;
  ring.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t v = static_cast<std::uint32_t>(ccw ? i : n - 1 - i);
    if (ring.empty() || p[v] != p[ring.back()]) ring.push_back(v);
  }
  while (ring.size() > 1 && p[ring.back()] == p[ring.front()]) ring.pop_back();
  if (ring.size() < 3) return;
  auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    out.push_back(ccw ? std::array<std::uint32_t, 3>{a, b, c}
                      : std::array<std::uint32_t, 3>{c, b, a});
  };

  // Convex (every turn to the left or straight): a fan from the first vertex, leaving out the
  // triangles of zero area that straight or repeated vertices make.
  bool convex = true;
  const std::size_t m = ring.size();
  for (std::size_t i = 0; i < m && convex; ++i)
    convex = orient2d(p[ring[i]], p[ring[(i + 1) % m]], p[ring[(i + 2) % m]]) >= 0;
  if (convex) {
    for (std::size_t i = 1; i + 1 < m; ++i)
      if (orient2d(p[ring[0]], p[ring[i]], p[ring[i + 1]]) != 0)
        emit(ring[0], ring[i], ring[i + 1]);
    return;
  }

  // Ear clipping: repeatedly cut off a convex corner (a, b, c) with no other vertex in the
  // closed triangle. A vertex at the same position as a, b or c does not block the ear: it is
  // the other end of a zero-width bridge to a hole. A corner with a, b, c collinear (a straight
  // vertex, or the tip of a zero-width spike) encloses nothing and is simply removed.
  auto blocked = [&](std::size_t at) {
    const std::size_t m = ring.size();
    const glm::dvec2& a = p[ring[(at + m - 1) % m]];
    const glm::dvec2& b = p[ring[at]];
    const glm::dvec2& c = p[ring[(at + 1) % m]];
    for (std::size_t k = 0; k < m; ++k) {
      const glm::dvec2& q = p[ring[k]];
      if (q == a || q == b || q == c) continue;
      if (orient2d(a, b, q) >= 0 && orient2d(b, c, q) >= 0 && orient2d(c, a, q) >= 0) return true;
    }
    return false;
  };
  std::size_t i = 0, misses = 0;
  while (ring.size() > 3 && misses < ring.size()) {
    const std::size_t m = ring.size();
    i %= m;
    const std::uint32_t a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
    const int turn = orient2d(p[a], p[b], p[c]);
    if (turn == 0 || (turn > 0 && !blocked(i))) {
      if (turn > 0) emit(a, b, c);
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
      misses = 0;
      if (i > 0) --i;  // the corner before the removed one has changed
    } else {
      ++i;
      ++misses;
    }
  }
  if (ring.size() == 3) {
    if (orient2d(p[ring[0]], p[ring[1]], p[ring[2]]) > 0) emit(ring[0], ring[1], ring[2]);
    return;
  }
  // Self-intersecting or otherwise hopeless leftovers: close with a fan so nothing vanishes.
  for (std::size_t k = 1; k + 1 < ring.size(); ++k) emit(ring[0], ring[k], ring[k + 1]);
}

glm::dvec3 newellNormal(const Scene& scene, std::span<const std::uint32_t> poly) {
  return newellNormal(poly.size(),
                      [&](std::size_t i) { return glm::dvec3(scene.position(poly[i])); });
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
  // Project onto the plane of the polygon's dominant normal axis, keeping orientation: the
  // coordinates are the vertices' own floats, so the exact tests see the true positions.
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
  std::vector<std::array<std::uint32_t, 3>> tris;
  triangulate2d(p2, tris);
  for (const auto& t : tris) out.push_back({{poly[t[0]], poly[t[1]], poly[t[2]]}, id});
}

std::vector<Triangle> triangulate(const Scene& scene) {
  std::vector<Triangle> out;
  out.reserve(scene.triangleCount());
  for (PolygonId id = 0; id < scene.polygonCount(); ++id) triangulatePolygon(scene, id, out);
  return out;
}

}  // namespace hsr::detail
