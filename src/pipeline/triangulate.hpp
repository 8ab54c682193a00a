#pragma once
// Polygon -> triangles, shared by every algorithm and by the test oracles so that all of them
// see exactly the same triangles. Convex polygons become a fan from their first vertex;
// concave ones are ear-clipped in their own plane. Every triangle keeps its polygon's id.

#include <cstdint>
#include <vector>

#include "hsr/scene.hpp"

namespace hsr::detail {

struct Triangle {
  std::uint32_t v[3];  // absolute vertex indices into Scene::positions()
  PolygonId id;
};

// Triangles of one polygon, appended to `out`. Polygons with fewer than 3 vertices or a
// non-finite vertex yield nothing.
void triangulatePolygon(const Scene& scene, PolygonId id, std::vector<Triangle>& out);
// All polygons in id order.
std::vector<Triangle> triangulate(const Scene& scene);

}  // namespace hsr::detail
