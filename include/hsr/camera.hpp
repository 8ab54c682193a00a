#pragma once
// Camera as gluLookAt + gluPerspective (vertical fov, aspect = width/height) or glOrtho.

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "hsr/scene.hpp"

namespace hsr {

struct Camera {
  glm::vec3 eye{0.0f, 0.0f, 5.0f};
  glm::vec3 target{0.0f, 0.0f, 0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fov_deg = 45.0f;           // vertical, as gluPerspective
  bool ortho = false;
  float ortho_half_height = 1.0f;  // glOrtho(-h*aspect, h*aspect, -h, h, near, far)
  float near = 0.1f;
  float far = 100.0f;
  int width = 800;
  int height = 600;

  glm::mat4 view() const;        // world -> eye
  glm::mat4 projection() const;  // eye -> clip
  // Throws hsr::Error on NaN/Inf, near <= 0, far <= near, eye == target, up parallel to the
  // view direction, fov outside (0, 180), or a size outside 1..kMaxDimension / kMaxPixels.
  void validate() const;

  static constexpr int kMaxDimension = 16384;
  static constexpr long long kMaxPixels = 16384LL * 16384LL;
};

// A camera that looks at the whole of `bounds` from a fixed three-quarter direction, with near
// and far fitted around it. Uses the scene's stored camera when it has one.
Camera frameScene(const Scene& scene, int width, int height);
Camera frameBounds(const Bounds& bounds, int width, int height, float fov_deg = 45.0f,
                   bool ortho = false);

// A perspective camera's pinhole intrinsics in pixels, in OpenCV's convention: a point at
// (X, Y, Z) in OpenCV's camera frame (x right, y down, z forward: the view's eye space with
// y and z turned) lands at pixel (fx X / Z + cx, fy Y / Z + cy), pixel centres at integers and
// (0, 0) the top-left pixel's centre, as hsr's pictures and arrays. For an orthographic camera
// all four are 0 (no pinhole).
struct Intrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
};
Intrinsics intrinsicsOf(const Camera& camera);

// View k of n on a ring around the camera's target, about its up axis, at its distance from
// the target (view 0 is the camera itself): an orbit, for showing that what an algorithm
// builds once (a BSP tree, an octree) serves every view.
Camera orbitView(const Camera& camera, int k, int n);

}  // namespace hsr
