// The command line's view arguments: parsing and conversion (see args.hpp).

#include "args.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

#include <fmt/core.h>
#include <unistd.h>
#include <glm/geometric.hpp>

#include "hsr/error.hpp"

namespace hsr::cli {

namespace fs = std::filesystem;

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
  if (reach > kMaxCoordinate) {
    // The limit holds whether the camera is framed or given (every vertex goes through the same
    // float transforms and clipping, whose squared distances overflow past 1.8e19): so say what
    // to do, with the power of ten to scale by.
    const int down =
        static_cast<int>(std::ceil(std::log10(double(reach) / double(kMaxCoordinate))));
    throw hsr::Error(fmt::format(
        "{}: coordinates reach {:.3g}, beyond the +-1e18 that hsr's float camera arithmetic is "
        "held to (a camera given by hand does not lift it); scale the model by 1e-{} or less "
        "(most exporters have a unit or scale option), or remove the vertices that far out",
        a.scene, reach, std::max(down, 1)));
  }
  if (b.lo == b.hi && scene.cameras.empty() && a.camera_file.empty() && a.pose_file.empty() &&
      (a.eye.empty() || a.target.empty()))
    throw hsr::Error(
        fmt::format("{}: every vertex lies at the same point ({:g}, {:g}, {:g}): "
                    "there is nothing with an extent to frame, or an area to draw",
                    a.scene, b.lo.x, b.lo.y, b.lo.z));
}

}  // namespace

void parseImageSize(const std::string& s, int* w, int* h) { parseSize(s, w, h); }

std::string readUserFile(const std::string& path, const char* option, std::uintmax_t limit) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) {
    if (ec &&
        ec != std::errc::no_such_file_or_directory)  // a loop of links, a folder it may not search
      throw hsr::Error(fmt::format("{} {}: {}", option, path, ec.message()));
    throw hsr::Error(fmt::format("{} {}: no such file", option, path));
  }
  if (!fs::is_regular_file(st)) {
    const char* what = fs::is_directory(st)        ? "a directory"
                       : fs::is_character_file(st) ? "a character device"
                       : fs::is_block_file(st)     ? "a block device"
                       : fs::is_fifo(st)           ? "a FIFO"
                       : fs::is_socket(st)         ? "a socket"
                                                   : "not a regular file";
    throw hsr::Error(fmt::format("{} {}: {}, not a file; name a file", option, path, what));
  }
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (ec || bytes > limit)
    throw hsr::Error(fmt::format("{} {}: {} (the limit is {} MiB)", option, path,
                                 ec ? "cannot read its size" : "too large", limit >> 20));
  std::ifstream in(path, std::ios::binary);
  std::string text(static_cast<std::size_t>(bytes), '\0');
  if (!in.read(text.data(), static_cast<std::streamsize>(text.size())))
    throw hsr::Error(fmt::format("{} {}: cannot be read", option, path));
  return text;
}

namespace {

hsr::Intrinsics parseIntrinsics(const std::string& s) {
  std::vector<double> v;
  std::size_t at = 0;
  while (at <= s.size()) {
    const std::size_t comma = std::min(s.find(',', at), s.size());
    const std::string part = s.substr(at, comma - at);
    char* end = nullptr;
    const double d = std::strtod(part.c_str(), &end);
    if (part.empty() || end != part.c_str() + part.size() || !std::isfinite(d))
      throw hsr::Error(fmt::format("--intrinsics must be fx,fy,cx,cy in pixels (got '{}')", s));
    v.push_back(d);
    at = comma + 1;
  }
  if (v.size() != 4)
    throw hsr::Error(fmt::format("--intrinsics must be fx,fy,cx,cy in pixels (got '{}')", s));
  // Every value given is used or refused: fx = fy = 0 is how a camera says "no intrinsics", so
  // zero focal lengths would otherwise be dropped for the default 45-degree camera
  if (!(v[0] > 0) || !(v[1] > 0))
    throw hsr::Error(fmt::format(
        "--intrinsics: the focal lengths fx and fy must be positive pixels (got '{}')", s));
  return {v[0], v[1], v[2], v[3]};
}

// Which of the scene file's cameras frames it: an index, or -1 for none (auto-framing)
int cameraIndex(const Args& a, const hsr::Scene& scene) {
  if (a.camera_index == "auto") return -1;
  char* end = nullptr;
  const long n = std::strtol(a.camera_index.c_str(), &end, 10);
  if (a.camera_index.empty() || end != a.camera_index.c_str() + a.camera_index.size() || n < 0)
    throw hsr::Error(fmt::format(
        "--camera-index must be a camera's number from 0, or auto (got '{}')", a.camera_index));
  if (n > 0 && static_cast<std::size_t>(n) >= scene.cameras.size())
    throw hsr::Error(fmt::format("--camera-index {}: {} has {} camera{}", n, a.scene,
                                 scene.cameras.size(), scene.cameras.size() == 1 ? "" : "s"));
  return static_cast<int>(n);
}

hsr::Camera cameraFromFile(const Args& a) {
  for (const auto& [given, name] : {std::pair{!a.eye.empty(), "--eye"},
                                    {!a.target.empty(), "--target"},
                                    {!a.up.empty(), "--up"},
                                    {!a.fov.empty(), "--fov"},
                                    {a.ortho, "--ortho"},
                                    {!a.intrinsics.empty(), "--intrinsics"},
                                    {!a.pose_file.empty(), "--pose"},
                                    {a.camera_index != "0", "--camera-index"}})
    if (given) throw hsr::Error(fmt::format("{} and --camera both set the view: give one", name));
  hsr::Camera cam;
  const std::string text = readUserFile(a.camera_file, "--camera", 16u << 20);  // names itself
  try {
    cam = hsr::cameraFromJson(text);
  } catch (const hsr::Error& e) {
    throw hsr::Error(fmt::format("--camera {}: {}", a.camera_file, e.what()));
  }
  if (!a.size.empty()) {
    int w = 0, h = 0;
    parseSize(a.size, &w, &h);
    if ((w != cam.width || h != cam.height) && cam.intrinsics.given())
      throw hsr::Error(fmt::format("--size {}: the camera's intrinsics are for {}x{} pixels",
                                   a.size, cam.width, cam.height));
    cam.width = w;
    cam.height = h;
  }
  return cam;
}

}  // namespace

hsr::Camera makeCamera(const Args& a, const hsr::Scene& scene) {
  checkFrameable(a, scene);
  const hsr::Bounds b = scene.bounds();
  hsr::Camera cam;
  if (!a.camera_file.empty()) {
    cam = cameraFromFile(a);
  } else {
    int w = 800, h = 600;
    if (!a.size.empty()) parseSize(a.size, &w, &h);
    const bool fov_given = !a.fov.empty();
    const float fov = fov_given ? parseFloat(a.fov, "--fov") : 45.0f;
    if (!(fov > 0.0f && fov < 180.0f))
      throw hsr::Error(fmt::format("--fov must be in (0, 180) degrees (got {})", a.fov));
    const int index = cameraIndex(a, scene);
    const bool file_camera = index >= 0 && static_cast<std::size_t>(index) < scene.cameras.size();
    // Framed with the given up axis (a Z-up model seen from its front three-quarter)
    const glm::vec3 up_axis = a.up.empty() ? glm::vec3(0.0f, 1.0f, 0.0f) : parseVec3(a.up, "--up");
    cam = file_camera ? hsr::fromSceneCamera(scene.cameras[index], b, w, h)
                      : hsr::frameBounds(b, w, h, fov, a.ortho, up_axis);
    if (fov_given) cam.fov_deg = fov;
    if (!a.intrinsics.empty()) {
      if (fov_given) throw hsr::Error("--fov and --intrinsics both set the projection: give one");
      if (a.ortho) throw hsr::Error("--intrinsics describe a pinhole camera: --ortho has none");
      cam.intrinsics = parseIntrinsics(a.intrinsics);
      cam.ortho = false;
    }
    bool moved = !a.eye.empty() || !a.target.empty();
    if (!a.pose_file.empty()) {
      if (!a.eye.empty() || !a.target.empty() || !a.up.empty())
        throw hsr::Error("--pose and --eye, --target or --up all place the camera: give one");
      const std::string text = readUserFile(a.pose_file, "--pose", 1u << 20);  // names itself
      try {
        hsr::setPose(cam, hsr::poseFromText(text), hsr::poseConventionNamed(a.pose_convention));
      } catch (const hsr::Error& e) {
        throw hsr::Error(fmt::format("--pose {}: {}", a.pose_file, e.what()));
      }
      moved = true;
    }
    if (!a.eye.empty()) cam.eye = parseVec3(a.eye, "--eye");
    if (!a.target.empty()) cam.target = parseVec3(a.target, "--target");
    if (!a.up.empty()) cam.up = parseVec3(a.up, "--up");
    // Near and far (and the orthographic extent) refitted around the scene for a new view
    if (moved) hsr::fitNearFar(cam, b);
    if (a.ortho) cam.ortho = true;
    if (cam.ortho && (moved || (a.ortho && file_camera && !scene.cameras[index].ortho)))
      cam.ortho_half_height = hsr::orthoHalfHeightFor(cam, b);
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
  o.point_size = a.point_size;
  if (!a.clear_depth.empty()) {
    o.clear_depth = parseFloat(a.clear_depth, "--clear-depth");
    if (!(o.clear_depth >= 0.0f && o.clear_depth <= 1.0f))
      throw hsr::Error(fmt::format(
          "--clear-depth must be in [0, 1], as glClearDepth clamps (got {})", a.clear_depth));
  }
  o.outline = a.outline;
  o.shade = !a.flat;
  if (a.facing == "window")
    o.facing_test = hsr::FacingTest::WindowArea;
  else if (a.facing == "eye")
    o.facing_test = hsr::FacingTest::EyePlane;
  else
    throw hsr::Error(fmt::format("unknown facing test '{}' (window, eye)", a.facing));
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
  app->add_option("--bsp-candidates", a.bsp_candidates,
                  "polygons sampled per node by balanced and best-of-k")
      ->capture_default_str();
}

void addViewOptions(CLI::App* app, Args& a) {
  app->add_option(
         "scene", a.scene,
         "mesh file (OBJ, PLY, STL, OFF, glTF, ...), a Doom map (FILE.wad:MAP01) or built-in scene")
      ->capture_default_str();
  app->add_option("--size", a.size, "image size WxH (default 800x600, or --camera's)");
  app->add_option("--eye", a.eye, "camera position X,Y,Z (gluLookAt eye)");
  app->add_option("--target", a.target, "point looked at X,Y,Z");
  app->add_option("--up", a.up, "up vector X,Y,Z");
  app->add_option("--fov", a.fov, "vertical field of view in degrees (gluPerspective; default 45)");
  app->add_flag("--ortho", a.ortho, "orthographic projection");
  app->add_option("--near", a.near, "near plane distance (> 0; default: fitted to the scene)");
  app->add_option("--far", a.far, "far plane distance (> near; default: fitted)");
  app->add_option("--camera", a.camera_file,
                  "the view from a camera JSON file, as --stats or --raw's manifest.json write it");
  app->add_option("--camera-index", a.camera_index,
                  "which of the model file's cameras (glTF) frames it: N, or auto to ignore them")
      ->capture_default_str();
  app->add_option("--intrinsics", a.intrinsics,
                  "pinhole intrinsics fx,fy,cx,cy in pixels (OpenCV: pixel centres at integers, "
                  "(0,0) the top-left pixel's centre)");
  app->add_option("--pose", a.pose_file,
                  "file with the camera's pose: 4x4 (or 3x4) camera-to-world matrix, row by row");
  app->add_option("--pose-convention", a.pose_convention,
                  "the pose's camera axes: opencv (x right, y down, z forward) | opengl "
                  "(x right, y up, looking down -z)")
      ->capture_default_str();
  app->add_option("--cull", a.cull, "back-face culling: none|back|front|both")
      ->capture_default_str();
  app->add_option("--front-face", a.front_face, "front-face winding: ccw|cw")
      ->capture_default_str();
  app->add_option("--facing", a.facing,
                  "facing test: window (OpenGL's window-space area) | eye (the notes' N.V)")
      ->capture_default_str();
  app->add_option("--polygon-mode", a.polygon_mode, "fill|line|point")->capture_default_str();
  app->add_option("--point-size", a.point_size,
                  "--polygon-mode point: each vertex as a square of this many pixels, as "
                  "glPointSize (1 to 64)")
      ->capture_default_str();
  app->add_option("--depth-func", a.depth_func,
                  "never|less|equal|lequal|greater|notequal|gequal|always")
      ->capture_default_str();
  app->add_option("--clear-depth", a.clear_depth,
                  "the depth the buffer is cleared to, as glClearDepth (default 1; 0 lets "
                  "--depth-func greater draw)");
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
  app->add_option(
      "--samples", a.samples,
      "sub-pixel samples per pixel for --algorithm abuffer: 1|4|8|16|32|64 (default 4)");
  app->add_option(
         "--fragment-memory", a.fragment_memory_mib,
         "most MiB the A-buffer's fragment lists may take; a frame needing more is refused")
      ->capture_default_str();
  addBspBuildOptions(app, a);
}

hsr::ImportLimits importLimits(const Args& a) {
  hsr::ImportLimits limits;
  limits.allow_outside_references = a.allow_outside_refs;
  // A long import shows how long it has run on a terminal (from its first second on)
  if (!a.quiet && ::isatty(STDERR_FILENO)) {
    const std::string name = fs::path(a.scene).filename().string();
    limits.progress = [name, shown = false](double seconds, std::uint64_t bytes,
                                            bool done) mutable {
      if (seconds < 1.0 && !shown) return;
      shown = true;
      fmt::print(
          stderr, "\r  importing {}: {:.1f} s{}{}", name, seconds,
          bytes > 0 ? fmt::format(", {:.0f} MiB received", bytes / 1048576.0) : std::string(),
          done ? "\n" : "");
    };
  }
  return limits;
}

}  // namespace hsr::cli
