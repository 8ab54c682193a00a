#pragma once
// Tile binning: each primitive is listed in every screen tile its bounding box touches, by a
// counting sort that keeps submission order inside each tile. Guarantee: the bins depend only
// on the primitives and the viewport, never on how the work was split between threads.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/default_init.hpp"
#include "core/large_pages.hpp"
#include "raster/primitives.hpp"

namespace hsr::detail {

inline constexpr int kTileShift = 6;  // 64x64 pixel tiles: 16 KiB of depth, fits in L1/L2
inline constexpr int kTile = 1 << kTileShift;

// Per-tile lists of primitive indices, in submission order.
struct Bins {
  int tiles_x = 0, tiles_y = 0;
  std::vector<std::size_t> start;  // tiles + 1 offsets into items
  // Sized without a fill (the second pass writes every entry) and on huge pages when large: a
  // one-shot render's first touch of a million entries took 4 KiB faults (bin 15.6 ms against
  // 4.3 warm).
  std::vector<std::uint32_t, DefaultInitAllocator<std::uint32_t, LargePageAllocator<std::uint32_t>>>
      items;
  std::size_t tiles() const { return static_cast<std::size_t>(tiles_x) * tiles_y; }
  std::size_t bytes() const { return start.size() * sizeof(std::size_t) + items.size() * 4; }
  // The pixels of tile `index`, within a width x height viewport.
  PixelBox tileBox(std::size_t index, int width, int height) const;
};

// The pixels a primitive may touch (lines get a margin for rounding and the outline pen, as
// binPrimitives below says; a triangle's box is its own).
PixelBox boxOf(const ScreenTriangle& t, int width, int height, float margin);
PixelBox boxOf(const ScreenLine& l, int width, int height, float margin);

// Bins `prims` for a width x height viewport. `counts` is working memory kept by the caller.
// Throws hsr::Error when the bins would exceed 2^31 entries.
void binPrimitives(std::span<const ScreenTriangle> prims, int width, int height, Bins& bins,
                   std::vector<std::size_t>& counts);
// Lines and points reach `margin` pixels beyond their ends (1: the nearest centre and the
// outline pen; a point of size s: s / 2 + 1).
void binPrimitives(std::span<const ScreenLine> prims, int width, int height, Bins& bins,
                   std::vector<std::size_t>& counts, float margin = 1.0f);

}  // namespace hsr::detail
