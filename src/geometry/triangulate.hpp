#pragma once
// Polygon -> triangles, shared by every algorithm and by the test oracles so that all of them
// see exactly the same triangles. Convex polygons become a fan from their first vertex;
// concave ones are ear-clipped (Meisters 1975) in their own plane with exact orientation
// tests. Polygons with holes joined to the outside by a zero-width bridge (a "keyhole", whose
// bridge vertices appear twice) triangulate to the ring, not the disc. Every triangle keeps
// its polygon's id and winding.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "hsr/scene.hpp"

namespace hsr::detail {

struct Triangle {
  std::uint32_t v[3];  // absolute vertex indices into Scene::positions()
  PolygonId id;
};

// Triangles of the polygon with 2D vertices `p` (either winding; the triangles keep it), as
// index triples into p, appended to `out`. Zero-width spikes, straight and repeated vertices
// add no triangle (a polygon of n vertices gives at most n - 2). A polygon the ear clipper cannot
// finish (self-intersecting) is closed with a fan of what is left, so nothing vanishes.
// `vertex_tests`, when given, counts the vertices tested against candidate ears: the work,
// about proportional to n for the polygons of real models (tests pin it).
void triangulate2d(std::span<const glm::dvec2> p, std::vector<std::array<std::uint32_t, 3>>& out,
                   std::uint64_t* vertex_tests = nullptr);

// Triangles of one polygon of the scene, appended to `out`. Polygons with fewer than 3
// vertices or a non-finite vertex yield nothing.
void triangulatePolygon(const Scene& scene, PolygonId id, std::vector<Triangle>& out);
// All polygons in id order.
std::vector<Triangle> triangulate(const Scene& scene);

// Newell's normal of a scene polygon (see geometry/polygon.hpp).
glm::dvec3 newellNormal(const Scene& scene, std::span<const std::uint32_t> polygon);

}  // namespace hsr::detail
