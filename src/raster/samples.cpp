// Sample patterns and per-triangle sample edge offsets (samples.hpp).

#include "raster/samples.hpp"

#include <algorithm>
#include <array>
#include <string>

#include "hsr/error.hpp"

namespace hsr::detail {
namespace {

// Direct3D's standard patterns, in 1/16 pixel from the centre, y down.
constexpr int kD3D4[4][2] = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
constexpr int kD3D8[8][2] = {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
constexpr int kD3D16[16][2] = {{1, 1},  {-1, -3}, {-3, 2},  {4, -1},  {-5, -2}, {2, 5},  {5, 3},   {3, -5},
                               {-2, 6}, {0, -7},  {-4, -6}, {-6, 4},  {-8, 0},  {7, -4}, {6, 7},   {-7, -8}};

SamplePattern fromSixteenths(const int (*xy)[2], int n) {
  SamplePattern p;
  p.count = n;
  for (int i = 0; i < n; ++i) {
    p.x[i] = xy[i][0] * (kSubpixelOne / 16);
    p.y[i] = xy[i][1] * (kSubpixelOne / 16);
  }
  return p;
}

// The n Hammersley points (n = 2^bits) on the sub-pixel grid: sample i at ((i + 1/2) / n,
// (reverse(i) + 1/2) / n) of the pixel square.
SamplePattern hammersley(int bits) {
  SamplePattern p;
  p.count = 1 << bits;
  const int cell = kSubpixelOne / p.count;  // 8 (32 samples) or 4 (64)
  for (int i = 0; i < p.count; ++i) {
    int r = 0;
    for (int b = 0; b < bits; ++b) r |= ((i >> b) & 1) << (bits - 1 - b);
    p.x[i] = i * cell + cell / 2 - kSubpixelOne / 2;
    p.y[i] = r * cell + cell / 2 - kSubpixelOne / 2;
  }
  return p;
}

}  // namespace

bool validSampleCount(int count) {
  return count == 1 || count == 4 || count == 8 || count == 16 || count == 32 || count == 64;
}

const SamplePattern& samplePattern(int count) {
  static const std::array<SamplePattern, 6> patterns = [] {
    std::array<SamplePattern, 6> p{};
    p[0].count = 1;
    p[0].x[0] = p[0].y[0] = 0;
    p[1] = fromSixteenths(kD3D4, 4);
    p[2] = fromSixteenths(kD3D8, 8);
    p[3] = fromSixteenths(kD3D16, 16);
    p[4] = hammersley(5);
    p[5] = hammersley(6);
    return p;
  }();
  for (const SamplePattern& p : patterns)
    if (p.count == count) return p;
  throw Error("--samples must be 1, 4, 8, 16, 32 or 64 (got " + std::to_string(count) + ")");
}

void setupSampleEdges(const TriangleSetup& s, const SamplePattern& p, SampleEdges* out) {
  out->count = p.count;
  for (int k = 0; k < 3; ++k) {
    // step_x = -dy * 256 and step_y = dx * 256, so the edge function
    // E = dx * (py - ay) - dy * (px - ax) changes by dx * oy - dy * ox at the offset (ox, oy)
    const std::int64_t dx = s.edge[k].step_y / kSubpixelOne, dy = -s.edge[k].step_x / kSubpixelOne;
    std::int64_t lo = INT64_MAX, hi = INT64_MIN;
    for (int i = 0; i < p.count; ++i) {
      const std::int64_t d = dx * p.y[i] - dy * p.x[i];
      out->offset[k][i] = d;
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    out->lowest[k] = lo;
    out->highest[k] = hi;
  }
}

}  // namespace hsr::detail
