#pragma once
// Embree (Intel's ray tracing kernels, Debian's libembree-dev) as the peer of hsr's rays: the
// same triangles (a RayScene's triangulation, so Embree's primID is hsr's triangle number) in
// an Embree scene, and the same rays through it. Used by tests/agreement/embree_test.cpp and
// bench/bench_rays.cpp.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "hsr/ray_scene.hpp"

namespace hsr::testing {

struct EmbreeHit {
  float t = 0;
  std::uint32_t triangle = 0xFFFFFFFFu;  // Embree's primID
  float u = 0, v = 0;
  bool hit() const { return triangle != 0xFFFFFFFFu; }
};

enum class EmbreeQuality {
  kLow,
  kMedium,
  kHigh
};  // RTC_BUILD_QUALITY_*: medium is Embree's default

class EmbreeScene {
 public:
  // `threads` 0: Embree's default (every core); `robust`: RTC_SCENE_FLAG_ROBUST (watertight).
  EmbreeScene(const RayScene& scene, int threads = 0, bool robust = false,
              EmbreeQuality quality = EmbreeQuality::kMedium);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  double buildMs() const { return build_ms_; }
  // rtcIntersect1, one ray at a time, on the calling thread.
  EmbreeHit intersect1(const glm::vec3& org, const glm::vec3& dir, float tmin, float tmax) const;
  // rtcIntersect8 over rays [i, i + 8) (fewer at the end), on the calling thread.
  void intersect8(const glm::vec3* org, const glm::vec3* dir, int n, float tmin, float tmax,
                  EmbreeHit* out) const;
  // rtcIntersect1M over a stream of rays, on the calling thread.
  void intersect1M(const glm::vec3* org, const glm::vec3* dir, int n, float tmin, float tmax,
                   EmbreeHit* out) const;

  static std::string version();

 private:
  void* device_ = nullptr;
  void* scene_ = nullptr;
  double build_ms_ = 0;
};

}  // namespace hsr::testing
