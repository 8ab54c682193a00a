// The front-ends' one table of options and the request that checks and combines them (see
// hsr/frontend.hpp). Tested by tests/frontend_test.cpp (the table against the registry and
// render()), and the three front-ends against one list of cases by tests/cli/frontends_test.cpp,
// tests/python/test_frontends.py and web/test/node_test.mjs (tests/frontend/cases.json).

#include "hsr/frontend.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <glm/geometric.hpp>

#include "hsr/algorithms.hpp"
#include "hsr/error.hpp"

namespace hsr {
namespace {

using K = OptionKind;
constexpr double kInf = std::numeric_limits<double>::infinity();

// The table, laid out by hand (an entry to a few lines). Each reads: name, kind, view or render
// state, default, help; then what the kind needs.
// clang-format off
const OptionSpec kSpecs[] = {
    // The view
    {.name = "size", .kind = K::kVector, .view = true, .default_text = "",
     .help = "image size WxH (default 800x600, or --camera's)", .choices = "WxH", .count = 2},
    {.name = "eye", .kind = K::kVector, .view = true, .default_text = "",
     .help = "camera position X,Y,Z (gluLookAt eye)", .choices = "X,Y,Z", .count = 3},
    {.name = "target", .kind = K::kVector, .view = true, .default_text = "",
     .help = "point looked at X,Y,Z", .choices = "X,Y,Z", .count = 3},
    {.name = "up", .kind = K::kVector, .view = true, .default_text = "", .help = "up vector X,Y,Z",
     .choices = "X,Y,Z", .count = 3},
    {.name = "fov", .kind = K::kNumber, .view = true, .default_text = "",
     .help = "vertical field of view in degrees (gluPerspective; default 45)", .lo = 0, .hi = 180,
     .lo_open = true, .hi_open = true, .note = " degrees"},
    {.name = "ortho", .kind = K::kFlag, .view = true, .default_text = "false",
     .help = "orthographic projection"},
    {.name = "near", .kind = K::kNumber, .view = true, .default_text = "",
     .help = "near plane distance (> 0; default: fitted to the scene)"},
    {.name = "far", .kind = K::kNumber, .view = true, .default_text = "",
     .help = "far plane distance (> near; default: fitted)"},
    {.name = "camera", .kind = K::kFile, .view = true, .default_text = "",
     .help = "the view from a camera JSON file, as --stats or --raw's manifest.json write it",
     .front_ends = kCommandLineOnly},
    {.name = "camera_index", .kind = K::kText, .view = true, .default_text = "0",
     .help = "which of the model file's cameras (glTF) frames it: N, or auto to ignore them"},
    {.name = "intrinsics", .kind = K::kVector, .view = true, .default_text = "",
     .help = "pinhole intrinsics fx,fy,cx,cy in pixels (OpenCV: pixel centres at integers, "
             "(0,0) the top-left pixel's centre)",
     .choices = "fx,fy,cx,cy in pixels", .count = 4, .wide = true},
    {.name = "pose", .kind = K::kFile, .view = true, .default_text = "",
     .help = "file with the camera's pose: 4x4 (or 3x4) camera-to-world matrix, row by row",
     .front_ends = kCommandLineOnly},
    {.name = "pose_convention", .kind = K::kName, .view = true, .default_text = "opencv",
     .help = "the pose's camera axes: opencv (x right, y down, z forward) | opengl "
             "(x right, y up, looking down -z)",
     .choices = "opencv|opengl", .front_ends = kCommandLineOnly},
    // The render state
    {.name = "cull", .kind = K::kName, .view = false, .default_text = "none",
     .help = "back-face culling: none|back|front|both", .choices = "none|back|front|both"},
    {.name = "front_face", .kind = K::kName, .view = false, .default_text = "ccw",
     .help = "front-face winding: ccw|cw", .choices = "ccw|cw"},
    {.name = "facing", .kind = K::kName, .view = false, .default_text = "window",
     .help = "facing test: window (OpenGL's window-space area) | eye (the notes' N.V)",
     .choices = "window|eye"},
    {.name = "polygon_mode", .kind = K::kName, .view = false, .default_text = "fill",
     .help = "fill|line|point", .choices = "fill|line|point", .needs = kPolygonModes,
     .trial = "line"},
    {.name = "point_size", .kind = K::kNumber, .view = false, .default_text = "1",
     .help = "polygon mode point: each vertex as a square of this many pixels, as glPointSize "
             "(1 to 64)",
     .lo = 1, .hi = 64, .note = " pixels, as glPointSize"},
    {.name = "depth_func", .kind = K::kName, .view = false, .default_text = "less",
     .help = "never|less|equal|lequal|greater|notequal|gequal|always",
     .choices = "never|less|equal|lequal|greater|notequal|gequal|always", .needs = kDepthFuncs,
     .trial = "greater"},
    {.name = "clear_depth", .kind = K::kNumber, .view = false, .default_text = "1",
     .help = "the depth the buffer is cleared to, as glClearDepth (0 lets depth func greater "
             "draw)",
     .lo = 0, .hi = 1, .note = ", as glClearDepth clamps"},
    {.name = "depth_test", .kind = K::kFlag, .view = false, .default_text = "true",
     .help = "disable the depth test (draw in order)", .needs = kDepthFuncs, .trial = "false",
     .cli = "no-depth-test"},
    {.name = "depth_mask", .kind = K::kFlag, .view = false, .default_text = "true",
     .help = "do not write the depth buffer", .needs = kDepthMask, .trial = "false",
     .cli = "no-depth-mask"},
    {.name = "outline", .kind = K::kFlag, .view = false, .default_text = "false",
     .help = "draw silhouette edges over the fill", .needs = kOutline, .trial = "true"},
    {.name = "shade", .kind = K::kFlag, .view = false, .default_text = "true",
     .help = "material colour without headlight shading", .cli = "flat"},
    {.name = "algorithm", .kind = K::kName, .view = false, .default_text = "zbuffer",
     .help = "visibility algorithm (see `hsr scenes`)"},
    {.name = "threads", .kind = K::kInteger, .view = false, .default_text = "0",
     .help = "worker threads (0 = all); output is identical for any", .lo = 0, .hi = 1 << 20},
    {.name = "samples", .kind = K::kInteger, .view = false, .default_text = "0",
     .help = "sub-pixel samples per pixel for algorithm abuffer: 1|4|8|16|32|64 (0: its default, "
             "4)",
     .lo = 0, .hi = 1 << 20, .needs = kAntialiasing, .trial = "4"},
    {.name = "fragment_memory", .kind = K::kNumber, .view = false, .default_text = "2048",
     .help = "most MiB the A-buffer's fragment lists may take; a frame needing more is refused",
     .lo = 0, .hi = 1048576, .lo_open = true, .note = " MiB", .wide = true},
    {.name = "bsp_splitter", .kind = K::kName, .view = false, .default_text = "balanced",
     .help = "how each BSP node's splitter is chosen: first|random|fewest|balanced|best-of-k",
     .choices = "first|random|fewest|balanced|best-of-k"},
    {.name = "bsp_seed", .kind = K::kInteger, .view = false, .default_text = "1",
     .help = "seed of the random and sampled splitter choices", .lo = 0,
     .hi = 9.2233720368547748e18},
    {.name = "bsp_candidates", .kind = K::kInteger, .view = false, .default_text = "8",
     .help = "polygons sampled per node by balanced and best-of-k", .lo = 1, .hi = 4096},
};
// clang-format on

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// The value as a message quotes it.
std::string shown(const OptionValue& v) {
  struct {
    std::string operator()(bool b) const { return b ? "true" : "false"; }
    std::string operator()(std::int64_t i) const { return std::to_string(i); }
    std::string operator()(double d) const { return number(d); }
    std::string operator()(const std::string& s) const { return "'" + s + "'"; }
    std::string operator()(const std::vector<double>& v) const {
      std::string out = "[";
      for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + number(v[i]);
      return out + "]";
    }
  } visit;
  return std::visit(visit, v);
}

const OptionSpec& specNamed(std::string_view name, FrontEnd fe) {
  const OptionSpec* spec = findOptionSpec(name);
  if (spec && spec->offeredBy(fe)) return *spec;
  std::string best;
  std::size_t best_distance = 3;  // at most two edits away
  for (const OptionSpec& s : kSpecs) {
    if (!s.offeredBy(fe)) continue;
    const std::size_t d = editDistance(name, s.name);
    if (d < best_distance) best_distance = d, best = s.name;
  }
  throw Error("unknown option '" + std::string(name) + "'" +
              (best.empty() ? std::string() : "; did you mean " + spelled(best, fe) + "?"));
}

// A float-held number within a float's range (nan and inf pass: the camera check refuses them)
void checkFloat(const OptionSpec& spec, double v, const std::string& opt, const std::string& got) {
  if (spec.wide || !std::isfinite(v)) return;
  const double a = std::abs(v);
  if (a > std::numeric_limits<float>::max())
    throw Error(opt + " " + got + " is larger than a float holds (3.4e38 at most)");
  if (a != 0 && a < std::numeric_limits<float>::min())
    throw Error(opt + " " + got + " is closer to 0 than a float holds (1.2e-38 at least)");
}

void checkRange(const OptionSpec& spec, double v, const std::string& opt, const std::string& got) {
  const bool above = spec.lo_open ? v > spec.lo : v >= spec.lo;
  const bool below = spec.hi_open ? v < spec.hi : v <= spec.hi;
  if (above && below) return;
  const std::string interval = spec.hi == kInf || spec.hi >= 1e9
                                   ? (spec.lo_open ? "> " : ">= ") + number(spec.lo)
                                   : std::string(spec.lo_open ? "(" : "[") + number(spec.lo) +
                                         ", " + number(spec.hi) + (spec.hi_open ? ")" : "]");
  throw Error(opt + " must be " + (interval[0] == '>' ? "" : "in ") + interval +
              std::string(spec.note) + " (got " + got + ")");
}

// A whole string as one number (false when it is not one). A float-held one is read as a float
// (one rounding, as the C library makes it); past a float's range, as a double, so that the
// message can say so.
bool parseNumber(std::string_view text, bool wide, double* out) {
  const std::string s(text);
  char* end = nullptr;
  errno = 0;
  double v = wide ? std::strtod(s.c_str(), &end) : double(std::strtof(s.c_str(), &end));
  if (s.empty() || end != s.c_str() + s.size() || std::isspace(static_cast<unsigned char>(s[0])))
    return false;
  if (!wide && errno == ERANGE) v = std::strtod(s.c_str(), nullptr);
  *out = v;
  return true;
}

std::string shortNumber(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

std::span<const OptionSpec> optionSpecs() { return kSpecs; }

const OptionSpec* findOptionSpec(std::string_view name) {
  for (const OptionSpec& s : kSpecs)
    if (s.name == name) return &s;
  return nullptr;
}

std::string spelled(std::string_view name, FrontEnd fe) {
  if (fe != FrontEnd::kCli) return std::string(name);
  const OptionSpec* spec = findOptionSpec(name);
  std::string s(spec && !spec->cli.empty() ? spec->cli : name);
  std::replace(s.begin(), s.end(), '_', '-');
  return "--" + s;
}

void OptionRequest::set(std::string_view option, const OptionValue& value) {
  put(specNamed(option, fe_), value, shown(value));
}

void OptionRequest::put(const OptionSpec& spec, const OptionValue& value, const std::string& got) {
  const std::string opt = name(spec.name);
  OptionValue stored;
  switch (spec.kind) {
    case K::kFlag:
      if (!std::holds_alternative<bool>(value))
        throw Error(opt + " must be true or false (got " + got + ")");
      stored = value;
      break;
    case K::kInteger: {
      double v = 0;
      if (const auto* i = std::get_if<std::int64_t>(&value))
        v = double(*i);
      else if (const auto* d = std::get_if<double>(&value); d && std::floor(*d) == *d)
        v = *d;
      else
        throw Error(opt + " must be a whole number (got " + got + ")");
      checkRange(spec, v, opt, got);
      stored = std::holds_alternative<std::int64_t>(value) ? std::get<std::int64_t>(value)
                                                           : static_cast<std::int64_t>(v);
      break;
    }
    case K::kNumber: {
      double v = 0;
      if (const auto* i = std::get_if<std::int64_t>(&value))
        v = double(*i);
      else if (const auto* d = std::get_if<double>(&value))
        v = *d;
      else
        throw Error(opt + " must be a number (got " + got + ")");
      checkFloat(spec, v, opt, got);
      checkRange(spec, v, opt, got);
      stored = v;
      break;
    }
    case K::kName: {
      const auto* s = std::get_if<std::string>(&value);
      if (!s) throw Error(opt + " must be a name (got " + got + ")");
      const std::string v = lower(*s);
      if (!spec.choices.empty()) {
        bool known = false;
        for (std::size_t at = 0; at <= spec.choices.size();) {
          const std::size_t bar = std::min(spec.choices.find('|', at), spec.choices.size());
          known = known || spec.choices.substr(at, bar - at) == v;
          at = bar + 1;
        }
        if (!known)
          throw Error(opt + " must be one of " + std::string(spec.choices) + " (got " + got + ")");
      }
      stored = spec.name == "algorithm" ? *s : v;  // algorithms are named as the registry spells
      break;
    }
    case K::kVector: {
      std::vector<double> v;
      if (const auto* numbers = std::get_if<std::vector<double>>(&value)) v = *numbers;
      if (v.size() != static_cast<std::size_t>(spec.count))
        throw Error(opt + " must be " + std::string(spec.choices) + " (got " + got + ")");
      for (double x : v) {
        if (spec.name == "intrinsics" && !std::isfinite(x))
          throw Error(opt + " must be " + std::string(spec.choices) + " (got " + got + ")");
        checkFloat(spec, x, opt, got);
      }
      if (spec.name == "size") {
        for (double x : v)
          if (std::floor(x) != x)
            throw Error(opt + " must be WxH in whole pixels (got " + got + ")");
        const std::string bare = got.front() == '\'' ? got.substr(1, got.size() - 2) : got;
        if (!(v[0] >= 1 && v[1] >= 1)) throw Error("image size " + bare + " must be at least 1x1");
        if (v[0] > 1e6 || v[1] > 1e6)
          throw Error("image size " + bare + " is absurd: the limit is " +
                      std::to_string(Camera::kMaxDimension) + " pixels per side");
      }
      // Every value given is used or refused: fx = fy = 0 is how a camera says "no intrinsics",
      // so zero focal lengths would otherwise be dropped for the default 45-degree camera
      if (spec.name == "intrinsics" && (!(v[0] > 0) || !(v[1] > 0)))
        throw Error(opt + ": the focal lengths fx and fy must be positive pixels (got " + got +
                    ")");
      stored = v;
      break;
    }
    case K::kText:
      if (const auto* i = std::get_if<std::int64_t>(&value))
        stored = std::to_string(*i);
      else if (const auto* s = std::get_if<std::string>(&value))
        stored = *s;
      else
        throw Error(opt + " must be a name or a whole number (got " + got + ")");
      break;
    case K::kFile:
      throw Error(opt + " names a file, which the command line reads");
  }
  values_[std::string(spec.name)] = std::move(stored);
}

void OptionRequest::setText(std::string_view option, std::string_view text) {
  const OptionSpec& spec = specNamed(option, fe_);
  const std::string quoted = "'" + std::string(text) + "'";
  OptionValue value = std::string(text);
  double d = 0;
  switch (spec.kind) {
    case K::kFlag:
      if (text == "true") value = true;
      if (text == "false") value = false;
      break;
    case K::kInteger: {
      const std::string s(text);
      char* end = nullptr;
      errno = 0;
      const long long i = std::strtoll(s.c_str(), &end, 10);
      if (!s.empty() && end == s.c_str() + s.size() && errno == 0)
        value = static_cast<std::int64_t>(i);
      break;
    }
    case K::kNumber:
      if (parseNumber(text, spec.wide, &d)) value = d;
      break;
    case K::kVector: {
      // "1,2,3", or for the size "WxH"
      const char sep = spec.name == "size" ? 'x' : ',';
      const std::string s = spec.name == "size" ? lower(text) : std::string(text);
      std::vector<double> v;
      bool ok = true;
      for (std::size_t at = 0; ok && at <= s.size();) {
        const std::size_t end = std::min(s.find(sep, at), s.size());
        ok = parseNumber(std::string_view(s).substr(at, end - at), spec.wide, &d);
        v.push_back(d);
        at = end + 1;
      }
      if (ok) value = v;
      break;
    }
    default:
      break;
  }
  put(spec, value,
      spec.kind == K::kNumber || spec.kind == K::kInteger ? std::string(text) : quoted);
}

void OptionRequest::setCameraFile(std::string label, const Camera& camera) {
  file_camera_ = camera;
  file_camera_label_ = label;
  values_["camera"] = std::move(label);
}

void OptionRequest::setPoseFile(std::string label, const glm::dmat4& camera_to_world) {
  pose_ = camera_to_world;
  pose_label_ = label;
  values_["pose"] = std::move(label);
}

const OptionValue* OptionRequest::value(std::string_view option) const {
  const auto it = values_.find(option);
  return it == values_.end() ? nullptr : &it->second;
}

std::string OptionRequest::text(std::string_view option) const {
  const OptionValue* v = value(option);
  if (!v) {
    const OptionSpec* spec = findOptionSpec(option);
    return spec ? std::string(spec->default_text) : std::string();
  }
  if (const auto* s = std::get_if<std::string>(v)) return *s;
  return shown(*v);
}

bool OptionRequest::size(int* width, int* height) const {
  const OptionValue* v = value("size");
  if (!v) return false;
  const auto& wh = std::get<std::vector<double>>(*v);
  *width = static_cast<int>(wh[0]);
  *height = static_cast<int>(wh[1]);
  return true;
}

RenderOptions OptionRequest::options() const {
  RenderOptions o;
  auto flag = [&](const char* n, bool d) {
    const OptionValue* v = value(n);
    return v ? std::get<bool>(*v) : d;
  };
  auto integer = [&](const char* n, std::int64_t d) {
    const OptionValue* v = value(n);
    return v ? std::get<std::int64_t>(*v) : d;
  };
  auto real = [&](const char* n, double d) {
    const OptionValue* v = value(n);
    return v ? std::get<double>(*v) : d;
  };
  o.algorithm = text("algorithm");
  o.cull = parseCullMode(text("cull"));
  o.front_face = parseFrontFace(text("front_face"));
  o.facing_test = text("facing") == "eye" ? FacingTest::EyePlane : FacingTest::WindowArea;
  o.polygon_mode = parsePolygonMode(text("polygon_mode"));
  o.point_size = static_cast<float>(real("point_size", o.point_size));
  o.depth_func = parseDepthFunc(text("depth_func"));
  o.clear_depth = static_cast<float>(real("clear_depth", o.clear_depth));
  o.depth_test = flag("depth_test", o.depth_test);
  o.depth_mask = flag("depth_mask", o.depth_mask);
  o.outline = flag("outline", o.outline);
  o.shade = flag("shade", o.shade);
  o.threads = static_cast<int>(integer("threads", o.threads));
  o.samples = static_cast<int>(integer("samples", o.samples));
  if (const OptionValue* v = value("fragment_memory"))
    o.fragment_memory = static_cast<std::uint64_t>(std::get<double>(*v) * 1048576.0);
  o.bsp.splitter = text("bsp_splitter");
  o.bsp.seed = static_cast<std::uint64_t>(integer("bsp_seed", std::int64_t(o.bsp.seed)));
  o.bsp.candidates = static_cast<int>(integer("bsp_candidates", o.bsp.candidates));
  return o;
}

namespace {

constexpr float kMaxCoordinate = 1e18f;

glm::vec3 vec3(const OptionValue& v) {
  const auto& x = std::get<std::vector<double>>(v);
  return {static_cast<float>(x[0]), static_cast<float>(x[1]), static_cast<float>(x[2])};
}

}  // namespace

// A scene the camera's float arithmetic can frame: coordinates within +-1e18 (at 1e19 the
// squared distances overflow), and, unless the view is given, some extent to frame.
void OptionRequest::checkFrameable(const Scene& scene, std::string_view label) const {
  const Bounds b = scene.bounds();
  if (b.empty()) return;
  const float reach = std::max({std::abs(b.lo.x), std::abs(b.lo.y), std::abs(b.lo.z),
                                std::abs(b.hi.x), std::abs(b.hi.y), std::abs(b.hi.z)});
  if (reach > kMaxCoordinate) {
    // The limit holds whether the camera is framed or given (every vertex goes through the same
    // float transforms and clipping, whose squared distances overflow past 1.8e19): so say what
    // to do, with the power of ten to scale by.
    const int down =
        static_cast<int>(std::ceil(std::log10(double(reach) / double(kMaxCoordinate))));
    char reach_text[32];
    std::snprintf(reach_text, sizeof reach_text, "%.3g", double(reach));
    throw Error(std::string(label) + ": coordinates reach " + reach_text +
                ", beyond the +-1e18 that hsr's float camera arithmetic is held to (a camera "
                "given by hand does not lift it); scale the model by 1e-" +
                std::to_string(std::max(down, 1)) +
                " or less (most exporters have a unit or scale option), or remove the vertices "
                "that far out");
  }
  if (b.lo == b.hi && scene.cameras.empty() && !given("camera") && !given("pose") &&
      !(given("eye") && given("target")))
    throw Error(std::string(label) + ": every vertex lies at the same point (" +
                shortNumber(b.lo.x) + ", " + shortNumber(b.lo.y) + ", " + shortNumber(b.lo.z) +
                "): there is nothing with an extent to frame, or an area to draw");
}

Camera OptionRequest::cameraFromFile() const {
  for (const char* other :
       {"eye", "target", "up", "fov", "ortho", "intrinsics", "pose", "camera_index"})
    if (given(other) && !(std::string_view(other) == "camera_index" && text(other) == "0"))
      throw Error(name(other) + " and " + name("camera") + " both set the view: give one");
  Camera cam = file_camera_;
  int w = 0, h = 0;
  if (size(&w, &h)) {
    if ((w != cam.width || h != cam.height) && cam.intrinsics.given())
      throw Error(name("size") + " " + std::to_string(w) + "x" + std::to_string(h) +
                  ": the camera's intrinsics are for " + std::to_string(cam.width) + "x" +
                  std::to_string(cam.height) + " pixels");
    cam.width = w;
    cam.height = h;
  }
  return cam;
}

Camera OptionRequest::camera(const Scene& scene, std::string_view label) const {
  checkFrameable(scene, label);
  const Bounds b = scene.bounds();
  Camera cam;
  if (given("camera")) {
    cam = cameraFromFile();
  } else {
    int w = 800, h = 600;
    size(&w, &h);
    const bool fov_given = given("fov"), ortho = given("ortho") && std::get<bool>(*value("ortho"));
    const float fov = fov_given ? static_cast<float>(std::get<double>(*value("fov"))) : 45.0f;
    // Which of the scene file's cameras frames it: an index, or -1 for none (auto-framing)
    int index = 0;
    const std::string index_text = text("camera_index");
    if (index_text == "auto") {
      index = -1;
    } else {
      char* end = nullptr;
      const long n = std::strtol(index_text.c_str(), &end, 10);
      if (index_text.empty() || end != index_text.c_str() + index_text.size() || n < 0)
        throw Error(name("camera_index") + " must be a camera's number from 0, or auto (got '" +
                    index_text + "')");
      if (n > 0 && static_cast<std::size_t>(n) >= scene.cameras.size())
        throw Error(name("camera_index") + " " + std::to_string(n) + ": " + std::string(label) +
                    " has " + std::to_string(scene.cameras.size()) + " camera" +
                    (scene.cameras.size() == 1 ? "" : "s"));
      index = static_cast<int>(n);
    }
    const bool file_camera = index >= 0 && static_cast<std::size_t>(index) < scene.cameras.size();
    // Framed with the given up axis (a Z-up model seen from its front three-quarter)
    const glm::vec3 up_axis = given("up") ? vec3(*value("up")) : glm::vec3(0.0f, 1.0f, 0.0f);
    cam = file_camera ? fromSceneCamera(scene.cameras[index], b, w, h)
                      : frameBounds(b, w, h, fov, ortho, up_axis);
    if (fov_given) cam.fov_deg = fov;
    if (given("intrinsics")) {
      if (fov_given)
        throw Error(name("fov") + " and " + name("intrinsics") +
                    " both set the projection: give one");
      if (ortho)
        throw Error(name("intrinsics") + " describe a pinhole camera: " + name("ortho") +
                    " has none");
      const auto& k = std::get<std::vector<double>>(*value("intrinsics"));
      cam.intrinsics = {k[0], k[1], k[2], k[3]};
      cam.ortho = false;
    }
    bool moved = given("eye") || given("target");
    if (given("pose")) {
      if (given("eye") || given("target") || given("up"))
        throw Error(name("pose") + " and " + name("eye") + ", " + name("target") + " or " +
                    name("up") + " all place the camera: give one");
      try {
        setPose(cam, pose_, poseConventionNamed(text("pose_convention")));
      } catch (const Error& e) {
        throw Error(name("pose") + " " + pose_label_ + ": " + e.what());
      }
      moved = true;
    }
    if (given("eye")) cam.eye = vec3(*value("eye"));
    if (given("target")) cam.target = vec3(*value("target"));
    if (given("up")) cam.up = vec3(*value("up"));
    // Near and far (and the orthographic extent) refitted around the scene for a new view
    if (moved) fitNearFar(cam, b);
    if (ortho) cam.ortho = true;
    if (cam.ortho && (moved || (ortho && file_camera && !scene.cameras[index].ortho)))
      cam.ortho_half_height = orthoHalfHeightFor(cam, b);
  }
  if (given("near")) cam.near = static_cast<float>(std::get<double>(*value("near")));
  if (given("far")) cam.far = static_cast<float>(std::get<double>(*value("far")));
  cam.validate();
  return cam;
}

}  // namespace hsr
