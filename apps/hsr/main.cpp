// hsr: the command line. The only code that parses argv, prints, and picks exit codes:
// 0 success, 2 bad input or usage (one line on stderr), 1 internal error.

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/vector_relational.hpp>
#include <fmt/core.h>

#include "hsr/compare.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"

namespace fs = std::filesystem;

namespace {

struct Args {
  std::string scene = "demo";
  std::string size = "800x600";
  std::string eye, target, up;
  std::string fov;  // empty: 45, or the scene file's camera
  bool ortho = false;
  std::string near, far;  // empty: fitted to the scene
  std::string cull = "none", front_face = "ccw", polygon_mode = "fill", depth_func = "less";
  std::string facing = "window";
  bool no_depth_test = false, no_depth_mask = false, outline = false, flat = false;
  std::string algorithm = "zbuffer";
  std::string outputs = "color";
  std::string output_file;
  std::string raw_dir, stats_file, sheet_file;
  int threads = 0;
  bool quiet = false;
};

// A whole string as one float (nan and inf parse; the camera check refuses them).
float parseFloat(const std::string& s, const char* what) {
  char* end = nullptr;
  errno = 0;
  const float v = std::strtof(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE)
    throw hsr::Error(fmt::format("{} must be a number (got '{}')", what, s));
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

std::string sceneLabel(const std::string& spec) {
  std::string name = fs::exists(spec) ? fs::path(spec).stem().string() : spec;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return name;
}

hsr::Camera makeCamera(const Args& a, const hsr::Scene& scene) {
  int w = 0, h = 0;
  parseSize(a.size, &w, &h);
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

// Rendering from inside an object is legitimate (the near plane clips what surrounds the
// eye), but often a mistake: say so on one line.
void warnIfEyeInside(const hsr::Scene& scene, const hsr::Camera& cam) {
  if (cam.ortho) return;
  for (const hsr::Object& o : scene.objects) {
    const hsr::Bounds& b = o.bounds;
    if (b.empty()) continue;
    if (glm::all(glm::greaterThanEqual(cam.eye, b.lo)) && glm::all(glm::lessThanEqual(cam.eye, b.hi))) {
      std::fprintf(stderr, "hsr: warning: the eye is inside the bounds of object '%s'; what "
                   "surrounds it is clipped at the near plane\n", o.name.c_str());
      return;
    }
  }
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
  return o;
}

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == ',') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

void ensureParent(const fs::path& p) {
  if (p.has_parent_path()) fs::create_directories(p.parent_path());
}

void printSummary(const hsr::Frame& f, const std::string& scene, const std::string& algorithm,
                  const std::vector<std::string>& written) {
  const hsr::Stats& s = f.stats;
  fmt::print("hsr {} {}  {}x{}\n", algorithm, scene, f.width, f.height);
  fmt::print("  polygons in        {:>12}   triangles {:>12}\n", s.polygons_in, s.triangles_in);
  fmt::print("  degenerate dropped {:>12}\n", s.degenerate_dropped);
  fmt::print("  frustum culled     {:>12}   (polygons of objects outside the view)\n", s.culled_frustum);
  fmt::print("  back-face culled   {:>12}   (triangles)\n", s.culled_backface);
  fmt::print("  clipped            {:>12}   clipped away {:>12}\n", s.clipped, s.clipped_away);
  fmt::print("  rasterized         {:>12}\n", s.triangles_rasterized);
  fmt::print("  fragments tested   {:>12}   written {:>12}\n", s.fragments_tested, s.fragments_written);
  fmt::print("  state memory       {:>12.1f} MiB ({:.1f} bytes/pixel)\n",
             s.state_bytes / 1048576.0, double(s.state_bytes) / (double(f.width) * f.height));
  fmt::print("  time per stage:");
  for (const hsr::StageTime& st : s.stages) fmt::print("  {} {:.2f} ms", st.name, st.ms);
  fmt::print("\n  total {:.2f} ms\n", s.totalMs());
  for (const std::string& w : written) fmt::print("  wrote {}\n", w);
}

int runRender(const Args& a) {
  const hsr::Scene scene = hsr::loadScene(a.scene);
  const hsr::Camera cam = makeCamera(a, scene);
  warnIfEyeInside(scene, cam);
  const hsr::RenderOptions opt = makeOptions(a);
  const std::vector<std::string> kinds = splitList(a.outputs);
  if (kinds.empty()) throw hsr::Error("--output needs at least one of color,depth,ids,overdraw");
  for (const std::string& k : kinds)
    if (k != "color" && k != "depth" && k != "ids" && k != "overdraw")
      throw hsr::Error(fmt::format("unknown output '{}' (color, depth, ids, overdraw)", k));
  const hsr::Frame frame = hsr::render(scene, cam, opt);

  std::vector<std::string> written;
  const fs::path base = a.output_file.empty() ? fs::path("out") / (sceneLabel(a.scene) + ".png")
                                              : fs::path(a.output_file);
  for (const std::string& k : kinds) {
    fs::path p = base;
    if (kinds.size() > 1) p.replace_filename(base.stem().string() + "-" + k + ".png");
    ensureParent(p);
    hsr::writePng(p, frame.width, frame.height, 3, hsr::picture(frame, k).data());
    written.push_back(p.string());
  }
  if (!a.raw_dir.empty()) {
    const fs::path d(a.raw_dir);
    fs::create_directories(d);
    hsr::writeNpy(d / "depth.npy", frame.width, frame.height, frame.depth.data());
    hsr::writeNpy(d / "ids.npy", frame.width, frame.height, frame.ids.data());
    hsr::writeNpy(d / "overdraw.npy", frame.width, frame.height, frame.overdraw.data());
    written.push_back((d / "{depth,ids,overdraw}.npy").string());
  }
  if (!a.stats_file.empty()) {
    const fs::path p(a.stats_file);
    ensureParent(p);
    std::FILE* f = std::fopen(p.string().c_str(), "wb");
    if (!f) throw hsr::Error(fmt::format("{}: cannot open for writing", p.string()));
    const std::string json = hsr::statsJson(frame, a.scene, opt.algorithm);
    const bool ok = std::fwrite(json.data(), 1, json.size(), f) == json.size();
    if (std::fclose(f) != 0 || !ok) throw hsr::Error(fmt::format("{}: write failed", p.string()));
    written.push_back(p.string());
  }
  if (!a.quiet) printSummary(frame, a.scene, opt.algorithm, written);
  return 0;
}

int runCompare(const Args& a) {
  const hsr::Scene scene = hsr::loadScene(a.scene);
  const hsr::Camera cam = makeCamera(a, scene);
  const hsr::RenderOptions opt = makeOptions(a);
  const std::vector<hsr::ComparisonRow> rows = hsr::compareAlgorithms(scene, cam, opt);
  fmt::print("hsr compare {}  {}x{}  ({} polygons)\n", a.scene, cam.width, cam.height,
             scene.polygonCount());
  fmt::print("  {:<12} {:>10} {:>12} {:>10} {:>8} {:>12} {:>10}\n", "algorithm", "time ms",
             "memory MiB", "overdraw", "max", "ids = zbuf", "differ px");
  for (const hsr::ComparisonRow& r : rows)
    fmt::print("  {:<12} {:>10.2f} {:>12.1f} {:>10.2f} {:>8} {:>11.4f}% {:>10}\n", r.algorithm,
               r.ms, r.state_bytes / 1048576.0, r.mean_overdraw, r.max_overdraw,
               100.0 * r.id_agreement, r.differing_pixels);
  if (!a.sheet_file.empty()) {
    int w = 0, h = 0;
    const std::vector<std::uint8_t> sheet = hsr::comparisonSheet(rows, &w, &h);
    ensureParent(a.sheet_file);
    hsr::writePng(a.sheet_file, w, h, 3, sheet.data());
    fmt::print("  wrote {}\n", a.sheet_file);
  }
  return 0;
}

int runScenes() {
  fmt::print("built-in scenes (a file of the same name wins):\n");
  for (const hsr::BuiltinScene& s : hsr::builtinScenes()) fmt::print("  {:<16} {}\n", s.name, s.summary);
  fmt::print("algorithms:\n");
  for (const hsr::AlgorithmInfo& i : hsr::algorithms())
    fmt::print("  {:<16} {} precision: {}\n", i.name, i.precision, i.summary);
  return 0;
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
  app->add_option("--threads", a.threads, "worker threads (0 = all); output is identical for any")
      ->capture_default_str();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hsr: hidden-surface removal with every classic algorithm.\n"
               "Examples:\n"
               "  hsr                                  render the demo scene to out/demo.png\n"
               "  hsr render spheres:100000 --size 1920x1080 --cull back -o out/s.png\n"
               "  hsr render model.obj --output color,depth,ids,overdraw --raw out/raw\n"
               "  hsr render demo --polygon-mode line --eye 4,3,6 --target 0,0,0\n"
               "  hsr compare demo --sheet out/sheet.png\n"
               "  hsr scenes"};
  app.require_subcommand(0, 1);
  Args a;
  CLI::App* render = app.add_subcommand("render", "render SCENE with one algorithm");
  addViewOptions(render, a);
  render->add_option("--output", a.outputs, "pictures to write: color,depth,ids,overdraw")
      ->capture_default_str();
  render->add_option("-o", a.output_file, "output PNG (default out/SCENE.png; with several "
                                          "outputs, FILE-KIND.png)");
  render->add_option("--raw", a.raw_dir, "write depth.npy, ids.npy, overdraw.npy into DIR");
  render->add_option("--stats", a.stats_file, "write counts and stage times as JSON");
  render->add_flag("-q,--quiet", a.quiet, "no summary");
  CLI::App* compare = app.add_subcommand("compare", "run every algorithm on SCENE and compare");
  addViewOptions(compare, a);
  compare->add_option("--sheet", a.sheet_file, "write the pictures side by side, labelled");
  CLI::App* scenes = app.add_subcommand("scenes", "list built-in scenes and algorithms");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "hsr: %s (see hsr --help)\n", e.what());
    return 2;
  }

  try {
    if (*scenes) return runScenes();
    if (*compare) return runCompare(a);
    return runRender(a);  // `render`, or no verb at all: the demo scene
  } catch (const hsr::Error& e) {
    std::fprintf(stderr, "hsr: %s\n", e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "hsr: out of memory\n");
    return 1;
  } catch (const fs::filesystem_error& e) {
    std::fprintf(stderr, "hsr: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hsr: internal error: %s\n", e.what());
    return 1;
  }
}
