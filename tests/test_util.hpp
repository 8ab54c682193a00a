#pragma once
// Small helpers shared by the tests: deterministic random numbers and scene builders.

#include <cstdint>
#include <cstdlib>
#include <string>

#include "hsr/camera.hpp"
#include "hsr/render.hpp"
#include "core/random.hpp"
#include "hsr/scene.hpp"

namespace hsr::testing {

using Rng = hsr::detail::SplitMix64;

// Channel c (0 = R, 1 = G, 2 = B) of pixel k of a frame's packed RGBA colour.
inline int channel(const Frame& f, std::size_t k, int c) { return (f.color[k] >> (8 * c)) & 0xFF; }

// HSR_TEST_INTENSITY: 1 in CI (default), 3 for long local runs.
inline int testIntensity() {
  const char* v = std::getenv("HSR_TEST_INTENSITY");
  const int i = v ? std::atoi(v) : 1;
  return i < 1 ? 1 : i;
}

// An orthographic camera on which world x,y in [0,w]x[0,h] map to window pixels (y up),
// looking down -z from z = 10 with near 1 and far 20 (window depth = (10 - z - 1) / 19 ... ).
inline Camera pixelCamera(int w, int h) {
  Camera c;
  c.width = w;
  c.height = h;
  c.ortho = true;
  c.ortho_half_height = h * 0.5f;
  c.eye = {w * 0.5f, h * 0.5f, 10.0f};
  c.target = {w * 0.5f, h * 0.5f, 0.0f};
  c.up = {0.0f, 1.0f, 0.0f};
  c.near = 1.0f;
  c.far = 20.0f;
  return c;
}

}  // namespace hsr::testing
