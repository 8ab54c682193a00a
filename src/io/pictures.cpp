// The pictures of a frame's buffers (hsr/io.hpp): depth as a grey ramp, polygon ids in hashed
// hues, overdraw as a heatmap, colour as RGB. RGB8, top row first, as the files store them.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "core/color.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "io/pictures.hpp"

namespace hsr {
namespace {

using detail::framePixels;

// A good 32-bit integer hash (Chris Wellons' lowbias32): neighbouring ids get unrelated colours.
std::uint32_t hashId(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7FEB352Du;
  x ^= x >> 15;
  x *= 0x846CA68Bu;
  x ^= x >> 16;
  return x;
}

void hsvToRgb8(float h, float s, float v, std::uint8_t* out) {
  const glm::vec3 c = detail::hsvToRgb(h, s, v);
  for (int k = 0; k < 3; ++k)
    out[k] = static_cast<std::uint8_t>(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
}

// Heatmap ramp for t in [0,1]: blue, green, yellow, red, white (brightness rises steadily,
// so the order reads without the hues).
void heat(float t, std::uint8_t* out) {
  static constexpr float kStops[5][3] = {{0.13f, 0.25f, 0.95f},
                                         {0.10f, 0.75f, 0.30f},
                                         {0.98f, 0.88f, 0.15f},
                                         {0.95f, 0.20f, 0.12f},
                                         {1.00f, 1.00f, 1.00f}};
  t = std::clamp(t, 0.0f, 1.0f) * 4.0f;
  const int i = std::min(static_cast<int>(t), 3);
  const float f = t - static_cast<float>(i);
  for (int c = 0; c < 3; ++c) {
    const float v = kStops[i][c] + (kStops[i + 1][c] - kStops[i][c]) * f;
    out[c] = static_cast<std::uint8_t>(std::lround(v * 255.0f));
  }
}

}  // namespace

namespace {
// A pixel was drawn where it holds a polygon id (or, without ids, a depth below 1)
bool depthDrawn(const Frame& frame, std::size_t k) {
  const float d = frame.depth[k];
  return std::isfinite(d) &&
         (frame.ids.size() == frame.depth.size() ? frame.ids[k] != kNoPolygon : d < 1.0f);
}
}  // namespace

DepthRange drawnDepthRange(const Frame& frame) {
  DepthRange r{std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
  if (frame.depth.size() != framePixels(frame)) return r;
  for (std::size_t k = 0; k < frame.depth.size(); ++k)
    if (depthDrawn(frame, k))
      r.lo = std::min(r.lo, frame.depth[k]), r.hi = std::max(r.hi, frame.depth[k]);
  return r;
}

std::vector<std::uint8_t> depthPicture(const Frame& frame, DepthRange range) {
  const std::size_t n = framePixels(frame);
  std::vector<std::uint8_t> rgb(n * 3, 0);
  if (frame.depth.size() != n) return rgb;
  const float span = range.hi > range.lo ? range.hi - range.lo : 1.0f;
  for (std::size_t k = 0; k < n; ++k)
    if (depthDrawn(frame, k)) depthRampColor((frame.depth[k] - range.lo) / span, &rgb[3 * k]);
  return rgb;
}

void depthRampColor(float t, std::uint8_t* rgb) {
  constexpr float kNear = 255.0f, kFar = 48.0f;  // far stays visibly grey against black
  const auto g =
      static_cast<std::uint8_t>(std::lround(kNear + (kFar - kNear) * std::clamp(t, 0.0f, 1.0f)));
  rgb[0] = rgb[1] = rgb[2] = g;
}

void overdrawRampColor(float t, std::uint8_t* rgb) { heat(t, rgb); }

std::vector<std::uint8_t> depthPicture(const Frame& frame) {
  // Normalised over the drawn pixels' depth range
  return depthPicture(frame, drawnDepthRange(frame));
}

std::vector<std::uint8_t> idPicture(const Frame& frame) {
  const std::size_t n = framePixels(frame);
  std::vector<std::uint8_t> rgb(n * 3, 0);
  if (frame.ids.size() != n) return rgb;
  for (std::size_t k = 0; k < n; ++k) {
    const PolygonId id = frame.ids[k];
    if (id == kNoPolygon) continue;
    // Hue by the golden angle: ids k and k + 1 (a mesh's neighbouring faces, mostly) lie 137.5
    // degrees apart on the colour wheel, k + 2 85, k + 3 52; value alternates with k's parity
    // and saturation with its hash, so that ids whose hues meet still differ: always bright
    const double hue = static_cast<double>(id) * 0.6180339887498949;
    const std::uint32_t h = hashId(id);
    hsvToRgb8(static_cast<float>(hue - std::floor(hue)), 0.55f + 0.4f * ((h & 0xF) / 15.0f),
              (id & 1) ? 0.82f : 1.0f, &rgb[3 * k]);
  }
  return rgb;
}

std::vector<std::uint8_t> overdrawPicture(const Frame& frame) {
  const std::size_t n = framePixels(frame);
  if (frame.overdraw.size() != n) return std::vector<std::uint8_t>(n * 3, 0);
  return overdrawPicture(frame,
                         n ? *std::max_element(frame.overdraw.begin(), frame.overdraw.end()) : 0);
}

std::vector<std::uint8_t> overdrawPicture(const Frame& frame, std::uint32_t most) {
  const std::size_t n = framePixels(frame);
  std::vector<std::uint8_t> rgb(n * 3, 0);
  if (n == 0 || frame.overdraw.size() != n) return rgb;
  const std::uint32_t max =
      std::max(most, *std::max_element(frame.overdraw.begin(), frame.overdraw.end()));
  // Logarithmic over 1..max: depth complexity is heavy-tailed, and a linear scale would paint
  // a few hot pixels white and everything else blue
  const float log_max = max > 1 ? std::log(static_cast<float>(max)) : 1.0f;
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t c = frame.overdraw[k];
    if (c == 0) continue;
    heat(std::log(static_cast<float>(c)) / log_max, &rgb[3 * k]);
  }
  return rgb;
}

std::vector<std::uint8_t> picture(const Frame& frame, std::string_view kind) {
  if (kind == "depth") return depthPicture(frame);
  if (kind == "ids") return idPicture(frame);
  if (kind == "overdraw") return overdrawPicture(frame);
  if (kind != "color")
    throw Error("unknown picture '" + std::string(kind) + "' (color, depth, ids, overdraw)");
  const std::size_t n = framePixels(frame);
  std::vector<std::uint8_t> rgb(n * 3, 0);
  if (frame.color.size() != n) return rgb;
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t c = frame.color[k];  // bytes R, G, B, A: R in the low byte
    rgb[3 * k] = static_cast<std::uint8_t>(c & 0xFF);
    rgb[3 * k + 1] = static_cast<std::uint8_t>((c >> 8) & 0xFF);
    rgb[3 * k + 2] = static_cast<std::uint8_t>((c >> 16) & 0xFF);
  }
  return rgb;
}

}  // namespace hsr
