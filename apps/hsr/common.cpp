// What the verbs of `hsr` share (common.hpp).

#include "common.hpp"

#include "hsr/compare.hpp"
#include "hsr/frontend.hpp"
#include "hsr/io.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string_view>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <glm/vector_relational.hpp>

namespace hsr::cli {

namespace {

void allOptionNames(CLI::App* app, std::vector<std::string>& names) {
  for (const CLI::Option* o : app->get_options()) {
    for (const std::string& n : o->get_lnames()) names.push_back("--" + n);
    for (const std::string& n : o->get_snames()) names.push_back("-" + n);
  }
  for (CLI::App* sub : app->get_subcommands({})) allOptionNames(sub, names);
}

}  // namespace

void refuseFlagsAsValues(CLI::App* app) {
  const CLI::Validator not_a_flag(
      [](std::string& v) {
        const bool flag = v.size() > 1 && v[0] == '-' &&
                          (std::isalpha(static_cast<unsigned char>(v[1])) || v[1] == '-');
        return flag ? "needs a value, and " + v + " is a flag" : std::string();
      },
      "", "not a flag");
  for (CLI::Option* o : app->get_options())
    if (o->get_type_size() > 0 && o->get_expected_min() > 0) o->check(not_a_flag);
  for (CLI::App* sub : app->get_subcommands({})) refuseFlagsAsValues(sub);
}

void lowercaseNameValues(CLI::App* app) {
  static constexpr std::string_view kNamed[] = {
      "cull",   "front-face", "facing",  "polygon-mode",    "depth-func",   "algorithm",
      "output", "depth",      "normals", "pose-convention", "camera-index", "bsp-splitter",
      "style",  "hidden",     "lines",   "engine",          "fallback"};
  const CLI::Validator lower(
      [](std::string& v) {
        std::transform(v.begin(), v.end(), v.begin(),
                       [](unsigned char c) { return std::tolower(c); });
        return std::string();
      },
      "", "lower case");
  for (CLI::Option* o : app->get_options())
    for (const std::string& n : o->get_lnames())
      if (std::find(std::begin(kNamed), std::end(kNamed), n) != std::end(kNamed))
        o->transform(lower);
  if (CLI::Option* algorithm = app->get_option_no_throw("ALGORITHM")) algorithm->transform(lower);
  for (CLI::App* sub : app->get_subcommands({})) lowercaseNameValues(sub);
}

std::string nearMissHint(CLI::App* app, int argc, const char* const* argv) {
  std::vector<std::string> names;
  allOptionNames(app, names);
  for (int i = 1; i < argc; ++i) {
    std::string_view arg = argv[i];
    if (arg.size() < 3 || arg[0] != '-' || std::isdigit(static_cast<unsigned char>(arg[1])) ||
        arg[1] == '.')
      continue;
    arg = arg.substr(0, arg.find('='));
    if (std::find(names.begin(), names.end(), arg) != names.end()) continue;
    std::string best;
    std::size_t best_distance = 3;
    for (const std::string& n : names) {
      const std::size_t d = hsr::editDistance(arg, n);
      if (d < best_distance) best_distance = d, best = n;
    }
    if (!best.empty()) return fmt::format("{}: did you mean {}?", arg, best);
  }
  return {};
}

std::string commaHint(int argc, const char* const* argv) {
  auto number = [](std::string_view t) {
    if (t.empty()) return false;
    char* end = nullptr;
    const std::string copy(t);
    std::strtod(copy.c_str(), &end);
    return end == copy.c_str() + copy.size();
  };
  for (int i = 1; i + 2 < argc; ++i) {
    const std::string_view o = argv[i];
    if ((o == "--eye" || o == "--target" || o == "--up") && number(argv[i + 1]) &&
        number(argv[i + 2]))
      return fmt::format("{} takes x,y,z joined by commas, such as {} {},{},{}", o, o, argv[i + 1],
                         argv[i + 2], i + 3 < argc && number(argv[i + 3]) ? argv[i + 3] : "0");
  }
  return {};
}

std::string plainParseMessage(std::string_view what) {
  // CLI11's ArgumentMismatch::AtMost: "NAME: At Most 1 required but received N"
  constexpr std::string_view kAtMost = ": At Most 1 required but received ";
  const std::size_t at = what.find(kAtMost);
  if (at != std::string_view::npos && at > 0) {
    const std::string_view count = what.substr(at + kAtMost.size());
    if (!count.empty() &&
        std::all_of(count.begin(), count.end(), [](char c) { return c >= '0' && c <= '9'; }))
      return fmt::format(
          "{} is given {} times; give it once (a later one does not replace an earlier)",
          what.substr(0, at), count);
  }
  return std::string(what);
}

std::string verbMissHint(std::string_view first, const std::vector<std::string_view>& verbs) {
  std::error_code ec;
  if (first.empty() || first[0] == '-' || fs::exists(fs::path(first), ec)) return {};
  const std::string_view base = first.substr(0, first.find(':'));
  for (const hsr::BuiltinScene& b : hsr::builtinScenes())
    if (b.name.substr(0, b.name.find(':')) == base) return {};
  for (const std::string_view v : verbs)
    if (hsr::editDistance(first, v) <= 2)
      return fmt::format("{}: no such verb, file or built-in scene; did you mean {}?",
                         printable(first), v);
  return {};
}

// A message as one line on a terminal: control characters (a newline in a file name, an
// escape sequence) are shown escaped, never acted on.
std::string printable(std::string_view s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    const bool c1 = c == 0xC2 && i + 1 < s.size() &&  // U+0080..U+009F, the C1 controls
                    static_cast<unsigned char>(s[i + 1]) >= 0x80 &&
                    static_cast<unsigned char>(s[i + 1]) <= 0x9F;
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c < 0x20 || c == 0x7F) {
      out += fmt::format("\\x{:02x}", c);
    } else if (c1) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned char>(s[++i]));
    } else {
      out += static_cast<char>(c);
    }
  }
  return out;
}

void printError(std::string_view message) {
  std::fprintf(stderr, "hsr: %s\n", printable(message).c_str());
}

void requireExtension(std::string_view option, const std::string& path, std::string_view extension,
                      std::string_view what) {
  std::string given = fs::path(path).extension().string();
  std::transform(given.begin(), given.end(), given.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (!given.empty() && given != extension)
    throw hsr::Error(fmt::format("{} {}: hsr writes {} there; name the file {}", option,
                                 printable(path), what, extension));
}

std::string sceneLabel(const std::string& spec) {
  std::string name = fs::exists(spec) ? fs::path(spec).stem().string() : spec;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return name;
}

// Rendering from inside an object is legitimate (the near plane clips what surrounds the
// eye), but often a mistake: say so on one line.
void warnIfEyeInside(const hsr::Scene& scene, const hsr::Camera& cam) {
  if (cam.ortho) return;
  for (const hsr::Object& o : scene.objects) {
    const hsr::Bounds& b = o.bounds;
    if (b.empty()) continue;
    if (glm::all(glm::greaterThanEqual(cam.eye, b.lo)) &&
        glm::all(glm::lessThanEqual(cam.eye, b.hi))) {
      printError(
          fmt::format("warning: the eye is inside the bounds of object '{}'; what "
                      "surrounds it is clipped at the near plane",
                      o.name));
      return;
    }
  }
}

// A perspective depth buffer of floats resolves about 2^24 steps between near and far, most of
// them close to the near plane: past far/near = 2^24 every surface's depth rounds towards the
// clear value 1.0, and the picture comes out blank or merged. Valid, so a warning.
bool depthUnresolvable(const hsr::Camera& cam) {
  return !cam.ortho && cam.far / cam.near > 16777216.0f;
}

bool warnIfDepthUnresolvable(const hsr::Camera& cam) {
  if (!depthUnresolvable(cam)) return false;
  printError(
      fmt::format("warning: far/near = {:.3g} (near {:g}, far {:g}) is more than a float "
                  "depth buffer resolves (2^24): depths round to the clear value and "
                  "surfaces vanish or merge; raise --near",
                  cam.far / cam.near, cam.near, cam.far));
  return true;
}

void refuseIfNothingResolved(const hsr::Frame& f, const hsr::Camera& cam) {
  if (!depthUnresolvable(cam) || f.stats.fragments_tested == 0) return;
  for (const hsr::PolygonId id : f.ids)
    if (id != hsr::kNoPolygon) return;
  // Every fragment's depth rounded to the clear value: the picture would be empty, and an empty
  // picture written with exit 0 reads as "nothing there"
  throw hsr::Error(fmt::format(
      "nothing could be drawn: with near {:g} and far {:g} (far/near {:.3g}, past the 2^24 a float "
      "depth buffer resolves) every one of the {} fragments rounded to the clear depth; raise "
      "--near (to {:.3g} or more for this far)",
      cam.near, cam.far, cam.far / cam.near, f.stats.fragments_tested, cam.far / 1e6));
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

// An object-order algorithm that ran out of its split budget painted some polygons in the
// order reached: said on stderr even with --quiet, never silently.
void warnIfUnresolved(const hsr::Frame& f, const std::string& algorithm) {
  // Counters that say an algorithm's budget ran out, and what that means for the picture
  static constexpr std::pair<std::string_view, std::string_view> kBudgets[] = {
      {": unresolved",
       "left {} orderings unresolved (its split budget was spent); those polygons were painted in "
       "the "
       "order reached and may hide nearer ones"},
      {": left to the depth test",
       "reached its work limit; {} polygons were finished with a depth test per pixel instead of "
       "exact "
       "clipping"}};
  for (const hsr::Counter& c : f.stats.counters)
    for (const auto& [suffix, what] : kBudgets)
      if (c.value > 0 && c.name.ends_with(suffix))
        fmt::print(stderr, "hsr: warning: {} {}\n", algorithm,
                   fmt::format(fmt::runtime(what), c.value));
}

namespace {
const char* depthFuncName(hsr::DepthFunc f) {
  static constexpr const char* kNames[] = {"never",   "less",     "equal",  "lequal",
                                           "greater", "notequal", "gequal", "always"};
  return kNames[static_cast<int>(f)];
}
}  // namespace

void warnIfNothingDrawn(const hsr::Frame& f, const hsr::RenderOptions& o) {
  for (const hsr::PolygonId id : f.ids)
    if (id != hsr::kNoPolygon) return;
  const hsr::Stats& s = f.stats;
  std::string why;
  if (s.triangles_in == 0)
    why = "the scene has no polygons";
  else if (s.culled_frustum == s.triangles_in)
    why = "every polygon lies outside the view (check --eye, --target, --near, --far)";
  else if (s.culled_backface > 0 &&
           s.culled_backface + s.culled_frustum + s.clipped_away >= s.triangles_in)
    why = o.cull == hsr::CullMode::FrontAndBack ? "--cull both removes every polygon, front and "
                                                  "back faces alike (try --cull back or none)"
                                                : "every polygon in the view faces away and --cull "
                                                  "removed it (try --cull none or --front-face cw)";
  else if (s.clipped_away > 0 && s.culled_frustum + s.clipped_away >= s.triangles_in)
    why = "every polygon was clipped away by the near or far plane";
  else if (s.fragments_tested > 0 && s.fragments_written == 0)
    why = fmt::format(
        "no fragment passed the depth test (--depth-func {} against the clear depth {:g}{})",
        depthFuncName(o.depth_func), o.clear_depth,
        o.depth_func == hsr::DepthFunc::Greater || o.depth_func == hsr::DepthFunc::GEqual
            ? "; --clear-depth 0 lets it draw"
            : "");
  else if (s.triangles_rasterized == 0 || s.fragments_tested == 0)
    why = "every polygon in the view falls between pixel centres (too small for this --size)";
  else
    why = "no polygon reached a pixel";
  fmt::print(stderr, "hsr: warning: nothing was drawn: {}\n", why);
}

void addLegend(const hsr::Frame& f, std::string_view kind, std::vector<std::uint8_t>& rgb,
               const hsr::Camera& camera, hsr::DepthKind depth) {
  if (kind != "depth" && kind != "overdraw") return;
  constexpr int kBar = 150, kBarH = 8, kPad = 4, kText = 7;
  const int w = f.width, h = f.height;
  // A title row (what the numbers are), the two ends' values, the ramp
  const int box_w = kBar + 2 * kPad, box_h = kPad + 2 * (kText + 3) + kBarH + kPad;
  if (w < box_w + 16 || h < 4 * box_h) return;  // a small picture stays as it is
  if (rgb.size() != 3ull * w * h) return;
  std::string title, left, right;
  if (kind == "depth") {
    const hsr::DepthRange r = hsr::drawnDepthRange(f);
    if (!(r.hi >= r.lo)) return;  // nothing drawn
    if (depth == hsr::DepthKind::kWindow) {
      title = "WINDOW Z";
      left = fmt::format("NEAR {:.5f}", r.lo);
      right = fmt::format("FAR {:.5f}", r.hi);
    } else {
      // The ends in the units --depth asks for (the ramp is the picture's: window z)
      title =
          depth == hsr::DepthKind::kLinear ? "DEPTH ALONG THE VIEW AXIS" : "DISTANCE FROM THE EYE";
      const hsr::FrameBuffer<float> d = hsr::depthAs(f, camera, depth);
      float lo = INFINITY, hi = -INFINITY;
      for (const float v : d)
        if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
      if (!(hi >= lo)) return;
      left = fmt::format("NEAR {:.4g}", lo);
      right = fmt::format("FAR {:.4g}", hi);
    }
  } else {
    const std::uint32_t max =
        f.overdraw.empty() ? 0 : *std::max_element(f.overdraw.begin(), f.overdraw.end());
    if (max == 0) return;
    title = "OVERDRAW";
    left = "1";
    right = fmt::format("MAX {}", max);
  }
  // A black box in the bottom-right corner: the two ends' values, then the ramp between them
  const int x0 = w - box_w - 4, y0 = h - box_h - 4;
  for (int y = y0; y < y0 + box_h; ++y)
    for (int x = x0; x < x0 + box_w; ++x) {
      const bool edge = y == y0 || y == y0 + box_h - 1 || x == x0 || x == x0 + box_w - 1;
      std::uint8_t* p = &rgb[3 * (static_cast<std::size_t>(y) * w + x)];
      p[0] = p[1] = p[2] = edge ? 128 : 0;
    }
  hsr::drawLabel(rgb, w, h, x0 + kPad, y0 + kPad, title, 1);
  const int values_y = y0 + kPad + kText + 3;
  hsr::drawLabel(rgb, w, h, x0 + kPad, values_y, left, 1);
  hsr::drawLabel(rgb, w, h, x0 + kPad + kBar - 6 * static_cast<int>(right.size()) + 1, values_y,
                 right, 1);
  for (int i = 0; i < kBar; ++i) {
    std::uint8_t c[3];
    const float t = static_cast<float>(i) / (kBar - 1);
    if (kind == "depth")
      hsr::depthRampColor(t, c);
    else
      hsr::overdrawRampColor(t, c);
    for (int y = values_y + kText + 3; y < values_y + kText + 3 + kBarH; ++y)
      std::copy(c, c + 3, &rgb[3 * (static_cast<std::size_t>(y) * w + x0 + kPad + i)]);
  }
}

void printSummary(const hsr::Frame& f, const std::string& scene, const std::string& algorithm,
                  const std::vector<std::string>& written, const hsr::Camera* camera) {
  const hsr::Stats& s = f.stats;
  fmt::print("hsr {} {}  {}x{}\n", algorithm, scene, f.width, f.height);
  if (camera) {
    const hsr::Camera& c = *camera;
    fmt::print(
        "  camera   eye ({:g}, {:g}, {:g}) target ({:g}, {:g}, {:g}) up ({:g}, {:g}, {:g}), ",
        c.eye.x, c.eye.y, c.eye.z, c.target.x, c.target.y, c.target.z, c.up.x, c.up.y, c.up.z);
    if (c.ortho) {
      fmt::print("orthographic, half height {:g}, near {:g}, far {:g}\n", c.ortho_half_height,
                 c.near, c.far);
    } else {
      const hsr::Intrinsics k = hsr::intrinsicsOf(c);
      const hsr::FieldOfView fov = hsr::fieldOfView(c);
      const std::string angle =
          c.intrinsics.given()
              ? fmt::format("fov {:.4g} x {:.4g} deg (from the intrinsics)", fov.x_deg, fov.y_deg)
              : fmt::format("fov {:g} deg", c.fov_deg);
      fmt::print("{}, near {:g}, far {:g}; fx {:.3f} fy {:.3f} cx {:g} cy {:g} (OpenCV)\n", angle,
                 c.near, c.far, k.fx, k.fy, k.cx, k.cy);
    }
  }
  // Every count of the one table, with what it counts (zero counts of rarer events omitted).
  for (const hsr::Stats::Field& field : hsr::Stats::fields()) {
    const std::uint64_t v = s.*field.value;
    if (field.name == "state_bytes") continue;
    if (v == 0 && field.name != "polygons_in" && field.name != "triangles_in" &&
        field.name != "triangles_rasterized" && field.name != "fragments_written")
      continue;
    std::string label(field.name);
    std::replace(label.begin(), label.end(), '_', ' ');
    fmt::print("  {:<22}{:>12}   {}\n", label, v, field.meaning);
  }
  for (const hsr::Counter& c : s.counters) fmt::print("  {:<22}{:>12}\n", c.name, c.value);
  fmt::print("  {:<22}{:>12.1f}   MiB ({:.1f} bytes/pixel)\n", "state memory",
             s.state_bytes / 1048576.0, double(s.state_bytes) / (double(f.width) * f.height));
  fmt::print("  time per stage:");
  for (const hsr::StageTime& st : s.stages) fmt::print("  {} {:.2f} ms", st.name, st.ms);
  fmt::print("\n  total {:.2f} ms\n", s.totalMs());
  for (const std::string& w : written) fmt::print("  wrote {}\n", w);
}

}  // namespace hsr::cli
