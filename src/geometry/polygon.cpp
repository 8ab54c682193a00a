// Classification against a plane and splitting (Sutherland-Hodgman against one plane, both
// sides kept).

#include "geometry/polygon.hpp"

#include <cmath>

namespace hsr::detail {

PlaneSide classifyAgainstPlane(std::span<const glm::dvec3> polygon, const Plane& plane,
                               double epsilon) {
  const double len = glm::length(plane.normal);
  bool front = false, behind = false;
  for (const glm::dvec3& v : polygon) {
    const double dist = plane.value(v) / len;
    if (dist > epsilon)
      front = true;
    else if (dist < -epsilon)
      behind = true;
  }
  if (front && behind) return PlaneSide::kSpanning;
  if (front) return PlaneSide::kFront;
  if (behind) return PlaneSide::kBehind;
  return PlaneSide::kOn;
}

void splitVertices(std::span<const glm::dvec3> polygon, const Plane& plane, double epsilon,
                   std::vector<glm::dvec3>* front, std::vector<glm::dvec3>* behind) {
  front->clear();
  behind->clear();
  const double len = glm::length(plane.normal);
  const std::size_t n = polygon.size();
  std::vector<double> dist(n);
  for (std::size_t i = 0; i < n; ++i) {
    dist[i] = plane.value(polygon[i]) / len;
    if (std::abs(dist[i]) <= epsilon) dist[i] = 0.0;  // on the plane
  }
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3& a = polygon[i];
    const glm::dvec3& b = polygon[(i + 1) % n];
    const double da = dist[i], db = dist[(i + 1) % n];
    if (da >= 0.0) front->push_back(a);
    if (da <= 0.0) behind->push_back(a);
    if ((da > 0.0 && db < 0.0) || (da < 0.0 && db > 0.0)) {
      // The crossing, interpolated from the endpoint in front: a neighbour that lists the
      // shared edge the other way round gets the same point, so split meshes stay closed.
      const glm::dvec3 v =
          da > 0.0 ? a + (da / (da - db)) * (b - a) : b + (db / (db - da)) * (a - b);
      front->push_back(v);
      behind->push_back(v);
    }
  }
  if (front->size() < 3) front->clear();
  if (behind->size() < 3) behind->clear();
}

}  // namespace hsr::detail
