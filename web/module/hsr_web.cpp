// The web page's module: hsr's core behind a small C API that JavaScript calls (Emscripten's
// ccall/cwrap), built to WebAssembly for the page (web/) and natively for the tests, which
// compare the two builds byte for byte (web/test/).
//
// One scene and one frame are held at a time. Requests and answers are JSON text; buffers are
// pointers into the module's memory, valid until the next call that renders or loads:
//
//   hsr_web_load("spheres:2000")            a built-in scene (or hsr_web_load_obj(text, name))
//   hsr_web_render("{\"algorithm\": \"warnock\", \"width\": 320, \"height\": 240}")
//   hsr_web_picture("color")                RGBA8 of "color", "depth", "ids" or "overdraw"
//   hsr_web_depth(), hsr_web_ids()          the buffers themselves (float, uint32)
//   hsr_web_explain(request)                the algorithm's steps (hsr explain), then
//   hsr_web_step(i), hsr_web_step_picture(i, "color" | "depth")
//
// A call that fails returns -1 (or null) and hsr_web_error() says why in one line, as the CLI
// would. Nothing here reads or writes files.

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <exception>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "hsr/algorithms.hpp"
#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/explain.hpp"
#include "hsr/frontend.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

#ifdef __EMSCRIPTEN__
#include <emscripten/emscripten.h>
#define HSR_WEB_EXPORT EMSCRIPTEN_KEEPALIVE
#else
#define HSR_WEB_EXPORT
#endif

namespace {

using nlohmann::json;

// The largest picture the page asks for: 2048x2048 (a render's buffers and an explanation's
// pictures stay within the browser's memory)
constexpr int kMaxSide = 2048;

struct Step {
  std::string name, caption;
  std::vector<std::vector<glm::vec2>> outlines;
  std::vector<std::uint8_t> color, depth;  // RGBA8
};

struct State {
  hsr::Scene scene;
  bool loaded = false;
  hsr::Frame frame;
  std::vector<std::uint8_t> picture;  // the last hsr_web_picture's RGBA
  std::vector<Step> steps;
  std::string text;  // the last JSON answer
  std::string error;
};

State& state() {
  static State s;
  return s;
}

// RGB8 (hsr's pictures) as RGBA8 with alpha 255, as a canvas's ImageData holds it.
std::vector<std::uint8_t> rgba(const std::vector<std::uint8_t>& rgb) {
  std::vector<std::uint8_t> out(rgb.size() / 3 * 4);
  for (std::size_t i = 0, j = 0; i + 2 < rgb.size(); i += 3, j += 4) {
    out[j] = rgb[i], out[j + 1] = rgb[i + 1], out[j + 2] = rgb[i + 2];
    out[j + 3] = 255;
  }
  return out;
}

// Runs f, turning an exception into -1 and the error line.
template <class F>
int guarded(F&& f) {
  State& s = state();
  s.error.clear();
  try {
    return f();
  } catch (const std::exception& e) {
    s.error = e.what();
  }
  return -1;
}

// A JSON value as the option table takes it: a bool, a whole number, a number, a string, or
// an array of numbers.
hsr::OptionValue valueOf(const std::string& name, const json& v) {
  if (v.is_boolean()) return v.get<bool>();
  if (v.is_number_integer()) return v.get<std::int64_t>();
  if (v.is_number()) return v.get<double>();
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array() && std::all_of(v.begin(), v.end(), [](const json& x) { return x.is_number(); }))
    return v.get<std::vector<double>>();
  throw hsr::Error(name + " must be a bool, a number, a string or numbers (got " + v.dump() + ")");
}

// The request, read by the library's option table (hsr/frontend.hpp) and checked as `hsr
// render` checks its flags, with the same messages: "width" and "height" (default 320x240) are
// the size, the page's "camera" {eye, target, up, fov_deg, ortho} its view (fov_deg is the
// table's fov), and every other key an option of the table by its name. With no camera, the
// scene is framed as `hsr render` frames it; with one, near and far are fitted to the scene.
hsr::OptionRequest optionsOf(const json& r) {
  hsr::OptionRequest q(hsr::FrontEnd::kWeb);
  std::vector<double> size{320, 240};
  int w = 0, h = 0;
  for (const auto& [key, value] : r.items()) {
    if (key == "width" || key == "height") {
      if (!value.is_number())
        throw hsr::Error(key + " must be a number of pixels (got " + value.dump() + ")");
      size[key == "width" ? 0 : 1] = value.get<double>();
    } else if (key == "size") {
      q.set("size", valueOf(key, value));  // checked, then read back for the page's limit
      q.size(&w, &h);
      size = {double(w), double(h)};
    } else if (key == "camera") {
      if (!value.is_object()) throw hsr::Error("camera must be an object");
      for (const auto& [k, v] : value.items()) {
        const std::string name = k == "fov_deg" ? "fov" : k;
        q.set(name, valueOf(name, v));
      }
    } else {
      q.set(key, valueOf(key, value));
    }
  }
  q.set("size", size);  // checked as the table checks a size; then the page's own limit
  if (size[0] > kMaxSide || size[1] > kMaxSide)
    throw hsr::Error("size " + std::to_string(int(size[0])) + "x" + std::to_string(int(size[1])) +
                     ": 1 to " + std::to_string(kMaxSide) + " pixels a side");
  if (!r.contains("threads")) q.set("threads", std::int64_t{1});  // the module runs one thread
  return q;
}

hsr::Camera cameraOf(const hsr::OptionRequest& q, const hsr::Scene& scene) {
  return q.camera(scene, scene.name.empty() ? "the scene" : scene.name);
}

// The render state; an unknown algorithm is refused as the CLI refuses it.
hsr::RenderOptions renderOptionsOf(const hsr::OptionRequest& q) {
  hsr::RenderOptions o = q.options();
  (void)hsr::findAlgorithm(o.algorithm);
  return o;
}

json requestOf(const char* text) {
  json r = json::parse(text ? text : "{}", nullptr, /*allow_exceptions=*/false);
  if (!r.is_object()) throw hsr::Error("request: not a JSON object");
  return r;
}

void requireScene() {
  if (!state().loaded) throw hsr::Error("no scene loaded");
}

const char* answer(const json& j) {
  state().text = j.dump(-1, ' ', false, json::error_handler_t::replace);
  return state().text.c_str();
}

}  // namespace

extern "C" {

HSR_WEB_EXPORT const char* hsr_web_error() { return state().error.c_str(); }

// The built-in scenes and the registry's algorithms, as JSON.
HSR_WEB_EXPORT const char* hsr_web_catalogue() {
  json scenes = json::array(), algorithms = json::array();
  for (const hsr::BuiltinScene& b : hsr::builtinScenes())
    scenes.push_back({{"name", b.name}, {"summary", b.summary}});
  for (const hsr::AlgorithmInfo& a : hsr::algorithms())
    algorithms.push_back({{"name", a.name},
                          {"summary", a.summary},
                          {"source", a.source},
                          {"precision", a.precision == hsr::Precision::kImage ? "image" : "object"},
                          {"capabilities", hsr::capabilityList(a.capabilities)},
                          {"explain", hsr::explainedBy(a) != nullptr},
                          {"reference", a.reference},
                          {"demonstration", a.demonstration},
                          {"textbook", a.textbook},
                          {"sibling", a.sibling},
                          {"max_pixels", a.max_pixels}});
  return answer({{"scenes", scenes}, {"algorithms", algorithms}});
}

// Loads a built-in scene by its spec ("demo", "spheres:2000", "soup:500:7"); 0 or -1.
HSR_WEB_EXPORT int hsr_web_load(const char* spec) {
  return guarded([&] {
    // The page's memory is the browser's: a million triangles at most
    state().scene = hsr::makeBuiltinScene(spec ? spec : "", 1'000'000);
    state().loaded = true;
    return 0;
  });
}

// Loads Wavefront OBJ text (a file dropped on the page); 0 or -1.
HSR_WEB_EXPORT int hsr_web_load_obj(const char* text, const char* name) {
  return guarded([&] {
    state().scene = hsr::parseObjText(text ? text : "", name ? name : "dropped.obj");
    state().loaded = true;
    return 0;
  });
}

// The loaded scene: name, counts, bounds, and the camera `hsr render` frames it with at the
// request's size (the page's orbit starts there).
HSR_WEB_EXPORT const char* hsr_web_scene(const char* request) {
  json j;
  const int ok = guarded([&] {
    requireScene();
    const hsr::Scene& s = state().scene;
    const hsr::Camera c = cameraOf(optionsOf(requestOf(request)), s);
    const hsr::Bounds b = s.bounds();
    j = {{"name", s.name},
         {"polygons", s.polygonCount()},
         {"triangles", s.triangleCount()},
         {"vertices", s.vertexCount()},
         {"objects", s.objects.size()},
         {"bounds", {{"lo", {b.lo.x, b.lo.y, b.lo.z}}, {"hi", {b.hi.x, b.hi.y, b.hi.z}}}},
         {"camera",
          {{"eye", {c.eye.x, c.eye.y, c.eye.z}},
           {"target", {c.target.x, c.target.y, c.target.z}},
           {"up", {c.up.x, c.up.y, c.up.z}},
           {"fov_deg", c.fov_deg},
           {"near", c.near},
           {"far", c.far}}}};
    return 0;
  });
  return ok == 0 ? answer(j) : nullptr;
}

// Renders the loaded scene as the request says; 0 or -1. The request: "width", "height",
// "camera" {eye, target, up, fov_deg, ortho}, and every option of the library's table
// (hsr/frontend.hpp) by its name: "algorithm", the GL-style controls ("cull", "front_face",
// "depth_test", "depth_func", "depth_mask", "clear_depth", "polygon_mode", "point_size",
// "outline"), "samples" and the rest, each checked as the CLI checks it.
HSR_WEB_EXPORT int hsr_web_render(const char* request) {
  return guarded([&] {
    requireScene();
    const hsr::OptionRequest q = optionsOf(requestOf(request));
    const hsr::RenderOptions options = renderOptionsOf(q);
    const hsr::Camera camera = cameraOf(q, state().scene);
    const std::string why =
        hsr::unsupported(hsr::findAlgorithm(options.algorithm), camera, options);
    if (!why.empty()) throw hsr::Error(why);
    hsr::render(state().scene, camera, options, state().frame);
    return 0;
  });
}

HSR_WEB_EXPORT int hsr_web_width() { return state().frame.width; }
HSR_WEB_EXPORT int hsr_web_height() { return state().frame.height; }

// The last frame's picture of one kind (color, depth, ids, overdraw) as RGBA8, top row first.
HSR_WEB_EXPORT const std::uint8_t* hsr_web_picture(const char* kind) {
  std::uint8_t* out = nullptr;
  guarded([&] {
    state().picture = rgba(hsr::picture(state().frame, kind ? kind : ""));
    out = state().picture.data();
    return 0;
  });
  return out;
}

// The last frame's buffers: window depth (float), polygon ids (uint32, 0xFFFFFFFF where nothing
// was drawn), fragments per pixel (uint32); width x height each, top row first.
HSR_WEB_EXPORT const float* hsr_web_depth() { return state().frame.depth.data(); }
HSR_WEB_EXPORT const std::uint32_t* hsr_web_ids() { return state().frame.ids.data(); }
HSR_WEB_EXPORT const std::uint32_t* hsr_web_overdraw() { return state().frame.overdraw.data(); }

// The last frame's statistics: the pipeline's counts, the algorithm's counters, stage times.
HSR_WEB_EXPORT const char* hsr_web_stats() {
  const hsr::Stats& s = state().frame.stats;
  json fields = json::object(), counters = json::object(), stages = json::array();
  for (const hsr::Stats::Field& f : hsr::Stats::fields()) fields[std::string(f.name)] = s.*f.value;
  for (const hsr::Counter& c : s.counters) counters[c.name] = c.value;
  for (const hsr::StageTime& st : s.stages) stages.push_back({{"name", st.name}, {"ms", st.ms}});
  return answer(
      {{"fields", fields}, {"counters", counters}, {"stages", stages}, {"total_ms", s.totalMs()}});
}

// Runs the request's algorithm with its steps traced, as `hsr explain` does; the number of
// steps, or -1 (an algorithm without the explain capability is refused).
HSR_WEB_EXPORT int hsr_web_explain(const char* request) {
  return guarded([&] {
    requireScene();
    const hsr::OptionRequest q = optionsOf(requestOf(request));
    const hsr::RenderOptions options = renderOptionsOf(q);
    const hsr::Camera camera = cameraOf(q, state().scene);
    State& s = state();
    hsr::Explanation e = hsr::explainSteps(s.scene, camera, options);
    s.frame = std::move(e.frame);
    s.steps.clear();
    for (hsr::ExplainedStep& step : e.steps)
      s.steps.push_back({std::move(step.name), std::move(step.caption), std::move(step.outlines),
                         rgba(step.color), rgba(step.depth)});
    return static_cast<int>(s.steps.size());
  });
}

// Step i (0-based) of the last explanation: number, name, caption and outlines (window
// coordinates, pixel centres, y down), as JSON.
HSR_WEB_EXPORT const char* hsr_web_step(int i) {
  const std::vector<Step>& steps = state().steps;
  if (i < 0 || static_cast<std::size_t>(i) >= steps.size()) return nullptr;
  const Step& s = steps[static_cast<std::size_t>(i)];
  json outlines = json::array();
  for (const auto& o : s.outlines) {
    json points = json::array();
    for (const glm::vec2& p : o) points.push_back(p.x), points.push_back(p.y);
    outlines.push_back(std::move(points));
  }
  return answer(
      {{"number", i + 1}, {"name", s.name}, {"caption", s.caption}, {"outlines", outlines}});
}

// Step i's colour or depth buffer at that moment, RGBA8.
HSR_WEB_EXPORT const std::uint8_t* hsr_web_step_picture(int i, const char* kind) {
  const std::vector<Step>& steps = state().steps;
  if (i < 0 || static_cast<std::size_t>(i) >= steps.size() || !kind) return nullptr;
  const Step& s = steps[static_cast<std::size_t>(i)];
  return std::string_view(kind) == "depth" ? s.depth.data() : s.color.data();
}

}  // extern "C"
