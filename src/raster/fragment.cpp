// Fragment helpers that need no inlining.

#include "raster/fragment.hpp"

namespace hsr::detail {

bool depthPasses(DepthFunc f, float z, float stored) {
  return withDepthFunc(f, [&]<DepthFunc F>() { return depthPasses<F>(z, stored); });
}

std::uint32_t blendOver(std::uint32_t src, std::uint32_t dst) {
  const std::uint32_t a = src >> 24;
  std::uint32_t out = 0xFF000000u;
  for (int s = 0; s < 24; s += 8) {
    const std::uint32_t cs = (src >> s) & 0xFF, cd = (dst >> s) & 0xFF;
    out |= ((cs * a + cd * (255 - a) + 127) / 255) << s;
  }
  return out;
}

}  // namespace hsr::detail
