#pragma once
// Polygon -> triangles, shared by every algorithm and by the test oracles so that all of them
// see exactly the same triangles. Convex polygons become a fan from their first vertex;
// concave ones are ear-clipped in their own plane. Every triangle keeps its polygon's id.

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "hsr/scene.hpp"

namespace hsr::detail {

struct Triangle {
  std::uint32_t v[3];  // absolute vertex indices into Scene::positions()
  PolygonId id;
};

// Newell's method: a robust normal for any polygon, even a non-planar one; its direction
// follows the vertex order by the right-hand rule, its length is twice the area.
glm::dvec3 newellNormal(const Scene& scene, std::span<const std::uint32_t> polygon);

// Triangles of one polygon, appended to `out`. Polygons with fewer than 3 vertices or a
// non-finite vertex yield nothing.
void triangulatePolygon(const Scene& scene, PolygonId id, std::vector<Triangle>& out);
// All polygons in id order.
std::vector<Triangle> triangulate(const Scene& scene);

}  // namespace hsr::detail
