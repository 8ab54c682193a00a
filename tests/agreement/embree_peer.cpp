// The Embree peer (embree_peer.hpp).

#include "agreement/embree_peer.hpp"

#include <embree3/rtcore.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace hsr::testing {

EmbreeScene::EmbreeScene(const RayScene& rays, int threads, bool robust, EmbreeQuality quality) {
  const std::string config = threads > 0 ? "threads=" + std::to_string(threads) : std::string();
  RTCDevice device = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  if (!device) throw std::runtime_error("Embree: rtcNewDevice failed");
  device_ = device;
  const std::size_t n = rays.triangleCount();
  // The same triangles, unshared vertices: triangle i is primID i
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
  RayHit probe;
  for (std::size_t i = 0; i < n; ++i) {
    probe.triangle = static_cast<std::uint32_t>(i);
    glm::vec3 v[3];
    rays.triangleOf(probe, &v[0], &v[1], &v[2]);
    for (int k = 0; k < 3; ++k) {
      // A non-finite triangle (left out of hsr's hierarchy) becomes a point at the origin
      const bool finite = std::isfinite(v[0].x + v[0].y + v[0].z + v[1].x + v[1].y + v[1].z +
                                        v[2].x + v[2].y + v[2].z);
      for (int a = 0; a < 3; ++a) vertices[9 * i + 3 * k + a] = finite ? v[k][a] : 0.0f;
      indices[3 * i + k] = static_cast<unsigned>(3 * i + k);
    }
  }
  rtcCommitGeometry(geom);
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneFlags(scene, robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
  rtcSetSceneBuildQuality(scene, quality == EmbreeQuality::kLow    ? RTC_BUILD_QUALITY_LOW
                                 : quality == EmbreeQuality::kHigh ? RTC_BUILD_QUALITY_HIGH
                                                                   : RTC_BUILD_QUALITY_MEDIUM);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  const auto t0 = std::chrono::steady_clock::now();
  rtcCommitScene(scene);
  build_ms_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  scene_ = scene;
}

EmbreeScene::~EmbreeScene() {
  if (scene_) rtcReleaseScene(static_cast<RTCScene>(scene_));
  if (device_) rtcReleaseDevice(static_cast<RTCDevice>(device_));
}

EmbreeHit EmbreeScene::intersect1(const glm::vec3& org, const glm::vec3& dir, float tmin,
                                  float tmax) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = org.x, rh.ray.org_y = org.y, rh.ray.org_z = org.z;
  rh.ray.dir_x = dir.x, rh.ray.dir_y = dir.y, rh.ray.dir_z = dir.z;
  rh.ray.tnear = tmin, rh.ray.tfar = tmax, rh.ray.mask = 0xFFFFFFFFu, rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(static_cast<RTCScene>(scene_), &context, &rh);
  EmbreeHit h;
  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID)
    h = {rh.ray.tfar, rh.hit.primID, rh.hit.u, rh.hit.v};
  return h;
}

void EmbreeScene::intersect8(const glm::vec3* org, const glm::vec3* dir, int n, float tmin,
                             float tmax, EmbreeHit* out) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(32) RTCRayHit8 rh;
  alignas(32) int valid[8];
  for (int i = 0; i < 8; ++i) {
    const int k = i < n ? i : 0;
    valid[i] = i < n ? -1 : 0;
    rh.ray.org_x[i] = org[k].x, rh.ray.org_y[i] = org[k].y, rh.ray.org_z[i] = org[k].z;
    rh.ray.dir_x[i] = dir[k].x, rh.ray.dir_y[i] = dir[k].y, rh.ray.dir_z[i] = dir[k].z;
    rh.ray.tnear[i] = tmin, rh.ray.tfar[i] = tmax, rh.ray.mask[i] = 0xFFFFFFFFu,
    rh.ray.flags[i] = 0;
    rh.ray.time[i] = 0, rh.ray.id[i] = 0;
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
  }
  rtcIntersect8(valid, static_cast<RTCScene>(scene_), &context, &rh);
  for (int i = 0; i < n; ++i)
    out[i] = rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID
                 ? EmbreeHit{rh.ray.tfar[i], rh.hit.primID[i], rh.hit.u[i], rh.hit.v[i]}
                 : EmbreeHit{};
}

void EmbreeScene::intersect1M(const glm::vec3* org, const glm::vec3* dir, int n, float tmin,
                              float tmax, EmbreeHit* out) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  std::vector<RTCRayHit> rh(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    RTCRayHit& r = rh[static_cast<std::size_t>(i)];
    r = RTCRayHit{};
    r.ray.org_x = org[i].x, r.ray.org_y = org[i].y, r.ray.org_z = org[i].z;
    r.ray.dir_x = dir[i].x, r.ray.dir_y = dir[i].y, r.ray.dir_z = dir[i].z;
    r.ray.tnear = tmin, r.ray.tfar = tmax, r.ray.mask = 0xFFFFFFFFu;
    r.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  }
  rtcIntersect1M(static_cast<RTCScene>(scene_), &context, rh.data(), static_cast<unsigned>(n),
                 sizeof(RTCRayHit));
  for (int i = 0; i < n; ++i) {
    const RTCRayHit& r = rh[static_cast<std::size_t>(i)];
    out[i] = r.hit.geomID != RTC_INVALID_GEOMETRY_ID
                 ? EmbreeHit{r.ray.tfar, r.hit.primID, r.hit.u, r.hit.v}
                 : EmbreeHit{};
  }
}

std::string EmbreeScene::version() { return RTC_VERSION_STRING; }

}  // namespace hsr::testing
