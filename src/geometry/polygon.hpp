#pragma once
// Polygons in 3D: their plane (Newell's method), classification of a polygon against a plane
// (in front, behind, on it, or spanning it, with a stated epsilon), and splitting by a plane
// that keeps everything the polygon carries (its PolygonId above all).

#include <cstddef>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace hsr::detail {

// Newell's normal (the notes' "projected areas" method): robust for any polygon, even a
// non-planar one; it follows the vertex order by the right-hand rule and its length is twice
// the area. `at(i)` returns vertex i as a glm::dvec3.
template <class At>
glm::dvec3 newellNormal(std::size_t n, At at) {
  glm::dvec3 normal(0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 a = at(i), b = at((i + 1) % n);
    normal.x += (a.y - b.y) * (a.z + b.z);
    normal.y += (a.z - b.z) * (a.x + b.x);
    normal.z += (a.x - b.x) * (a.y + b.y);
  }
  return normal;
}

struct Plane {
  glm::dvec3 normal{0.0};  // not normalised
  double d = 0.0;          // normal . p + d = 0 on the plane
  // Signed distance in units of |normal| (positive on the side the normal points to).
  double value(const glm::dvec3& p) const { return glm::dot(normal, p) + d; }
  double distance(const glm::dvec3& p) const { return value(p) / glm::length(normal); }
};

// The polygon's plane, computed so that the same polygon gives bit-identical coefficients
// whichever vertex it is listed from and in either direction: Newell's sum starts at the
// lexicographically smallest vertex (x, then y, then z) and walks towards its smaller
// neighbour; d comes from that vertex. The normal's sign follows that walk, not the winding:
// this is the plane for depth; use newellNormal for facing.
template <class At>
Plane canonicalPlane(std::size_t n, At at) {
  auto less = [](const glm::dvec3& a, const glm::dvec3& b) {
    return a.x < b.x || (a.x == b.x && (a.y < b.y || (a.y == b.y && a.z < b.z)));
  };
  std::size_t first = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (less(at(i), at(first))) first = i;
  const bool backwards = n > 2 && less(at((first + n - 1) % n), at((first + 1) % n));
  auto walk = [&](std::size_t k) {
    return at(backwards ? (first + n - k % n) % n : (first + k) % n);
  };
  Plane p;
  p.normal = newellNormal(n, walk);
  p.d = -glm::dot(p.normal, walk(0));
  return p;
}

enum class PlaneSide { kFront, kBehind, kOn, kSpanning };

// Where a polygon lies relative to a plane. A vertex within `epsilon` (a distance, in the
// coordinates' units) of the plane counts as on it; the polygon is kFront or kBehind when its
// other vertices all lie on that side, kOn when every vertex is on the plane.
PlaneSide classifyAgainstPlane(std::span<const glm::dvec3> polygon, const Plane& plane,
                               double epsilon);

// Splits polygon `in` (any type with a member `std::vector<glm::dvec3> vertices`; every
// other member, the PolygonId first, is copied to both pieces) by `plane`: *front gets the
// part on the normal's side, *behind the rest; vertices within epsilon of the plane go to
// both. A side that gets fewer than 3 vertices is left with none.
void splitVertices(std::span<const glm::dvec3> polygon, const Plane& plane, double epsilon,
                   std::vector<glm::dvec3>* front, std::vector<glm::dvec3>* behind);
template <class P>
void splitPolygon(const P& in, const Plane& plane, double epsilon, P* front, P* behind) {
  *front = in;
  *behind = in;
  splitVertices(in.vertices, plane, epsilon, &front->vertices, &behind->vertices);
}

}  // namespace hsr::detail
