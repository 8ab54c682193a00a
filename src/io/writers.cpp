// Writers: PNG (stb_image_write), NumPy .npy (format version 1.0), stats JSON, and the
// pictures of a frame's buffers (depth grey ramp, hashed polygon ids, overdraw heatmap).
// Buffers arrive top row first, as the files store them; nothing here flips rows.

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "hsr/error.hpp"
#include "hsr/io.hpp"

// stb_image_write: implementation here only, with internal linkage so that no other
// translation unit (or library) that embeds stb can clash with it.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wshadow"
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace hsr {
namespace {

std::string systemReason() {
  return errno != 0 ? std::string(": ") + std::strerror(errno) : std::string();
}

std::size_t pixelCount(int width, int height, const std::filesystem::path& path) {
  if (width <= 0 || height <= 0)
    throw Error(path.string() + ": cannot write an image of size " + std::to_string(width) + "x" +
                std::to_string(height));
  return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
}

// NumPy .npy version 1.0: magic, version, little-endian u16 header length, a Python dict
// literal padded with spaces to a multiple of 64 bytes (as numpy writes it) ending in '\n',
// then the raw little-endian data in C order.
template <typename T>
void writeNpyData(const std::filesystem::path& path, int width, int height, const T* data,
                  const char* descr) {
  static_assert(sizeof(T) == 4, "the byte swap below handles 4-byte elements");
  const std::size_t n = pixelCount(width, height, path);
  std::string header = std::string("{'descr': '") + descr +
                       "', 'fortran_order': False, 'shape': (" + std::to_string(height) + ", " +
                       std::to_string(width) + "), }";
  constexpr std::size_t kPrefix = 10;  // magic (6) + version (2) + header length (2)
  constexpr std::size_t kAlign = 64;
  const std::size_t total = (kPrefix + header.size() + 1 + kAlign - 1) / kAlign * kAlign;
  header.append(total - kPrefix - header.size() - 1, ' ');
  header.push_back('\n');
  const auto header_len = static_cast<std::uint16_t>(header.size());
  const unsigned char prefix[kPrefix] = {0x93,
                                         'N',
                                         'U',
                                         'M',
                                         'P',
                                         'Y',
                                         1,
                                         0,
                                         static_cast<unsigned char>(header_len & 0xFF),
                                         static_cast<unsigned char>(header_len >> 8)};

  errno = 0;
  std::FILE* f = std::fopen(path.string().c_str(), "wb");
  if (!f) throw Error(path.string() + ": cannot open for writing" + systemReason());
  bool ok = std::fwrite(prefix, 1, kPrefix, f) == kPrefix &&
            std::fwrite(header.data(), 1, header.size(), f) == header.size();
  if constexpr (std::endian::native == std::endian::little) {
    ok = ok && std::fwrite(data, sizeof(T), n, f) == n;
  } else {
    // Byte-swap in chunks on big-endian hosts
    std::vector<std::uint32_t> chunk;
    for (std::size_t i = 0; ok && i < n; i += 65536) {
      const std::size_t m = std::min<std::size_t>(65536, n - i);
      chunk.resize(m);
      std::memcpy(chunk.data(), data + i, m * sizeof(T));
      for (std::uint32_t& w : chunk)
        w = (w >> 24) | ((w >> 8) & 0xFF00u) | ((w << 8) & 0xFF0000u) | (w << 24);
      ok = std::fwrite(chunk.data(), sizeof(T), m, f) == m;
    }
  }
  const int saved_errno = errno;
  if (std::fclose(f) != 0 || !ok) {
    errno = errno != 0 ? errno : saved_errno;
    throw Error(path.string() + ": write failed" + systemReason());
  }
}

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
  h = (h - std::floor(h)) * 6.0f;
  const int sector = std::min(static_cast<int>(h), 5);
  const float f = h - static_cast<float>(sector);
  const float p = v * (1.0f - s), q = v * (1.0f - s * f), t = v * (1.0f - s * (1.0f - f));
  float r = v, g = t, b = p;
  switch (sector) {
    case 0:
      r = v, g = t, b = p;
      break;
    case 1:
      r = q, g = v, b = p;
      break;
    case 2:
      r = p, g = v, b = t;
      break;
    case 3:
      r = p, g = q, b = v;
      break;
    case 4:
      r = t, g = p, b = v;
      break;
    default:
      r = v, g = p, b = q;
      break;
  }
  out[0] = static_cast<std::uint8_t>(std::lround(std::clamp(r, 0.0f, 1.0f) * 255.0f));
  out[1] = static_cast<std::uint8_t>(std::lround(std::clamp(g, 0.0f, 1.0f) * 255.0f));
  out[2] = static_cast<std::uint8_t>(std::lround(std::clamp(b, 0.0f, 1.0f) * 255.0f));
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

std::size_t framePixels(const Frame& frame) {
  if (frame.width <= 0 || frame.height <= 0) return 0;
  return static_cast<std::size_t>(frame.width) * static_cast<std::size_t>(frame.height);
}

}  // namespace

void writePng(const std::filesystem::path& path, int width, int height, int channels,
              const std::uint8_t* pixels) {
  pixelCount(width, height, path);
  if (channels < 1 || channels > 4)
    throw Error(path.string() + ": a PNG has 1 to 4 channels, not " + std::to_string(channels));
  if (static_cast<long long>(width) * channels > 0x7FFFFFFF)
    throw Error(path.string() + ": image too wide for PNG");
  errno = 0;
  if (stbi_write_png(path.string().c_str(), width, height, channels, pixels, width * channels) == 0)
    throw Error(path.string() + ": cannot write PNG" + systemReason());
}

void writeNpy(const std::filesystem::path& path, int width, int height, const float* data) {
  writeNpyData(path, width, height, data, "<f4");
}

void writeNpy(const std::filesystem::path& path, int width, int height, const std::uint32_t* data) {
  writeNpyData(path, width, height, data, "<u4");
}

namespace {
// A pixel was drawn where it holds a polygon id (or, without ids, a depth below 1)
bool depthDrawn(const Frame& frame, std::size_t k) {
  const float d = frame.depth[k];
  return std::isfinite(d) && (frame.ids.size() == frame.depth.size() ? frame.ids[k] != kNoPolygon
                                                                      : d < 1.0f);
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
  constexpr float kNear = 255.0f, kFar = 48.0f;  // far stays visibly grey against black
  for (std::size_t k = 0; k < n; ++k) {
    if (!depthDrawn(frame, k)) continue;
    const float t = std::clamp((frame.depth[k] - range.lo) / span, 0.0f, 1.0f);
    const auto g = static_cast<std::uint8_t>(std::lround(kNear + (kFar - kNear) * t));
    rgb[3 * k] = rgb[3 * k + 1] = rgb[3 * k + 2] = g;
  }
  return rgb;
}

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
    // Hue from the hash's high bits, saturation and value from its low bits: always bright
    const std::uint32_t h = hashId(id);
    hsvToRgb8(static_cast<float>(h >> 8) * 0x1.0p-24f, 0.55f + 0.4f * ((h & 0xF) / 15.0f),
              0.8f + 0.2f * (((h >> 4) & 0xF) / 15.0f), &rgb[3 * k]);
  }
  return rgb;
}

std::vector<std::uint8_t> overdrawPicture(const Frame& frame) {
  const std::size_t n = framePixels(frame);
  std::vector<std::uint8_t> rgb(n * 3, 0);
  if (frame.overdraw.size() != n) return rgb;
  const std::uint32_t max = *std::max_element(frame.overdraw.begin(), frame.overdraw.end());
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

std::string statsJson(const Frame& frame, const std::string& scene, const std::string& algorithm) {
  const Stats& s = frame.stats;
  nlohmann::ordered_json j;
  j["scene"] = scene;
  j["algorithm"] = algorithm;
  j["width"] = frame.width;
  j["height"] = frame.height;
  for (const Stats::Field& f : Stats::fields()) j[std::string(f.name)] = s.*f.value;
  nlohmann::ordered_json counters = nlohmann::ordered_json::object();
  for (const Counter& c : s.counters) counters[c.name] = c.value;
  j["counters"] = std::move(counters);
  nlohmann::ordered_json stages = nlohmann::ordered_json::array();
  for (const StageTime& st : s.stages) stages.push_back({{"name", st.name}, {"ms", st.ms}});
  j["stages"] = std::move(stages);
  j["total_ms"] = s.totalMs();
  // A scene named by a file path need not be UTF-8: replace what is not, never throw
  return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

}  // namespace hsr
