// DDA lines through pixel centres, and the outline pen.

#include "raster/lines.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace hsr::detail {
namespace {

// The steps k of the walk of l, 0..steps, that can land inside `clip` (3 px of margin for
// rounding and the pen): each clip box walks its own piece of the line, the same steps as a
// walk of the whole line.
struct Walk {
  int steps, k0, k1;
};

Walk walkWithin(const ScreenLine& l, const PixelBox& clip) {
  const float dx = l.x1 - l.x0, dy = l.y1 - l.y0;
  const float len = std::max(std::abs(dx), std::abs(dy));
  Walk w;
  w.steps = std::isfinite(len) ? static_cast<int>(std::min(std::ceil(len), 1e6f)) : 0;
  w.k0 = 0;
  w.k1 = w.steps;
  auto limit = [&](float a, float d, int lo, int hi) {
    if (d == 0.0f || w.steps == 0) return;
    double ka = (static_cast<double>(lo) - 3.0 - a) * w.steps / d;
    double kb = (static_cast<double>(hi) + 3.0 - a) * w.steps / d;
    if (ka > kb) std::swap(ka, kb);
    w.k0 = std::max(w.k0, static_cast<int>(std::max(std::floor(ka), -1.0)));
    w.k1 = std::min(w.k1, static_cast<int>(std::min(std::ceil(kb), static_cast<double>(w.steps))));
  };
  limit(l.x0, dx, clip.x0, clip.x1);
  limit(l.y0, dy, clip.y0, clip.y1);
  w.k0 = std::max(w.k0, 0);
  return w;
}

// Step k of the walk: the pixel and the depth there.
struct LinePixel {
  int x, y;
  float z;
};

LinePixel stepOf(const ScreenLine& l, const Walk& w, int k) {
  const float t = w.steps == 0 ? 0.0f : static_cast<float>(k) / static_cast<float>(w.steps);
  return {static_cast<int>(std::lround(l.x0 + (l.x1 - l.x0) * t)),
          static_cast<int>(std::lround(l.y0 + (l.y1 - l.y0) * t)),
          std::clamp(l.z0 + (l.z1 - l.z0) * t, 0.0f, 1.0f)};
}

bool inside(const PixelBox& b, int x, int y) {
  return x >= b.x0 && x <= b.x1 && y >= b.y0 && y <= b.y1;
}

// One fragment of a line or point at fb[idx]: depth-tested, then written like a triangle's.
void writeLineFragment(const ScreenLine& l, std::size_t idx, float z, const FrameView& fb,
                       DepthFunc func, bool depth_mask, FragmentCounts& c) {
  c.tested++;
  if (!depthPasses(func, z, fb.depth[idx])) return;
  c.written++;
  fb.overdraw[idx]++;
  if (depth_mask) fb.depth[idx] = z;
  fb.ids[idx] = l.id;
  fb.rgba[idx] = l.rgba;
}

}  // namespace

void drawLine(const ScreenLine& l, const PixelBox& clip, const FrameView& fb, DepthFunc func,
              bool depth_mask, FragmentCounts& c) {
  const Walk w = walkWithin(l, clip);
  for (int k = w.k0; k <= w.k1; ++k) {
    const LinePixel p = stepOf(l, w, k);
    if (!inside(clip, p.x, p.y)) continue;
    writeLineFragment(l, fb.index(p.x, p.y), p.z, fb, func, depth_mask, c);
  }
}

void drawPoint(const ScreenLine& p, float size, const PixelBox& clip, const FrameView& fb,
               DepthFunc func, bool depth_mask, FragmentCounts& c) {
  if (!(size > 1.0f)) {
    drawLine(p, clip, fb, func, depth_mask, c);
    return;
  }
  const float half = 0.5f * size;
  const int x0 = std::max(static_cast<int>(std::ceil(p.x0 - half)), clip.x0);
  const int x1 = std::min(static_cast<int>(std::ceil(p.x0 + half)) - 1, clip.x1);
  // Rows count from the top, so OpenGL's half-open [y - s/2, y + s/2) upwards is (y - s/2,
  // y + s/2] here
  const int y0 = std::max(static_cast<int>(std::floor(p.y0 - half)) + 1, clip.y0);
  const int y1 = std::min(static_cast<int>(std::floor(p.y0 + half)), clip.y1);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      writeLineFragment(p, fb.index(x, y), p.z0, fb, func, depth_mask, c);
}

void drawOutlinePen(const ScreenLine& l, const PixelBox& clip, const FrameView& fb) {
  const Walk w = walkWithin(l, clip);
  for (int k = w.k0; k <= w.k1; ++k) {
    const LinePixel p = stepOf(l, w, k);
    // The 2x2 pen, so the outline reads at any size.
    for (int py = p.y - 1; py <= p.y; ++py)
      for (int px = p.x - 1; px <= p.x; ++px) {
        if (!inside(clip, px, py)) continue;
        const std::size_t idx = fb.index(px, py);
        const PolygonId there = fb.ids[idx];
        if (there == kNoPolygon || there == l.id || there == l.other ||
            p.z <= fb.depth[idx] + 2e-4f)
          fb.rgba[idx] = l.rgba;
      }
  }
}

}  // namespace hsr::detail
