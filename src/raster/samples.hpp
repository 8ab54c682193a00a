#pragma once
// Sub-pixel samples: where in a pixel they lie, and which of them a triangle covers (the
// A-buffer's coverage masks). A sample is covered when the shared exact edge setup
// (raster/edge.hpp), evaluated at the sample instead of the pixel centre, says inside, with the
// same fill rule: triangles that share an edge cover each sample on it exactly once, as they
// do pixel centres, whatever order they come in.
//
// The patterns (offsets from the pixel centre, y down, in 1/16 pixel):
//   1 sample: the centre;  4, 8, 16: Direct3D's standard patterns (4: (-2,-6) (6,-2) (-6,2)
//   (2,6)), which every rasterizer uses for 4x MSAA;  32 and 64: points placed so that the share
//   of samples on one side of a straight edge is, on average over random edges, close to the
//   share of the pixel's area there (found by annealing from the Hammersley points; how, in
//   samples.cpp).

#include <cstdint>

#include "raster/edge.hpp"

namespace hsr::detail {

inline constexpr int kMaxSamples = 64;

struct SamplePattern {
  int count = 0;
  std::int32_t x[kMaxSamples],
      y[kMaxSamples];  // offsets from the centre in sub-pixel units (1/256)
};

bool validSampleCount(int count);               // 1, 4, 8, 16, 32 or 64
const SamplePattern& samplePattern(int count);  // throws hsr::Error for any other count

// A triangle's edge functions at its samples: the change from the pixel centre to each sample
// (exact integers: dx * oy - dy * ox per edge), and their extremes for a quick verdict on
// pixels far inside or outside an edge.
struct SampleEdges {
  int count = 0;
  std::int64_t offset[3][kMaxSamples];
  std::int64_t lowest[3], highest[3];
};
void setupSampleEdges(const TriangleSetup& s, const SamplePattern& p, SampleEdges* out);

// The mask of every sample of a pattern of `count`.
inline std::uint64_t allSamples(int count) {
  return count == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << count) - 1;
}

// The samples of one pixel a triangle covers, a bit each (bit i: sample i), from the three
// edge values at the pixel's centre (EdgeSetup::row + step_x * column, fill-rule bias
// included: the values whose signs say whether the centre is inside).
inline std::uint64_t sampleMask(const SampleEdges& se, const std::int64_t e[3]) {
  const std::uint64_t all = allSamples(se.count);
  bool inside_all = true;
  for (int k = 0; k < 3; ++k) {
    if (e[k] + se.highest[k] < 0) return 0;  // every sample outside this edge
    inside_all = inside_all && e[k] + se.lowest[k] >= 0;
  }
  if (inside_all) return all;
  std::uint64_t mask = 0;
  for (int i = 0; i < se.count; ++i)
    if (e[0] + se.offset[0][i] >= 0 && e[1] + se.offset[1][i] >= 0 && e[2] + se.offset[2][i] >= 0)
      mask |= std::uint64_t(1) << i;
  return mask;
}

}  // namespace hsr::detail
