// hsr::RayScene (include/hsr/ray_scene.hpp): the scene's triangles in a BVH
// (geometry/bvh.hpp), queried one ray at a time or in parallel batches.

#include "hsr/ray_scene.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/material.hpp"
#include "core/parallel.hpp"
#include "geometry/bvh.hpp"
#include "geometry/triangulate.hpp"
#include "hsr/error.hpp"
#include "geometry/ray_scene_data.hpp"

namespace hsr {

namespace detail {

HitSides hitSidesOf(RaySides sides) {
  switch (sides) {
    case RaySides::kFrontOnly:
      return HitSides::kCounterClockwiseOnly;
    case RaySides::kBackOnly:
      return HitSides::kClockwiseOnly;
    case RaySides::kBoth:
      break;
  }
  return HitSides::kBoth;
}

RayHit hitOf(const RaySceneData& d, const BvhHit& h) {
  RayHit out;
  if (h.triangle == kBvhNoTriangle) return out;
  out.t = h.t;
  out.u = h.u;
  out.v = h.v;
  out.triangle = h.triangle;
  out.polygon = d.polygon[h.triangle];
  out.object = d.object[h.triangle];
  out.front = h.counter_clockwise;
  glm::vec3 fa, fb, fc;  // from the leaf just tested, not the triangle arrays: no cache misses
  detail::bvhTriangleOf(d.bvh, h, &fa, &fb, &fc);
  // The unit normal in float, within a few float steps of the exact one in each component;
  // in double where float's products would overflow or lose their precision to underflow
  const glm::vec3 fn = glm::cross(fb - fa, fc - fa);
  const float len2 = glm::dot(fn, fn);
  if (len2 >= 1e-30f && len2 <= 1e30f) {
    out.normal = fn * (1.0f / std::sqrt(len2));
    return out;
  }
  const glm::dvec3 a(fa), b(fb), c(fc);
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double len = glm::length(n);
  // A hit triangle has area; a length that overflowed double still has a direction
  out.normal = len > 0.0 && std::isfinite(len) ? glm::vec3(n / len) : glm::vec3(0.0f);
  return out;
}

}  // namespace detail

RayScene::RayScene(const Scene& scene, bool opaque_only)
    : data_(std::make_unique<detail::RaySceneData>()) {
  detail::RaySceneData& d = *data_;
  // The triangles every algorithm sees, in polygon order
  std::vector<detail::Triangle> tris;
  for (PolygonId p = 0; p < scene.polygonCount(); ++p) {
    const std::uint32_t m = scene.material(p);
    if (opaque_only && m < scene.materials.size() &&
        detail::materialSeeThrough(scene.materials[m])) {
      d.stats.polygons_left_out++;
      continue;
    }
    const std::size_t before = tris.size();
    detail::triangulatePolygon(scene, p, tris);
    if (tris.size() == before)
      d.stats.polygons_left_out++;
    else
      d.stats.polygons++;
  }
  d.a.resize(tris.size());
  d.b.resize(tris.size());
  d.c.resize(tris.size());
  d.polygon.resize(tris.size());
  d.object.resize(tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i) {
    d.a[i] = scene.position(tris[i].v[0]);
    d.b[i] = scene.position(tris[i].v[1]);
    d.c[i] = scene.position(tris[i].v[2]);
    d.polygon[i] = tris[i].id;
    d.object[i] = scene.object(tris[i].id);
  }
  d.bvh = detail::buildBvh(d.a, d.b, d.c);
  d.stats.triangles = d.bvh.stats.triangles;
  d.stats.nodes = d.bvh.stats.nodes;
  d.stats.leaves = d.bvh.stats.leaves;
  d.stats.depth = d.bvh.stats.depth;
  d.stats.sah_cost = d.bvh.stats.sah_cost;
  d.stats.build_ms = d.bvh.stats.build_ms;
  d.stats.bytes =
      d.bvh.stats.bytes + tris.size() * (3 * sizeof(glm::vec3) + 2 * sizeof(std::uint32_t));
}

RayScene::~RayScene() = default;
RayScene::RayScene(RayScene&&) noexcept = default;
RayScene& RayScene::operator=(RayScene&&) noexcept = default;

namespace {

void checkSizes(std::span<const glm::vec3> origins, std::span<const glm::vec3> directions) {
  if (origins.size() != directions.size())
    throw Error("ray query: " + std::to_string(origins.size()) + " origins but " +
                std::to_string(directions.size()) + " directions");
}

constexpr std::size_t kRaysPerTask = 1024;
constexpr int kRayGroup = 32;  // neighbours cast as a group (bvh.hpp)

}  // namespace

RayHit RayScene::intersect(const glm::vec3& origin, const glm::vec3& direction, float tmax,
                           float tmin, RaySides sides) const {
  return detail::hitOf(*data_, detail::intersectNearest(data_->bvh, origin, direction, tmin, tmax,
                                                        detail::hitSidesOf(sides)));
}

std::vector<RayHit> RayScene::intersect(std::span<const glm::vec3> origins,
                                        std::span<const glm::vec3> directions, float tmax,
                                        float tmin, RaySides sides) const {
  checkSizes(origins, directions);
  std::vector<RayHit> hits(origins.size());
  intersect(origins, directions, hits, tmax, tmin, sides);
  return hits;
}

void RayScene::intersect(std::span<const glm::vec3> origins, std::span<const glm::vec3> directions,
                         std::span<RayHit> hits, float tmax, float tmin, RaySides sides) const {
  checkSizes(origins, directions);
  if (hits.size() != origins.size())
    throw Error("ray query: " + std::to_string(origins.size()) + " rays but room for " +
                std::to_string(hits.size()) + " answers");
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, origins.size(), kRaysPerTask),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      // Neighbours in the caller's order (a camera's rays, row by row) cast as
                      // a group: the same answers as one by one
                      detail::BvhHit found[kRayGroup];
                      for (std::size_t i = r.begin(); i < r.end(); i += kRayGroup) {
                        const int n =
                            static_cast<int>(std::min<std::size_t>(kRayGroup, r.end() - i));
                        detail::intersectNearestGroup(data_->bvh, &origins[i], &directions[i], n,
                                                      tmin, tmax, detail::hitSidesOf(sides), found);
                        for (int k = 0; k < n; ++k) hits[i + k] = detail::hitOf(*data_, found[k]);
                      }
                    });
}

bool RayScene::occluded(const glm::vec3& origin, const glm::vec3& direction, float tmax,
                        float tmin) const {
  return detail::intersectAny(data_->bvh, origin, direction, tmin, tmax);
}

std::vector<std::uint8_t> RayScene::occluded(std::span<const glm::vec3> origins,
                                             std::span<const glm::vec3> directions, float tmax,
                                             float tmin) const {
  checkSizes(origins, directions);
  std::vector<std::uint8_t> out(origins.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, origins.size(), kRaysPerTask),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i)
                        out[i] = occluded(origins[i], directions[i], tmax, tmin) ? 1 : 0;
                    });
  return out;
}

const RaySceneStats& RayScene::stats() const { return data_->stats; }
std::size_t RayScene::triangleCount() const { return data_->a.size(); }

void RayScene::triangleOf(const RayHit& hit, glm::vec3* v0, glm::vec3* v1, glm::vec3* v2) const {
  if (hit.triangle >= data_->a.size())
    throw Error("ray query: the hit names no triangle of this scene");
  *v0 = data_->a[hit.triangle];
  *v1 = data_->b[hit.triangle];
  *v2 = data_->c[hit.triangle];
}

}  // namespace hsr
