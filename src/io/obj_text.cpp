// A small Wavefront OBJ reader that needs no assimp (hsr/io.hpp: parseObjText): the web page
// reads the files a user drops on it with this, since assimp is not built for the browser.
// What it reads: "v x y z" vertices; "f" faces of three or more corners, each "v", "v/vt",
// "v//vn" or "v/vt/vn" (texture and normal indices are skipped), a negative index counting
// back from the last vertex; "o" and "g" begin a new object; "usemtl" chooses a material by
// name. Everything else ("vt", "vn", "s", "mtllib", "l", comments) is left aside. Polygons
// stay polygons, numbered in the file's order. Bad input is refused with the line number.

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/color.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"

namespace hsr {
namespace {

// The words of a line, split at spaces and tabs.
std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

// A material's colour when the file names it but no .mtl is read: hues a golden angle apart.
glm::vec3 paletteColor(std::size_t k) {
  return detail::hsvToRgb(
      static_cast<float>(std::fmod(0.08 + 0.6180339887498949 * static_cast<double>(k), 1.0)), 0.45f,
      0.9f);
}

class ObjReader {
 public:
  ObjReader(std::string_view text, std::string name) : text_(text) {
    scene_.name = std::move(name);
  }

  Scene read() {
    std::size_t at = 0;
    while (at < text_.size()) {
      std::size_t end = text_.find('\n', at);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view line = text_.substr(at, end - at);
      at = end + 1;
      ++line_number_;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      if (const std::size_t hash = line.find('#'); hash != std::string_view::npos)
        line = line.substr(0, hash);
      const std::vector<std::string_view> w = words(line);
      if (w.empty()) continue;
      if (w[0] == "v")
        vertex(w);
      else if (w[0] == "f")
        face(w);
      else if (w[0] == "o" || w[0] == "g")
        object_name_ = w.size() > 1 ? std::string(w[1]) : std::string();
      else if (w[0] == "usemtl")
        material_ = materialNamed(w.size() > 1 ? std::string(w[1]) : std::string());
    }
    if (scene_.polygonCount() == 0) throw Error(scene_.name + ": no faces");
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw Error(scene_.name + ":" + std::to_string(line_number_) + ": " + why);
  }

  float number(std::string_view word) const {
    // strtof on a terminated copy: libc++ 13 (the web build's) has no from_chars for floats
    const std::string s(word);
    char* end = nullptr;
    const float v = std::strtof(s.c_str(), &end);
    if (end != s.c_str() + s.size()) fail("'" + s + "' is not a number");
    if (!std::isfinite(v)) fail("'" + s + "' is not a finite coordinate");
    return v;
  }

  void vertex(const std::vector<std::string_view>& w) {
    if (w.size() < 4) fail("a vertex needs three coordinates");
    positions_.push_back({number(w[1]), number(w[2]), number(w[3])});
  }

  // A corner's vertex: its first index, 1-based, or negative counting back from the last
  std::uint32_t corner(std::string_view word) const {
    const std::string_view first = word.substr(0, word.find('/'));
    long long index = 0;
    const auto [end, ec] = std::from_chars(first.data(), first.data() + first.size(), index);
    if (ec != std::errc() || end != first.data() + first.size() || index == 0)
      fail("'" + std::string(word) + "' is not a vertex index");
    const long long n = static_cast<long long>(positions_.size());
    const long long k = index > 0 ? index - 1 : n + index;
    if (k < 0 || k >= n)
      fail("vertex " + std::to_string(index) + " does not exist (" + std::to_string(n) +
           " so far)");
    return static_cast<std::uint32_t>(k);
  }

  void face(const std::vector<std::string_view>& w) {
    if (w.size() < 4) fail("a face needs three corners or more");
    if (!object_open_ || object_name_ != current_object_) {
      scene_.beginObject(object_name_.empty() ? scene_.name : object_name_);
      current_object_ = object_name_;
      object_open_ = true;
      local_.clear();
    }
    if (material_ == kNone) material_ = materialNamed("");
    corners_.clear();
    for (std::size_t i = 1; i < w.size(); ++i) {
      // The object's own copy of the vertex, made when a face of it first uses it
      const std::uint32_t v = corner(w[i]);
      auto [it, added] = local_.try_emplace(v, 0u);
      if (added) it->second = scene_.addVertex(positions_[v]);
      corners_.push_back(it->second);
    }
    scene_.addPolygon(corners_, material_);
  }

  std::uint32_t materialNamed(const std::string& name) {
    auto [it, added] = materials_.try_emplace(name, 0u);
    if (added) {
      Material m;
      m.name = name;
      if (!name.empty()) m.color = paletteColor(materials_.size() - 1);
      it->second = scene_.addMaterial(m);
    }
    return it->second;
  }

  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
  std::string_view text_;
  Scene scene_;
  std::size_t line_number_ = 0;
  std::vector<glm::vec3> positions_;
  std::map<std::uint32_t, std::uint32_t> local_;  // file vertex -> the object's vertex
  std::vector<std::uint32_t> corners_;
  std::map<std::string, std::uint32_t> materials_;
  std::uint32_t material_ = kNone;
  std::string object_name_, current_object_;
  bool object_open_ = false;
};

}  // namespace

Scene parseObjText(std::string_view text, std::string name) {
  return ObjReader(text, std::move(name)).read();
}

}  // namespace hsr
