#pragma once
// HSV to RGB, once for every caller: the built-in scenes' colours, the colours of an OBJ file's
// named materials, and the hues of the polygon-id pictures.

#include <algorithm>
#include <cmath>

#include <glm/vec3.hpp>

namespace hsr::detail {

// Hue, saturation and value in [0, 1] (the hue wraps) to red, green and blue in [0, 1].
inline glm::vec3 hsvToRgb(float h, float s, float v) {
  h = (h - std::floor(h)) * 6.0f;
  const int sector = std::min(static_cast<int>(h), 5);
  const float f = h - static_cast<float>(sector);
  const float p = v * (1.0f - s), q = v * (1.0f - s * f), t = v * (1.0f - s * (1.0f - f));
  switch (sector) {
    case 0:
      return {v, t, p};
    case 1:
      return {q, v, p};
    case 2:
      return {p, v, t};
    case 3:
      return {p, q, v};
    case 4:
      return {t, p, v};
    default:
      return {v, p, q};
  }
}

}  // namespace hsr::detail
