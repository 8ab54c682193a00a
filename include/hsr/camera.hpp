#pragma once
// Camera as gluLookAt + gluPerspective (vertical fov, aspect = width/height) or glOrtho.

#include <string_view>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "hsr/scene.hpp"

namespace hsr {

// A perspective camera's pinhole intrinsics in pixels, in OpenCV's convention: a point at
// (X, Y, Z) in OpenCV's camera frame (x right, y down, z forward: the view's eye space with
// y and z turned) lands at pixel (fx X / Z + cx, fy Y / Z + cy), pixel centres at integers and
// (0, 0) the top-left pixel's centre, as hsr's pictures and arrays. For an orthographic camera
// all four are 0 (no pinhole).
struct Intrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  bool given() const { return fx != 0.0 || fy != 0.0 || cx != 0.0 || cy != 0.0; }
};

struct Camera {
  glm::vec3 eye{0.0f, 0.0f, 5.0f};
  glm::vec3 target{0.0f, 0.0f, 0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fov_deg = 45.0f;  // vertical, as gluPerspective
  // Calibrated input: when given, a perspective camera projects with these pixel intrinsics
  // (glFrustum's off-centre, possibly non-square frustum at `near`) instead of fov_deg.
  Intrinsics intrinsics{};
  bool ortho = false;
  float ortho_half_height = 1.0f;  // glOrtho(-h*aspect, h*aspect, -h, h, near, far)
  float near = 0.1f;
  float far = 100.0f;
  int width = 800;
  int height = 600;

  glm::mat4 view() const;        // world -> eye
  glm::mat4 projection() const;  // eye -> clip
  // Throws hsr::Error on NaN/Inf, near <= 0, far <= near, eye == target, up parallel to the
  // view direction, fov outside (0, 180), or a size outside 1..kMaxDimension / kMaxPixels;
  // intrinsics with fx or fy <= 0, or given to an orthographic camera.
  void validate() const;

  static constexpr int kMaxDimension = 16384;
  static constexpr long long kMaxPixels = 16384LL * 16384LL;
};

// A camera that looks at the whole of `bounds` from a fixed three-quarter direction, with near
// and far fitted around it. Uses the scene file's camera `camera_index` when it has one
// (fromSceneCamera); -1 ignores the file's cameras.
Camera frameScene(const Scene& scene, int width, int height, int camera_index = 0);
// A scene file's camera at this size. Where its far/near ratio passes 1000 (a glTF camera
// with near 0.05 and far 1e6 leaves float depth a few hundred steps across a model), near and
// far are pulled in to the scene's bounding sphere with a margin: nothing more is clipped, and
// depth keeps its precision.
Camera fromSceneCamera(const SceneCamera& camera, const Bounds& bounds, int width, int height);
// Near and far around `bounds` as seen from the camera's eye (a sphere of 1.5x the bounds'
// radius), as auto-framing does for a view given by hand.
void fitNearFar(Camera& camera, const Bounds& bounds);
// The orthographic half-height that shows all of `bounds` from the camera's eye along its
// view axis (with a 6% margin), for --ortho on a view made for a perspective camera.
float orthoHalfHeightFor(const Camera& camera, const Bounds& bounds);

// Where a camera is and where it looks, as a 4x4 pose: camera to world (its columns the
// camera's axes and position in world coordinates), in OpenCV's convention (x right, y down,
// z forward) or OpenGL's (x right, y up, looking down -z).
enum class PoseConvention { kOpenCV, kOpenGL };
PoseConvention poseConventionNamed(std::string_view name);  // "opencv", "opengl"; else Error
glm::dmat4 poseOf(const Camera& camera, PoseConvention convention);
// Sets the camera's eye, target and up from a pose; throws hsr::Error where the pose's upper
// 3x3 is not a rotation (columns not unit and orthogonal within 1e-4), or its last row is not
// 0 0 0 1, or a value is not finite.
void setPose(Camera& camera, const glm::dmat4& camera_to_world, PoseConvention convention);
// `up_axis`: the scene's up (z for CAD and Blender models); the view keeps it up.
Camera frameBounds(const Bounds& bounds, int width, int height, float fov_deg = 45.0f,
                   bool ortho = false, const glm::vec3& up_axis = {0.0f, 1.0f, 0.0f});

// The intrinsics the camera projects with: its own when given, else those of its fov (fx = fy,
// the principal point at the image centre); all 0 for an orthographic camera.
Intrinsics intrinsicsOf(const Camera& camera);

// The angles a perspective camera sees across the image, from its left pixel edge to its right
// (x) and from the top edge to the bottom (y), in degrees: what fov_deg gives (y equals it), or
// what intrinsics give (a principal point off centre included). Zero for an orthographic one.
struct FieldOfView {
  double x_deg = 0, y_deg = 0;
};
FieldOfView fieldOfView(const Camera& camera);

// View k of n on a ring around the camera's target, about its up axis, at its distance from
// the target (view 0 is the camera itself): an orbit, for showing that what an algorithm
// builds once (a BSP tree, an octree) serves every view.
Camera orbitView(const Camera& camera, int k, int n);

}  // namespace hsr
