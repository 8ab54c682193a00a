#pragma once
// Ray queries against a scene: any rays in, the nearest hit out (distance, polygon, object,
// barycentrics, normal), or only whether something is in the way. What the ray caster
// (--algorithm raycast) draws with, and what data users call directly, as they would call
// Open3D's RaycastingScene or Embree.
//
//   const hsr::RayScene rays(hsr::loadScene("model.obj"));
//   std::vector<glm::vec3> origins = ..., directions = ...;
//   const std::vector<hsr::RayHit> hits = rays.intersect(origins, directions);
//   for (const hsr::RayHit& h : hits)
//     if (h.hit()) use(h.t, h.polygon, h.normal);
//
// Guarantees: the scene's polygons are triangulated as every algorithm triangulates them, and
// each triangle is tested watertight (Woop, Benthin & Wald 2013): no ray slips between two
// triangles that share an edge. Of hits at the same distance the lowest polygon wins (the
// z-buffer's rule), so the answer does not depend on the thread count. A ray with a NaN or
// infinite component, or a zero direction, is answered "no hit" and harms no other ray.
// Polygons with a non-finite vertex are left out (counted in stats()).
//
// Cost: building is O(n log n) in the triangles (binned SAH, oneTBB), about 100 B per
// triangle; a query is O(log n) node visits on typical scenes; the batch calls run in
// parallel over the calling thread's oneTBB arena. The batch intersect casts neighbours in the
// caller's order as groups of 32: where a group's directions share their signs (a camera's
// rays, in any order that keeps neighbours together), one box test answers for the whole group
// wherever all 16 pass beside a box, so give rays in such an order for speed; the answers are
// the same in any order. Safe on untrusted scenes and rays.

#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "hsr/camera.hpp"
#include "hsr/scene.hpp"

namespace hsr {

namespace detail {
struct RaySceneData;
}

// One ray's answer.
struct RayHit {
  float t = std::numeric_limits<float>::infinity();  // hit point = origin + t * direction
                                                     // (direction as given, not normalised)
  PolygonId polygon = kNoPolygon;                    // the polygon hit, kNoPolygon for none
  std::uint32_t object = 0xFFFFFFFFu;                // Scene::objects index of that polygon
  std::uint32_t triangle = 0xFFFFFFFFu;  // the triangle of the scene's triangulation (polygons
                                         // in id order, each as triangulatePolygon splits it)
  float u = 0,
        v = 0;  // barycentrics in the hit triangle (v0, v1, v2): point = (1-u-v) v0 + u v1 + v v2
  glm::vec3 normal{0.0f};  // unit geometric normal by the right-hand rule of the polygon's winding
  bool front = false;      // the ray met the side the normal points to (counter-clockwise seen
                           // from the ray's origin)
  bool hit() const { return polygon != kNoPolygon; }
};

struct RaySceneStats {
  std::uint64_t polygons = 0, triangles = 0;  // in the hierarchy
  std::uint64_t polygons_left_out = 0;        // a non-finite vertex, or fewer than 3, or
                                              // see-through when building opaque_only
  std::uint64_t nodes = 0, leaves = 0, depth = 0;
  std::uint64_t bytes = 0;
  double build_ms = 0;
  double sah_cost = 0;
};

// Which sides a query may hit (as glCullFace does for drawing).
enum class RaySides : std::uint8_t {
  kBoth,
  kFrontOnly,  // the side the right-hand normal points to
  kBackOnly,
};

class RayScene {
 public:
  // Builds the hierarchy over the scene's polygons (the scene is not kept). With
  // `opaque_only`, see-through polygons (alpha below 1 as drawing rounds it: under 254.5/255)
  // are left out, as the ray caster leaves them to its blending pass.
  explicit RayScene(const Scene& scene, bool opaque_only = false);
  ~RayScene();
  RayScene(RayScene&&) noexcept;
  RayScene& operator=(RayScene&&) noexcept;

  // The nearest hit with tmin < t < tmax of each ray i = (origins[i], directions[i]). Throws
  // hsr::Error when the spans' sizes differ.
  std::vector<RayHit> intersect(std::span<const glm::vec3> origins,
                                std::span<const glm::vec3> directions,
                                float tmax = std::numeric_limits<float>::infinity(),
                                float tmin = 0.0f, RaySides sides = RaySides::kBoth) const;
  // The same into the caller's array (hits.size() == origins.size(), else hsr::Error): no
  // allocation, for callers that cast batch after batch.
  void intersect(std::span<const glm::vec3> origins, std::span<const glm::vec3> directions,
                 std::span<RayHit> hits, float tmax = std::numeric_limits<float>::infinity(),
                 float tmin = 0.0f, RaySides sides = RaySides::kBoth) const;
  RayHit intersect(const glm::vec3& origin, const glm::vec3& direction,
                   float tmax = std::numeric_limits<float>::infinity(), float tmin = 0.0f,
                   RaySides sides = RaySides::kBoth) const;

  // Whether anything lies on each ray with tmin < t < tmax (1) or not (0): stops at the first
  // hit found, so cheaper than intersect.
  std::vector<std::uint8_t> occluded(std::span<const glm::vec3> origins,
                                     std::span<const glm::vec3> directions,
                                     float tmax = std::numeric_limits<float>::infinity(),
                                     float tmin = 0.0f) const;
  bool occluded(const glm::vec3& origin, const glm::vec3& direction,
                float tmax = std::numeric_limits<float>::infinity(), float tmin = 0.0f) const;

  const RaySceneStats& stats() const;
  std::size_t triangleCount() const;
  // The hit triangle's vertices, for a hit of this scene (tests and teaching views).
  void triangleOf(const RayHit& hit, glm::vec3* v0, glm::vec3* v1, glm::vec3* v2) const;

  const detail::RaySceneData& data() const { return *data_; }

 private:
  std::unique_ptr<detail::RaySceneData> data_;
};

// A camera's rays through its pixel centres, top row first (the order of Frame's buffers), as
// the ray caster casts them: t = 1 at the far plane; in perspective from the eye, with tmin at
// the near plane (a hit's eye depth is t * far), in parallel from the near plane (tmin 0, t the
// window depth). Pass tmin and tmax to intersect() to clip by the near and far planes.
struct CameraRays {
  std::vector<glm::vec3> origins, directions;
  float tmin = 0, tmax = 1;
};
CameraRays cameraRays(const Camera& camera);

}  // namespace hsr
