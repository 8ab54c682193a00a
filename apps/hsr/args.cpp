// The command line's view arguments: parsing and conversion (see args.hpp).

#include "args.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <fmt/core.h>
#include <glm/geometric.hpp>

#include "hsr/error.hpp"

namespace hsr::cli {
namespace {

// A whole string as one float (nan and inf parse; the camera check refuses them).
float parseFloat(const std::string& s, const char* what) {
  char* end = nullptr;
  errno = 0;
  const float v = std::strtof(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size())
    throw hsr::Error(fmt::format("{} must be a number (got '{}')", what, s));
  if (errno == ERANGE)
    throw hsr::Error(fmt::format("{} {} is {} than a float holds ({})", what, s,
                                 std::isinf(v) ? "larger" : "closer to 0",
                                 std::isinf(v) ? "3.4e38 at most" : "1.2e-38 at least"));
  return v;
}

glm::vec3 parseVec3(const std::string& s, const char* what) {
  const std::size_t a = s.find(','), b = a == std::string::npos ? a : s.find(',', a + 1);
  if (a == std::string::npos || b == std::string::npos || s.find(',', b + 1) != std::string::npos)
    throw hsr::Error(fmt::format("{} must be X,Y,Z (got '{}')", what, s));
  return {parseFloat(s.substr(0, a), what), parseFloat(s.substr(a + 1, b - a - 1), what),
          parseFloat(s.substr(b + 1), what)};
}

void parseSize(const std::string& s, int* w, int* h) {
  long long a = 0, b = 0;
  char x = 0;
  std::istringstream in(s);
  if (!(in >> a >> x >> b) || (x != 'x' && x != 'X') || !(in >> std::ws).eof())
    throw hsr::Error(fmt::format("--size must be WxH (got '{}')", s));
  if (a <= 0 || b <= 0) throw hsr::Error(fmt::format("image size {} must be at least 1x1", s));
  if (a > 1000000 || b > 1000000)
    throw hsr::Error(fmt::format("image size {} is absurd: the limit is {} pixels per side", s,
                                 hsr::Camera::kMaxDimension));
  *w = static_cast<int>(a);
  *h = static_cast<int>(b);
}

constexpr float kMaxCoordinate = 1e18f;

// A scene the camera's float arithmetic can frame: coordinates within +-1e18 (at 1e19 the
// squared distances overflow), and, unless the view is given, some extent to frame.
void checkFrameable(const Args& a, const hsr::Scene& scene) {
  const hsr::Bounds b = scene.bounds();
  if (b.empty()) return;
  const float reach = std::max({std::abs(b.lo.x), std::abs(b.lo.y), std::abs(b.lo.z),
                                std::abs(b.hi.x), std::abs(b.hi.y), std::abs(b.hi.z)});
  if (reach > kMaxCoordinate)
    throw hsr::Error(fmt::format("{}: coordinates reach {:.3g}, beyond the +-1e18 within which "
                                 "the camera's float arithmetic works; scale the model",
                                 a.scene, reach));
  if (b.lo == b.hi && !scene.camera && (a.eye.empty() || a.target.empty()))
    throw hsr::Error(fmt::format("{}: every vertex lies at the same point ({:g}, {:g}, {:g}): "
                                 "there is nothing with an extent to frame, or an area to draw",
                                 a.scene, b.lo.x, b.lo.y, b.lo.z));
}

}  // namespace

hsr::Camera makeCamera(const Args& a, const hsr::Scene& scene) {
  int w = 0, h = 0;
  parseSize(a.size, &w, &h);
  checkFrameable(a, scene);
  const bool fov_given = !a.fov.empty();
  const float fov = fov_given ? parseFloat(a.fov, "--fov") : 45.0f;
  if (!(fov > 0.0f && fov < 180.0f))
    throw hsr::Error(fmt::format("--fov must be in (0, 180) degrees (got {})", a.fov));
  hsr::Camera cam = scene.camera ? hsr::frameScene(scene, w, h)
                                 : hsr::frameBounds(scene.bounds(), w, h,
                                                    fov, a.ortho);
  cam.width = w;
  cam.height = h;
  if (fov_given) cam.fov_deg = fov;
  if (a.ortho) cam.ortho = true;
  if (!a.eye.empty()) cam.eye = parseVec3(a.eye, "--eye");
  if (!a.target.empty()) cam.target = parseVec3(a.target, "--target");
  if (!a.up.empty()) cam.up = parseVec3(a.up, "--up");
  if (!a.eye.empty() || !a.target.empty()) {
    // Refit near/far (and the orthographic extent) around the scene for the new view.
    const hsr::Bounds b = scene.bounds();
    const float dist = glm::length(b.center() - cam.eye);
    const float r = b.radius();
    cam.near = std::max(dist - 1.5f * r, std::max(dist, r) * 1e-3f);
    cam.far = dist + 1.5f * r;
    cam.ortho_half_height = std::max(r, 1e-6f) * 1.05f;
  }
  if (!a.near.empty()) cam.near = parseFloat(a.near, "--near");
  if (!a.far.empty()) cam.far = parseFloat(a.far, "--far");
  cam.validate();
  return cam;
}

hsr::RenderOptions makeOptions(const Args& a) {
  hsr::RenderOptions o;
  o.algorithm = a.algorithm;
  o.cull = hsr::parseCullMode(a.cull);
  o.front_face = hsr::parseFrontFace(a.front_face);
  o.polygon_mode = hsr::parsePolygonMode(a.polygon_mode);
  o.depth_func = hsr::parseDepthFunc(a.depth_func);
  o.depth_test = !a.no_depth_test;
  o.depth_mask = !a.no_depth_mask;
  o.outline = a.outline;
  o.shade = !a.flat;
  if (a.facing == "window") o.facing_test = hsr::FacingTest::WindowArea;
  else if (a.facing == "eye") o.facing_test = hsr::FacingTest::EyePlane;
  else throw hsr::Error(fmt::format("unknown facing test '{}' (window, eye)", a.facing));
  if (a.threads < 0) throw hsr::Error("--threads must be >= 0");
  o.threads = a.threads;
  o.samples = a.samples;
  if (!(a.fragment_memory_mib > 0) || a.fragment_memory_mib > 1048576)
    throw hsr::Error("--fragment-memory must be between 0 and 1048576 MiB");
  o.fragment_memory = static_cast<std::uint64_t>(a.fragment_memory_mib * 1048576.0);
  o.bsp.splitter = a.bsp_splitter;
  o.bsp.seed = a.bsp_seed;
  o.bsp.candidates = a.bsp_candidates;
  return o;
}

void addBspBuildOptions(CLI::App* app, Args& a) {
  app->add_option("--bsp-splitter", a.bsp_splitter,
                  "how each BSP node's splitter is chosen: first|random|fewest|balanced|best-of-k")
      ->capture_default_str();
  app->add_option("--bsp-seed", a.bsp_seed, "seed of the random and sampled splitter choices")
      ->capture_default_str();
  app->add_option("--bsp-candidates", a.bsp_candidates, "polygons sampled per node by balanced and best-of-k")
      ->capture_default_str();
}

void addViewOptions(CLI::App* app, Args& a) {
  app->add_option("scene", a.scene, "mesh file (OBJ, PLY, STL, OFF, glTF, ...) or built-in scene")
      ->capture_default_str();
  app->add_option("--size", a.size, "image size WxH")->capture_default_str();
  app->add_option("--eye", a.eye, "camera position X,Y,Z (gluLookAt eye)");
  app->add_option("--target", a.target, "point looked at X,Y,Z");
  app->add_option("--up", a.up, "up vector X,Y,Z");
  app->add_option("--fov", a.fov, "vertical field of view in degrees (gluPerspective; default 45)");
  app->add_flag("--ortho", a.ortho, "orthographic projection");
  app->add_option("--near", a.near, "near plane distance (> 0; default: fitted to the scene)");
  app->add_option("--far", a.far, "far plane distance (> near; default: fitted)");
  app->add_option("--cull", a.cull, "back-face culling: none|back|front|both")->capture_default_str();
  app->add_option("--front-face", a.front_face, "front-face winding: ccw|cw")->capture_default_str();
  app->add_option("--facing", a.facing,
                  "facing test: window (OpenGL's window-space area) | eye (the notes' N.V)")
      ->capture_default_str();
  app->add_option("--polygon-mode", a.polygon_mode, "fill|line|point")->capture_default_str();
  app->add_option("--depth-func", a.depth_func,
                  "never|less|equal|lequal|greater|notequal|gequal|always")->capture_default_str();
  app->add_flag("--no-depth-test", a.no_depth_test, "disable the depth test (draw in order)");
  app->add_flag("--no-depth-mask", a.no_depth_mask, "do not write the depth buffer");
  app->add_flag("--outline", a.outline, "draw silhouette edges over the fill");
  app->add_flag("--flat", a.flat, "material colour without headlight shading");
  app->add_option("--algorithm", a.algorithm, "visibility algorithm (see `hsr scenes`)")
      ->capture_default_str();
  app->add_flag("--allow-outside-refs", a.allow_outside_refs,
                "let a model read files it references outside its own folder (mtllib, buffers)");
  app->add_option("--threads", a.threads, "worker threads (0 = all); output is identical for any")
      ->capture_default_str();
  app->add_option("--samples", a.samples,
                  "sub-pixel samples per pixel for --algorithm abuffer: 1|4|8|16|32|64 (default 4)");
  app->add_option("--fragment-memory", a.fragment_memory_mib,
                  "most MiB the A-buffer's fragment lists may take; a frame needing more is refused")
      ->capture_default_str();
  addBspBuildOptions(app, a);
}

hsr::ImportLimits importLimits(const Args& a) {
  hsr::ImportLimits limits;
  limits.allow_outside_references = a.allow_outside_refs;
  return limits;
}

}  // namespace hsr::cli
