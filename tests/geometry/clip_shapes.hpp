#pragma once
// Seeded random polygons on an integer grid for the clipping test, benchmark and fuzz target:
// star-shaped (vertices at increasing angles round a centre, at random radii), comb-shaped
// (teeth of random width and height on a spine) and star-shaped with a star-shaped hole.

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "core/random.hpp"
#include "hsr/clipping.hpp"

namespace hsr::testing {

// n vertices round (cx, cy), radii in [r_min, r_max], angles jittered within their slot. Not
// always valid after rounding to the grid (two vertices may round onto one): check it.
inline GridRing starRing(detail::SplitMix64& rng, int n, double cx, double cy, double r_min,
                         double r_max) {
  GridRing ring;
  for (int i = 0; i < n; ++i) {
    const double angle = 2 * std::numbers::pi * (i + 0.1 + 0.8 * rng.uniform()) / n;
    const double r = r_min + (r_max - r_min) * rng.uniform();
    ring.push_back(
        {std::llround(cx + r * std::cos(angle)), std::llround(cy + r * std::sin(angle))});
  }
  return ring;
}

// A comb: a spine along the bottom and `teeth` teeth upwards, about n = 4 teeth + 2 vertices.
inline GridRing combRing(detail::SplitMix64& rng, int teeth, std::int64_t x0, std::int64_t y0,
                         std::int64_t width, std::int64_t height) {
  GridRing ring;
  const std::int64_t spine = std::max<std::int64_t>(1, height / 5),
                     slot = std::max<std::int64_t>(2, width / teeth);
  ring.push_back({x0 + slot * teeth, y0});
  for (int t = teeth - 1; t >= 0; --t) {
    const std::int64_t left = x0 + slot * t,
                       w = 1 +
                           static_cast<std::int64_t>(rng.uniform() * static_cast<float>(slot - 1));
    const std::int64_t top =
        y0 + spine + 1 +
        static_cast<std::int64_t>(rng.uniform() * static_cast<float>(height - spine));
    ring.push_back({left + w, y0 + spine});
    ring.push_back({left + w, top});
    ring.push_back({left, top});
    ring.push_back({left, y0 + spine});
  }
  ring.push_back({x0, y0});
  // The teeth's right sides may share the spine's corner: drop repeated points
  GridRing out;
  for (const GridPoint& p : ring)
    if (out.empty() || !(out.back() == p)) out.push_back(p);
  if (out.size() > 1 && out.front() == out.back()) out.pop_back();
  return out;
}

}  // namespace hsr::testing
