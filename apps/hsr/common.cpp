// What the verbs of `hsr` share (common.hpp).

#include "common.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <string_view>
#include <utility>

#include <fmt/core.h>
#include <glm/vector_relational.hpp>

namespace hsr::cli {

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
    if (glm::all(glm::greaterThanEqual(cam.eye, b.lo)) && glm::all(glm::lessThanEqual(cam.eye, b.hi))) {
      printError(fmt::format("warning: the eye is inside the bounds of object '{}'; what "
                             "surrounds it is clipped at the near plane",
                             o.name));
      return;
    }
  }
}

// A perspective depth buffer of floats resolves about 2^24 steps between near and far, most of
// them close to the near plane: past far/near = 2^24 every surface's depth rounds towards the
// clear value 1.0, and the picture comes out blank or merged. Valid, so a warning.
void warnIfDepthUnresolvable(const hsr::Camera& cam) {
  if (cam.ortho || !(cam.far / cam.near > 16777216.0f)) return;
  printError(fmt::format("warning: far/near = {:.3g} (near {:g}, far {:g}) is more than a float "
                         "depth buffer resolves (2^24): depths round to the clear value and "
                         "surfaces vanish or merge; raise --near",
                         cam.far / cam.near, cam.near, cam.far));
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
       "left {} orderings unresolved (its split budget was spent); those polygons were painted in the "
       "order reached and may hide nearer ones"},
      {": left to the depth test",
       "reached its work limit; {} polygons were finished with a depth test per pixel instead of exact "
       "clipping"}};
  for (const hsr::Counter& c : f.stats.counters)
    for (const auto& [suffix, what] : kBudgets)
      if (c.value > 0 && c.name.ends_with(suffix))
        fmt::print(stderr, "hsr: warning: {} {}\n", algorithm, fmt::format(fmt::runtime(what), c.value));
}

void printSummary(const hsr::Frame& f, const std::string& scene, const std::string& algorithm,
                  const std::vector<std::string>& written, const hsr::Camera* camera) {
  const hsr::Stats& s = f.stats;
  fmt::print("hsr {} {}  {}x{}\n", algorithm, scene, f.width, f.height);
  if (camera) {
    const hsr::Camera& c = *camera;
    fmt::print("  camera   eye ({:g}, {:g}, {:g}) target ({:g}, {:g}, {:g}) up ({:g}, {:g}, {:g}), ",
               c.eye.x, c.eye.y, c.eye.z, c.target.x, c.target.y, c.target.z, c.up.x, c.up.y,
               c.up.z);
    if (c.ortho) {
      fmt::print("orthographic, half height {:g}, near {:g}, far {:g}\n", c.ortho_half_height,
                 c.near, c.far);
    } else {
      const hsr::Intrinsics k = hsr::intrinsicsOf(c);
      fmt::print("fov {:g} deg, near {:g}, far {:g}; fx {:.3f} fy {:.3f} cx {:g} cy {:g} (OpenCV)\n",
                 c.fov_deg, c.near, c.far, k.fx, k.fy, k.cx, k.cy);
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
