#pragma once
// How much of one line drawing lies on another: the length of a's segments (sampled every
// quarter pixel) within `tolerance` pixels of b's. Used to hold two drawings of the same lines
// together (the line drawing's engines in tests/lines/line_drawing_test.cpp, hsr against Open
// CASCADE in bench/bench_lines.cpp).

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

namespace hsr::testing {

using Segment2 = std::pair<glm::dvec2, glm::dvec2>;

struct NearLength {
  double length = 0, near = 0;  // of a: in all, and within the tolerance of b
  double share() const { return length > 0 ? near / length : 1.0; }
};

inline NearLength nearLength(const std::vector<Segment2>& a, const std::vector<Segment2>& b,
                             double tolerance = 1.0) {
  // b's segments by the unit cells their boxes (grown by the tolerance) reach
  std::map<std::pair<int, int>, std::vector<const Segment2*>> cells;
  for (const Segment2& s : b)
    for (int y = static_cast<int>(std::floor(std::min(s.first.y, s.second.y) - tolerance));
         y <= static_cast<int>(std::floor(std::max(s.first.y, s.second.y) + tolerance)); ++y)
      for (int x = static_cast<int>(std::floor(std::min(s.first.x, s.second.x) - tolerance));
           x <= static_cast<int>(std::floor(std::max(s.first.x, s.second.x) + tolerance)); ++x)
        cells[{x, y}].push_back(&s);
  NearLength out;
  for (const Segment2& s : a) {
    const glm::dvec2 d = s.second - s.first;
    const double len = glm::length(d);
    const int n = std::max(1, static_cast<int>(std::ceil(len * 4)));
    for (int k = 0; k < n; ++k) {
      const glm::dvec2 m = s.first + d * ((k + 0.5) / n);
      out.length += len / n;
      const auto it =
          cells.find({static_cast<int>(std::floor(m.x)), static_cast<int>(std::floor(m.y))});
      if (it == cells.end()) continue;
      for (const Segment2* t : it->second) {
        const glm::dvec2 e = t->second - t->first;
        const double ee = glm::dot(e, e);
        const double u = ee > 0 ? std::clamp(glm::dot(m - t->first, e) / ee, 0.0, 1.0) : 0.0;
        if (glm::length(m - (t->first + e * u)) <= tolerance) {
          out.near += len / n;
          break;
        }
      }
    }
  }
  return out;
}

}  // namespace hsr::testing
