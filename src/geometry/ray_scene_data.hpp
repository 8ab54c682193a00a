#pragma once
// What a hsr::RayScene holds (geometry/ray_scene.cpp), open to the ray caster
// (visibility/raycast_fast.cpp), which draws with the same hierarchy.

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "geometry/bvh.hpp"
#include "hsr/ray_scene.hpp"

namespace hsr::detail {

struct RaySceneData {
  std::vector<glm::vec3> a, b, c;     // triangle i's vertices, in its polygon's winding
  std::vector<PolygonId> polygon;     // triangle i's polygon
  std::vector<std::uint32_t> object;  // and that polygon's object
  Bvh bvh;
  RaySceneStats stats;
};

HitSides hitSidesOf(RaySides sides);
RayHit hitOf(const RaySceneData& d, const BvhHit& h);  // the public answer for a BVH hit

}  // namespace hsr::detail
