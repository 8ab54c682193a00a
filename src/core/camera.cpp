// Camera matrices (gluLookAt, gluPerspective, glOrtho via GLM) and auto-framing.

#include "hsr/camera.hpp"

#include <algorithm>
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

Intrinsics intrinsicsOf(const Camera& camera) {
  if (camera.ortho) return {};
  // y_ndc = f Y / Z with f = 1 / tan(fov / 2) (x_ndc the same over the aspect ratio, so square
  // pixels: fx = fy), and the window maps ndc [-1, 1] onto [-0.5, size - 0.5]
  const double f = 1.0 / std::tan(static_cast<double>(camera.fov_deg) * 3.14159265358979323846 / 360.0);
  const double focal = f * camera.height / 2.0;
  return {focal, focal, camera.width / 2.0 - 0.5, camera.height / 2.0 - 0.5};
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
  // Look from a three-quarter direction, just far enough that all 8 corners of the bounds
  // project inside the view (with a 6% margin): for a corner at (x, y) across the view and z
  // towards the eye, the eye distance d must satisfy |x| <= (d - z) tan(half fov x), and
  // likewise for y.
  const float r = std::max(bounds.radius(), 1e-6f);
  const float aspect = static_cast<float>(width) / static_cast<float>(std::max(height, 1));
  const float tan_v = std::tan(glm::radians(fov_deg) * 0.5f);
  const float tan_h = tan_v * aspect;
  const glm::vec3 forward = glm::normalize(glm::vec3(0.55f, 0.45f, 1.0f));  // target -> eye
  const glm::vec3 right = glm::normalize(glm::cross(glm::vec3(0.0f, 1.0f, 0.0f), forward));
  const glm::vec3 up = glm::cross(forward, right);
  c.target = bounds.center();
  float dist = 0.0f, half_w = 0.0f, half_h = 0.0f;
  for (int k = 0; k < 8; ++k) {
    const glm::vec3 corner((k & 1) ? bounds.hi.x : bounds.lo.x, (k & 2) ? bounds.hi.y : bounds.lo.y,
                           (k & 4) ? bounds.hi.z : bounds.lo.z);
    const glm::vec3 d = corner - c.target;
    const float x = std::abs(glm::dot(d, right)), y = std::abs(glm::dot(d, up));
    const float z = glm::dot(d, forward);
    dist = std::max({dist, z + x / tan_h * 1.06f, z + y / tan_v * 1.06f});
    half_w = std::max(half_w, x);
    half_h = std::max(half_h, y);
  }
  dist = std::max(dist, r * 1e-3f);
  c.eye = c.target + forward * dist;
  c.up = glm::vec3(0.0f, 1.0f, 0.0f);
  c.near = std::max(dist - 1.5f * r, dist * 1e-3f);
  c.far = dist + 1.5f * r;
  c.ortho_half_height = std::max({half_h, half_w / aspect, r * 1e-3f}) * 1.06f;
  return c;
}

Camera orbitView(const Camera& camera, int k, int n) {
  if (n < 1) throw Error("an orbit needs at least 1 view (got " + std::to_string(n) + ")");
  const glm::vec3 up = glm::normalize(camera.up);
  const glm::vec3 offset = camera.eye - camera.target;
  const float angle = 6.2831853f * static_cast<float>(k) / static_cast<float>(n);
  // Rodrigues' rotation of the offset about `up`.
  const glm::vec3 rotated = offset * std::cos(angle) + glm::cross(up, offset) * std::sin(angle) +
                            up * glm::dot(up, offset) * (1.0f - std::cos(angle));
  Camera view = camera;
  view.eye = camera.target + rotated;
  return view;
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
