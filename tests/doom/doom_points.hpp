#pragma once
// Random points inside a Doom map and away from its lines, for the tests that ask two trees (or
// a tree and the linedefs) which sector holds a point: the linedefs put each one in a sector,
// and each lies more than two units from every linedef (a builder rounds its split points by up
// to 0.71 units, so nearer a line two right trees may disagree).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "hsr/doom.hpp"

namespace hsr::testing {

inline std::vector<std::array<double, 2>> pointsInside(const doom::Map& map, int tries,
                                                       std::uint32_t seed) {
  double left = 1e300, right = -1e300, bottom = 1e300, top = -1e300;
  for (const doom::Vertex& v : map.vertices) {
    left = std::min(left, double(v.x)), right = std::max(right, double(v.x));
    bottom = std::min(bottom, double(v.y)), top = std::max(top, double(v.y));
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(left, right), uy(bottom, top);
  std::vector<std::array<double, 2>> points;
  for (int k = 0; k < tries; ++k) {
    const double x = ux(rng), y = uy(rng);
    if (!doom::sectorByLinedefs(map, x, y)) continue;
    const bool near_line =
        std::any_of(map.linedefs.begin(), map.linedefs.end(), [&](const doom::Linedef& l) {
          const doom::Vertex p = map.vertices[l.v1], q = map.vertices[l.v2];
          const double dx = q.x - p.x, dy = q.y - p.y, len2 = dx * dx + dy * dy;
          const double t =
              len2 > 0 ? std::clamp(((x - p.x) * dx + (y - p.y) * dy) / len2, 0.0, 1.0) : 0.0;
          return std::hypot(x - (p.x + t * dx), y - (p.y + t * dy)) < 2.0;
        });
    if (!near_line) points.push_back({x, y});
  }
  return points;
}

}  // namespace hsr::testing
