// Camera matrices (gluLookAt, gluPerspective, glOrtho via GLM) and auto-framing.

#include "hsr/camera.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

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
  if (intrinsics.given()) {
    // The frustum at `near` whose window mapping puts OpenCV pixel u at window x = u + 0.5 and
    // row v (top first) at window y = height - v - 0.5: x_w = (n X / -z - l) / (r - l) width.
    const Intrinsics& k = intrinsics;
    const double n = near;
    const double l = -(k.cx + 0.5) * n / k.fx, r = (width - k.cx - 0.5) * n / k.fx;
    const double t = (k.cy + 0.5) * n / k.fy, b = -(height - k.cy - 0.5) * n / k.fy;
    return glm::mat4(glm::frustum(l, r, b, t, n, static_cast<double>(far)));
  }
  return glm::perspective(glm::radians(fov_deg), aspect, near, far);
}

Intrinsics intrinsicsOf(const Camera& camera) {
  if (camera.ortho) return {};
  if (camera.intrinsics.given()) return camera.intrinsics;
  // y_ndc = f Y / Z with f = 1 / tan(fov / 2) (x_ndc the same over the aspect ratio, so square
  // pixels: fx = fy), and the window maps ndc [-1, 1] onto [-0.5, size - 0.5]
  const double f =
      1.0 / std::tan(static_cast<double>(camera.fov_deg) * 3.14159265358979323846 / 360.0);
  const double focal = f * camera.height / 2.0;
  return {focal, focal, camera.width / 2.0 - 0.5, camera.height / 2.0 - 0.5};
}

FieldOfView fieldOfView(const Camera& camera) {
  if (camera.ortho) return {};
  const Intrinsics k = intrinsicsOf(camera);
  // Pixel centres at integers: the image spans [-0.5, size - 0.5] about the principal point
  const double to_deg = 180.0 / 3.14159265358979323846;
  const double x = std::atan((k.cx + 0.5) / k.fx) + std::atan((camera.width - 0.5 - k.cx) / k.fx);
  const double y = std::atan((k.cy + 0.5) / k.fy) + std::atan((camera.height - 0.5 - k.cy) / k.fy);
  return {x * to_deg, y * to_deg};
}

void Camera::validate() const {
  if (width <= 0 || height <= 0)
    throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) +
                " must be at least 1x1");
  if (width > kMaxDimension || height > kMaxDimension ||
      static_cast<long long>(width) * height > kMaxPixels) {
    // 4 buffers of 4 bytes + 3 bytes of colour per pixel, said where it is a sizeable figure
    const double gib = static_cast<double>(width) * height * 19.0 / (1024.0 * 1024.0 * 1024.0);
    throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) +
                " is over the limit of " + std::to_string(kMaxDimension) + " pixels per side" +
                (gib >= 1.0 ? " (its buffers would take " +
                                  std::to_string(static_cast<long long>(gib + 0.5)) + " GiB)"
                            : std::string()));
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
  if (intrinsics.given()) {
    const Intrinsics& k = intrinsics;
    if (ortho) throw Error("pixel intrinsics describe a pinhole: an orthographic camera has none");
    if (!std::isfinite(k.fx) || !std::isfinite(k.fy) || !std::isfinite(k.cx) ||
        !std::isfinite(k.cy))
      throw Error("camera intrinsics are not finite");
    // A focal length below 1e-3 px spans more than 179.9 degrees on a 1-pixel image; beyond 1e9
    // the frustum's width underflows float at any sensible near plane
    if (!(k.fx >= 1e-3 && k.fy >= 1e-3 && k.fx <= 1e9 && k.fy <= 1e9))
      throw Error("focal lengths fx " + std::to_string(k.fx) + ", fy " + std::to_string(k.fy) +
                  " must be between 0.001 and 1e9 pixels");
    if (std::abs(k.cx) > 1e9 || std::abs(k.cy) > 1e9)
      throw Error("principal point beyond 1e9 pixels");
  }
  const glm::vec3 dir = target - eye;
  if (glm::length(dir) == 0.0f) throw Error("camera eye and target are the same point " + str(eye));
  if (glm::length(glm::cross(glm::normalize(dir), up)) < 1e-6f) {
    // The suggestion: the axis least along the view direction
    const glm::vec3 d = glm::abs(glm::normalize(dir));
    const char* other = d.x <= d.y && d.x <= d.z ? "1,0,0" : (d.y <= d.z ? "0,1,0" : "0,0,1");
    throw Error("camera up vector " + str(up) +
                " is parallel to the view direction: give another up vector (--up), such as " +
                other);
  }
}

Camera frameBounds(const Bounds& bounds, int width, int height, float fov_deg, bool ortho,
                   const glm::vec3& up_axis) {
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
  // The three-quarter direction in the frame of the scene's up axis: for y up, (0.55, 0.45, 1)
  // (right, up, towards the viewer); for z up (CAD, Blender), the viewer stands at -y
  const glm::vec3 u =
      glm::length(up_axis) > 0.0f ? glm::normalize(up_axis) : glm::vec3(0.0f, 1.0f, 0.0f);
  glm::vec3 x_axis = glm::vec3(1.0f, 0.0f, 0.0f) - u * u.x;
  if (glm::length(x_axis) < 1e-3f) x_axis = glm::vec3(0.0f, 0.0f, -1.0f) - u * -u.z;  // up along x
  x_axis = glm::normalize(x_axis);
  const glm::vec3 toward_viewer = glm::cross(x_axis, u);
  // target -> eye
  const glm::vec3 forward = glm::normalize(0.55f * x_axis + 0.45f * u + 1.0f * toward_viewer);
  const glm::vec3 right = glm::normalize(glm::cross(u, forward));
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
  c.up = u;
  c.near = std::max(dist - 1.5f * r, dist * 1e-3f);
  c.far = dist + 1.5f * r;
  c.ortho_half_height = std::max({half_h, half_w / aspect, r * 1e-3f}) * 1.06f;
  // A field of view so narrow that the eye stands where float cannot tell near from far (at
  // 1e-6 degrees the bounds of the demo need 3.9e8 units, where floats are 32 apart) is the
  // reason, not the near and far it gives: said so
  if (!ortho && !(c.far > c.near && std::isfinite(c.far) && std::isfinite(glm::length(c.eye)))) {
    char buf[256];
    std::snprintf(
        buf, sizeof buf,
        "a field of view of %g degrees is too narrow to frame the scene: its eye would stand "
        "%.3g units away, where float cannot tell the near plane from the far; widen the "
        "field of view, or place the camera by hand",
        double(fov_deg), double(dist));
    throw Error(buf);
  }
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

void fitNearFar(Camera& camera, const Bounds& bounds) {
  if (bounds.empty()) return;
  const float dist = glm::length(bounds.center() - camera.eye);
  const float r = bounds.radius();
  camera.near = std::max(dist - 1.5f * r, std::max(dist, r) * 1e-3f);
  camera.far = dist + 1.5f * r;
}

float orthoHalfHeightFor(const Camera& camera, const Bounds& bounds) {
  const float r = std::max(bounds.empty() ? 1.0f : bounds.radius(), 1e-6f);
  if (bounds.empty()) return camera.ortho_half_height;
  const glm::vec3 forward = glm::normalize(camera.target - camera.eye);
  const glm::vec3 right = glm::normalize(glm::cross(forward, camera.up));
  const glm::vec3 up = glm::cross(right, forward);
  const float aspect =
      static_cast<float>(camera.width) / static_cast<float>(std::max(camera.height, 1));
  float half = r * 1e-3f;
  for (int k = 0; k < 8; ++k) {
    const glm::vec3 corner((k & 1) ? bounds.hi.x : bounds.lo.x, (k & 2) ? bounds.hi.y : bounds.lo.y,
                           (k & 4) ? bounds.hi.z : bounds.lo.z);
    const glm::vec3 d = corner - camera.eye;
    half = std::max({half, std::abs(glm::dot(d, up)), std::abs(glm::dot(d, right)) / aspect});
  }
  return half * 1.06f;
}

Camera fromSceneCamera(const SceneCamera& s, const Bounds& bounds, int width, int height) {
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
  if (!bounds.empty() && s.far > 1000.0f * s.near) {
    // Pull near and far in to the bounding sphere (1.5 radii, so nothing inside is clipped),
    // never past the file's own planes
    Camera fitted = c;
    fitNearFar(fitted, bounds);
    const float near = std::max(c.near, fitted.near), far = std::min(c.far, fitted.far);
    if (far > near) c.near = near, c.far = far;
  }
  return c;
}

Camera frameScene(const Scene& scene, int width, int height, int camera_index) {
  if (camera_index >= 0 && static_cast<std::size_t>(camera_index) < scene.cameras.size())
    return fromSceneCamera(scene.cameras[camera_index], scene.bounds(), width, height);
  return frameBounds(scene.bounds(), width, height);
}

PoseConvention poseConventionNamed(std::string_view name) {
  if (name == "opencv") return PoseConvention::kOpenCV;
  if (name == "opengl") return PoseConvention::kOpenGL;
  throw Error("pose convention '" + std::string(name) + "': opencv or opengl");
}

glm::dmat4 poseOf(const Camera& camera, PoseConvention convention) {
  // The view matrix's inverse is OpenGL's pose (camera to world, looking down -z); OpenCV's
  // turns y and z about x
  glm::dmat4 pose = glm::inverse(glm::dmat4(camera.view()));
  if (convention == PoseConvention::kOpenCV) {
    pose[1] = -pose[1];
    pose[2] = -pose[2];
  }
  return pose;
}

void setPose(Camera& camera, const glm::dmat4& m, PoseConvention convention) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) throw Error("the pose has a value that is not a finite number");
  if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
    throw Error("the pose's last row must be 0 0 0 1");
  const glm::dvec3 x(m[0]), y(m[1]), z(m[2]), t(m[3]);
  const double tol = 1e-4;
  if (std::abs(glm::length(x) - 1) > tol || std::abs(glm::length(y) - 1) > tol ||
      std::abs(glm::length(z) - 1) > tol || std::abs(glm::dot(x, y)) > tol ||
      std::abs(glm::dot(y, z)) > tol || std::abs(glm::dot(z, x)) > tol)
    throw Error(
        "the pose's upper 3x3 is not a rotation (its columns must be unit length and "
        "at right angles, within 1e-4): give camera to world without scale");
  if (glm::dot(glm::cross(x, y), z) < 0)
    throw Error("the pose's upper 3x3 is a reflection (determinant -1), not a rotation");
  // OpenGL: the camera looks down its -z with y up; OpenCV: down +z with y down
  const glm::dvec3 forward = convention == PoseConvention::kOpenCV ? z : -z;
  const glm::dvec3 up = convention == PoseConvention::kOpenCV ? -y : y;
  // The target as far out as the eye is from the origin, so that target - eye keeps its
  // direction to float precision wherever the camera stands
  camera.eye = glm::vec3(t);
  camera.target = glm::vec3(t + forward * std::max(1.0, glm::length(t)));
  camera.up = glm::vec3(up);
}

}  // namespace hsr
