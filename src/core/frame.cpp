// Clearing a frame: a fresh one filled as it is sized, one drawn before in parallel bands.

#include "core/frame.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>

#include "core/large_pages.hpp"
#include "core/parallel.hpp"

namespace hsr {

void* allocateFrameBuffer(std::size_t bytes) {
  // A buffer of 1 to 2 MiB (an 800x600 frame's: 1.8 MiB) takes one whole huge page: its 470
  // 4 KiB faults took most of a small one-shot render (clear 20 ms of 22 for the demo scene).
  const std::size_t placed =
      bytes >= detail::kLargePage / 2 && bytes < detail::kLargePage ? detail::kLargePage : bytes;
  return detail::allocateLargePages(placed, alignof(std::max_align_t));
}
void freeFrameBuffer(void* p) noexcept { std::free(p); }

}  // namespace hsr

namespace hsr::detail {

std::uint32_t clearColorRgba(const RenderOptions& options) {
  auto q = [](float v) {
    return static_cast<std::uint32_t>(
        std::lround(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f));
  };
  const glm::vec3& c = options.clear_color;
  return q(c.r) | (q(c.g) << 8) | (q(c.b) << 16) | 0xFF000000u;
}

void clearFrame(Frame& f, int width, int height, const RenderOptions& options) {
  f.width = width;
  f.height = height;
  f.stats = Stats{};
  const std::size_t n = static_cast<std::size_t>(width) * height;
  const std::uint32_t clear = clearColorRgba(options);
  const float clear_depth =
      std::isfinite(options.clear_depth) ? std::clamp(options.clear_depth, 0.0f, 1.0f) : 1.0f;
  f.coverage.clear();  // made by the algorithms that antialias
  const bool sized =
      f.color.size() == n && f.depth.size() == n && f.ids.size() == n && f.overdraw.size() == n;
  if (!sized) {
    // A fresh or resized frame: each buffer filled as it is sized, in one pass (resize() wrote
    // zeros first, on one thread, and the bands then wrote the clear values over them)
    f.color.assign(n, clear);
    f.depth.assign(n, clear_depth);
    f.ids.assign(n, kNoPolygon);
    f.overdraw.assign(n, 0u);
    return;
  }
  // A frame drawn before: cleared in parallel bands
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16), [&](const auto& r) {
    std::fill(f.color.begin() + r.begin(), f.color.begin() + r.end(), clear);
    std::fill(f.depth.begin() + r.begin(), f.depth.begin() + r.end(), clear_depth);
    std::fill(f.ids.begin() + r.begin(), f.ids.begin() + r.end(), kNoPolygon);
    std::fill(f.overdraw.begin() + r.begin(), f.overdraw.begin() + r.end(), 0u);
  });
}

std::uint64_t frameBufferBytes(const Frame& f) {
  return f.color.size() * 4 + f.depth.size() * 4 + f.ids.size() * 4 + f.overdraw.size() * 4 +
         f.coverage.size() * 4;
}

}  // namespace hsr::detail
