#pragma once
// A material as drawing uses it, shared by the pipeline (shading) and the ray scene (which
// polygons are see-through): channels clamped to [0, 1] (NaN as 0), alpha rounded to a byte
// in an rgba's top byte. Below 0xFF the polygon is see-through, blended in a second pass.

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/vec3.hpp>

#include "hsr/scene.hpp"

namespace hsr::detail {

inline float unitChannel(float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f; }

inline glm::vec3 materialRgb(const Material& m) {
  return {unitChannel(m.color.r), unitChannel(m.color.g), unitChannel(m.color.b)};
}

inline std::uint32_t materialAlphaBits(const Material& m) {
  return static_cast<std::uint32_t>(unitChannel(m.alpha) * 255.0f + 0.5f) << 24;
}

inline bool materialSeeThrough(const Material& m) { return materialAlphaBits(m) != 0xFF000000u; }

}  // namespace hsr::detail
