// Camera matrices (gluLookAt, gluPerspective, glOrtho via GLM) and auto-framing.

#include "hsr/camera.hpp"

#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "hsr/error.hpp"

namespace hsr {
namespace {

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string str(const glm::vec3& v) {
  return std::to_string(v.x) + "," + std::to_string(v.y) + "," + std::to_string(v.z);
}

}  // namespace

glm::mat4 Camera::view() const { return glm::lookAt(eye, target, up); }

glm::mat4 Camera::projection() const {
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  if (ortho) {
    const float h = ortho_half_height;
    return glm::ortho(-h * aspect, h * aspect, -h, h, near, far);
  }
  return glm::perspective(glm::radians(fov_deg), aspect, near, far);
}

void Camera::validate() const {
  if (width <= 0 || height <= 0)
    throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) +
                " must be at least 1x1");
  if (width > kMaxDimension || height > kMaxDimension ||
      static_cast<long long>(width) * height > kMaxPixels) {
    // 4 buffers of 4 bytes + 3 bytes of colour per pixel.
    const double gib = static_cast<double>(width) * height * 19.0 / (1024.0 * 1024.0 * 1024.0);
    throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) +
                " would need " + std::to_string(static_cast<long long>(gib + 0.5)) +
                " GiB of buffers; the limit is " + std::to_string(kMaxDimension) +
                " pixels per side");
  }
  if (!finite(eye) || !finite(target) || !finite(up))
    throw Error("camera has a non-finite eye, target or up vector");
  if (!std::isfinite(near) || !std::isfinite(far) || !std::isfinite(fov_deg) ||
      !std::isfinite(ortho_half_height))
    throw Error("camera near, far or fov is not finite");
  if (near <= 0.0f) throw Error("near plane must be > 0 (got " + std::to_string(near) + ")");
  if (far <= near)
    throw Error("far plane must be > near (got near " + std::to_string(near) + ", far " +
                std::to_string(far) + ")");
  if (!ortho && (fov_deg <= 0.0f || fov_deg >= 180.0f))
    throw Error("fov must be in (0, 180) degrees (got " + std::to_string(fov_deg) + ")");
  if (ortho && ortho_half_height <= 0.0f) throw Error("orthographic half-height must be > 0");
  const glm::vec3 dir = target - eye;
  if (glm::length(dir) == 0.0f) throw Error("camera eye and target are the same point " + str(eye));
  if (glm::length(glm::cross(glm::normalize(dir), up)) < 1e-6f)
    throw Error("camera up vector " + str(up) + " is parallel to the view direction");
}

Camera frameBounds(const Bounds& bounds, int width, int height, float fov_deg, bool ortho) {
  Camera c;
  c.width = width;
  c.height = height;
  c.fov_deg = fov_deg;
  c.ortho = ortho;
  if (bounds.empty()) return c;
  // Look from a three-quarter direction, far enough that the bounding sphere fits the
  // narrower of the two fields of view, with 5% margin.
  const float r = std::max(bounds.radius(), 1e-6f);
  const float aspect = static_cast<float>(width) / static_cast<float>(std::max(height, 1));
  const float half_v = glm::radians(fov_deg) * 0.5f;
  const float half_h = std::atan(std::tan(half_v) * std::min(aspect, 1.0f));
  const float dist = r / std::sin(std::min(half_v, half_h)) * 1.05f;
  c.target = bounds.center();
  c.eye = c.target + glm::normalize(glm::vec3(0.55f, 0.45f, 1.0f)) * dist;
  c.up = glm::vec3(0.0f, 1.0f, 0.0f);
  c.near = std::max(dist - 1.5f * r, dist * 1e-3f);
  c.far = dist + 1.5f * r;
  c.ortho_half_height = r * 1.05f / std::min(aspect, 1.0f);
  return c;
}

Camera frameScene(const Scene& scene, int width, int height) {
  if (scene.camera) {
    const SceneCamera& s = *scene.camera;
    Camera c;
    c.width = width;
    c.height = height;
    c.eye = s.eye;
    c.target = s.target;
    c.up = s.up;
    c.fov_deg = s.fov_deg;
    c.ortho = s.ortho;
    c.ortho_half_height = s.ortho_half_height;
    c.near = s.near;
    c.far = s.far;
    return c;
  }
  return frameBounds(scene.bounds(), width, height);
}

}  // namespace hsr
