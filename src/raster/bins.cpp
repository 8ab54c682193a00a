// Tile binning by a two-pass counting sort over fixed chunks of primitives (oneTBB).

#include "raster/bins.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/check.hpp"
#include "core/parallel.hpp"
#include "hsr/error.hpp"

namespace hsr::detail {

PixelBox Bins::tileBox(std::size_t index, int width, int height) const {
  const int tx = static_cast<int>(index % static_cast<std::size_t>(tiles_x));
  const int ty = static_cast<int>(index / static_cast<std::size_t>(tiles_x));
  return {tx * kTile, ty * kTile, std::min(width, (tx + 1) * kTile) - 1,
          std::min(height, (ty + 1) * kTile) - 1};
}

PixelBox boxOf(const ScreenTriangle& t, int, int, float) { return t.box(); }

PixelBox boxOf(const ScreenLine& l, int w, int h, float margin) {
  // A pixel of margin on each side: rounding to the nearest centre and the 2x2 outline pen;
  // more for points drawn larger than a pixel.
  auto lo = [margin](float a, float b) { return std::floor(std::min(a, b)) - margin; };
  auto hi = [margin](float a, float b) { return std::ceil(std::max(a, b)) + margin; };
  const float x0 = std::max(lo(l.x0, l.x1), 0.0f), y0 = std::max(lo(l.y0, l.y1), 0.0f);
  const float x1 = std::min(hi(l.x0, l.x1), float(w - 1)),
              y1 = std::min(hi(l.y0, l.y1), float(h - 1));
  if (!(x0 <= x1) || !(y0 <= y1)) return {1, 1, 0, 0};
  return {int(x0), int(y0), int(x1), int(y1)};
}

namespace {

template <class T>
void binAll(std::span<const T> prims, int w, int h, Bins& bins, std::vector<std::size_t>& counts,
            float margin) {
  bins.tiles_x = (w + kTile - 1) >> kTileShift;
  bins.tiles_y = (h + kTile - 1) >> kTileShift;
  const std::size_t tiles = bins.tiles();
  const std::size_t n = prims.size();
  // Chunks only split the work; the result (sorted by tile, then index) does not depend on them.
  const std::size_t chunk = std::max<std::size_t>(8192, n / 64 + 1);
  const std::size_t chunks = (n + chunk - 1) / chunk;
  counts.assign(chunks * tiles, 0);
  // Both passes take a box inside one tile (nearly every triangle of a dense mesh) without the
  // loops over tile rows and columns: spheres:1M's bin stage 7.3 -> 5.5 ms.
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    std::size_t* cnt = &counts[c * tiles];
    for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) {
      const PixelBox b = boxOf(prims[i], w, h, margin);
      if (b.empty()) continue;
      const int tx0 = b.x0 >> kTileShift, tx1 = b.x1 >> kTileShift;
      const int ty0 = b.y0 >> kTileShift, ty1 = b.y1 >> kTileShift;
      if ((tx0 == tx1) & (ty0 == ty1)) {
        cnt[static_cast<std::size_t>(ty0) * bins.tiles_x + tx0]++;
        continue;
      }
      for (int ty = ty0; ty <= ty1; ++ty)
        for (int tx = tx0; tx <= tx1; ++tx) cnt[static_cast<std::size_t>(ty) * bins.tiles_x + tx]++;
    }
  });
  // Exclusive prefix sum in (tile, chunk) order: tile-major keeps each tile's list contiguous
  // and, within a tile, chunk order = submission order.
  bins.start.assign(tiles + 1, 0);
  std::size_t running = 0;
  for (std::size_t t = 0; t < tiles; ++t) {
    bins.start[t] = running;
    for (std::size_t c = 0; c < chunks; ++c) {
      const std::size_t k = counts[c * tiles + t];
      counts[c * tiles + t] = running;
      running += k;
    }
  }
  bins.start[tiles] = running;
  if (running > (std::size_t(1) << 31))
    throw Error("scene too heavy to bin: " + std::to_string(running) + " tile entries");
  bins.items.resize(running);
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    std::size_t* off = &counts[c * tiles];
    for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) {
      const PixelBox b = boxOf(prims[i], w, h, margin);
      if (b.empty()) continue;
      const int tx0 = b.x0 >> kTileShift, tx1 = b.x1 >> kTileShift;
      const int ty0 = b.y0 >> kTileShift, ty1 = b.y1 >> kTileShift;
      if ((tx0 == tx1) & (ty0 == ty1)) {
        bins.items[off[static_cast<std::size_t>(ty0) * bins.tiles_x + tx0]++] =
            static_cast<std::uint32_t>(i);
        continue;
      }
      for (int ty = ty0; ty <= ty1; ++ty)
        for (int tx = tx0; tx <= tx1; ++tx)
          bins.items[off[static_cast<std::size_t>(ty) * bins.tiles_x + tx]++] =
              static_cast<std::uint32_t>(i);
    }
  });
  // The second pass wrote exactly what the first counted: the last chunk's cursor of every
  // tile ends where the next tile begins.
  if (chunks > 0)
    for (std::size_t t = 0; t < tiles; ++t)
      HSR_CHECK_EQ(counts[(chunks - 1) * tiles + t], bins.start[t + 1]);
}

}  // namespace

void binPrimitives(std::span<const ScreenTriangle> prims, int w, int h, Bins& bins,
                   std::vector<std::size_t>& counts) {
  binAll(prims, w, h, bins, counts, 0.0f);
}

void binPrimitives(std::span<const ScreenLine> prims, int w, int h, Bins& bins,
                   std::vector<std::size_t>& counts, float margin) {
  binAll(prims, w, h, bins, counts, margin);
}

}  // namespace hsr::detail
