// Polygon triangulation: a fan for convex polygons, ear clipping for the others.

#include "geometry/triangulate.hpp"

#include <algorithm>
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

// The ring's vertices bucketed in a uniform grid over their bounding box, about one per cell:
// any(lo, hi, test) asks `test` of the vertices in the cells that the box [lo, hi] touches (a
// superset of the vertices inside the box, since a vertex's cell is monotone in its position).
class VertexGrid {
 public:
  VertexGrid(std::span<const glm::dvec2> p, const std::vector<std::uint32_t>& ring) {
    lo_ = hi_ = p[ring[0]];
    for (std::uint32_t v : ring) lo_ = glm::min(lo_, p[v]), hi_ = glm::max(hi_, p[v]);
    side_ = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(ring.size()))));
    const glm::dvec2 extent = hi_ - lo_;
    scale_ =
        glm::dvec2(extent.x > 0 ? side_ / extent.x : 0.0, extent.y > 0 ? side_ / extent.y : 0.0);
    start_.assign(static_cast<std::size_t>(side_) * side_ + 1, 0);
    for (std::uint32_t v : ring) ++start_[cellOf(p[v]) + 1];
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    members_.resize(ring.size());
    for (std::size_t k = 0; k < ring.size(); ++k)
      members_[fill[cellOf(p[ring[k]])]++] = static_cast<std::uint32_t>(k);
  }

  template <class Test>
  bool any(glm::dvec2 lo, glm::dvec2 hi, Test test) const {
    const int x0 = axis(lo.x, 0), x1 = axis(hi.x, 0), y0 = axis(lo.y, 1), y1 = axis(hi.y, 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const std::size_t cell = static_cast<std::size_t>(y) * side_ + x;
        for (std::uint32_t i = start_[cell]; i < start_[cell + 1]; ++i)
          if (test(members_[i])) return true;
      }
    return false;
  }

 private:
  int axis(double v, int d) const {
    const double t = std::floor((v - lo_[d]) * scale_[d]);
    return t <= 0 ? 0 : (t >= side_ - 1 ? side_ - 1 : static_cast<int>(t));
  }
  std::size_t cellOf(glm::dvec2 v) const {
    return static_cast<std::size_t>(axis(v.y, 1)) * side_ + axis(v.x, 0);
  }

  glm::dvec2 lo_, hi_, scale_;
  int side_ = 1;
  std::vector<std::uint32_t> start_, members_;  // members_[start_[c] .. start_[c+1]): cell c
};

}  // namespace

void triangulate2d(std::span<const glm::dvec2> p, std::vector<std::array<std::uint32_t, 3>>& out,
                   std::uint64_t* vertex_tests) {
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
  //
  // The ring is a circular list (a removal costs O(1)), and the test for blocking vertices
  // looks only at the grid cells under the corner's bounding box: a polygon of 32,767 vertices
  // takes milliseconds, not the seconds of a scan of every vertex for every corner.
  std::vector<std::uint32_t> next(m), prev(m);
  for (std::size_t k = 0; k < m; ++k) {
    next[k] = static_cast<std::uint32_t>((k + 1) % m);
    prev[k] = static_cast<std::uint32_t>((k + m - 1) % m);
  }
  std::vector<char> alive(m, 1);
  const VertexGrid grid(p, ring);
  auto blocked = [&](std::uint32_t at) {
    const glm::dvec2& a = p[ring[prev[at]]];
    const glm::dvec2& b = p[ring[at]];
    const glm::dvec2& c = p[ring[next[at]]];
    return grid.any(glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c)), [&](std::uint32_t k) {
      if (vertex_tests) ++*vertex_tests;
      if (!alive[k]) return false;
      const glm::dvec2& q = p[ring[k]];
      if (q == a || q == b || q == c) return false;
      return orient2d(a, b, q) >= 0 && orient2d(b, c, q) >= 0 && orient2d(c, a, q) >= 0;
    });
  };
  std::uint32_t head = 0, at = 0;
  std::size_t count = m, misses = 0;
  while (count > 3 && misses < count) {
    const std::uint32_t a = ring[prev[at]], b = ring[at], c = ring[next[at]];
    const int turn = orient2d(p[a], p[b], p[c]);
    if (turn == 0 || (turn > 0 && !blocked(at))) {
      if (turn > 0) emit(a, b, c);
      // Unlink the corner and go on past the next one, as earcut does: the ears of one lap are
      // every other corner, so they stay small (a fan from one corner would make every later
      // ear span the polygon, and each blocking test scan it)
      alive[at] = 0;
      const std::uint32_t after = next[at];
      next[prev[at]] = after;
      prev[after] = prev[at];
      if (at == head) head = after;
      at = next[after];
      --count;
      misses = 0;
    } else {
      at = next[at];
      ++misses;
    }
  }
  std::vector<std::uint32_t> left;
  for (std::uint32_t k = head, i = 0; i < count; k = next[k], ++i) left.push_back(ring[k]);
  if (left.size() == 3) {
    if (orient2d(p[left[0]], p[left[1]], p[left[2]]) > 0) emit(left[0], left[1], left[2]);
    return;
  }
  // Self-intersecting or otherwise hopeless leftovers: close with a fan so nothing vanishes.
  for (std::size_t k = 1; k + 1 < left.size(); ++k) emit(left[0], left[k], left[k + 1]);
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
