// A camera's rays through pixel centres (pipeline.hpp: PixelRays), for the ray caster and
// hsr::cameraRays: the pipeline's own device-from-world matrix carried back.

#include <cmath>

#include <glm/matrix.hpp>

#include "hsr/ray_scene.hpp"
#include "pipeline/pipeline.hpp"

namespace hsr {
namespace detail {

PixelRays::PixelRays(const Camera& camera)
    : world_from_device_(glm::inverse(deviceFromWorld(camera))),
      eye_(camera.eye),
      ortho_(camera.ortho),
      tmin_(camera.ortho ? 0.0f : static_cast<float>(double(camera.near) / double(camera.far))) {}

PixelRay PixelRays::at(double x, double y) const {
  // Device coordinates have pixel centres at integers
  auto unproject = [&](double z) {
    const glm::dvec4 p = world_from_device_ * glm::dvec4(x, y, z, 1.0);
    return glm::dvec3(p) / p.w;
  };
  const glm::dvec3 at_far = unproject(1.0);
  const glm::dvec3 org = ortho_ ? unproject(0.0) : eye_;
  return {glm::vec3(org), glm::vec3(at_far - org), tmin_, std::nextafter(1.0f, 2.0f)};
}

}  // namespace detail

CameraRays cameraRays(const Camera& camera) {
  camera.validate();
  const detail::PixelRays rays(camera);
  CameraRays out;
  const std::size_t n = static_cast<std::size_t>(camera.width) * camera.height;
  out.origins.resize(n);
  out.directions.resize(n);
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const detail::PixelRay r = rays.at(x, y);
      out.origins[static_cast<std::size_t>(y) * camera.width + x] = r.org;
      out.directions[static_cast<std::size_t>(y) * camera.width + x] = r.dir;
      out.tmin = r.tmin, out.tmax = r.tmax;
    }
  return out;
}

}  // namespace hsr
