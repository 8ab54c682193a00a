// Tile binning (raster/bins.hpp): every primitive is listed in exactly the tiles its box
// touches, in submission order, checked against listing them one tile at a time: small boxes
// and boxes as wide as the viewport, very wide viewports, empty line boxes, and working memory
// kept from a larger set.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "raster/bins.hpp"

namespace hsr::detail {
namespace {

// The bins as a direct reading of their definition: tile by tile, the primitives in order.
template <class T>
std::vector<std::vector<std::uint32_t>> binsByDefinition(const std::vector<T>& prims, int w, int h,
                                                         float margin) {
  const int tx = (w + kTile - 1) / kTile, ty = (h + kTile - 1) / kTile;
  std::vector<std::vector<std::uint32_t>> out(static_cast<std::size_t>(tx) * ty);
  for (std::size_t i = 0; i < prims.size(); ++i) {
    const PixelBox b = boxOf(prims[i], w, h, margin);
    if (b.empty()) continue;
    for (int y = 0; y < ty; ++y)
      for (int x = 0; x < tx; ++x) {
        const bool touches = b.x0 <= (x + 1) * kTile - 1 && b.x1 >= x * kTile &&
                             b.y0 <= (y + 1) * kTile - 1 && b.y1 >= y * kTile;
        if (touches) out[static_cast<std::size_t>(y) * tx + x].push_back(std::uint32_t(i));
      }
  }
  return out;
}

std::vector<std::vector<std::uint32_t>> listed(const Bins& bins) {
  std::vector<std::vector<std::uint32_t>> out(bins.tiles());
  for (std::size_t t = 0; t < bins.tiles(); ++t)
    out[t].assign(bins.items.begin() + static_cast<std::ptrdiff_t>(bins.start[t]),
                  bins.items.begin() + static_cast<std::ptrdiff_t>(bins.start[t + 1]));
  return out;
}

// Triangles whose boxes are mostly small, some as wide or tall as the viewport.
std::vector<ScreenTriangle> randomBoxes(std::mt19937& rng, int w, int h, int n) {
  std::vector<ScreenTriangle> tris(static_cast<std::size_t>(n));
  for (ScreenTriangle& t : tris) {
    t = {};
    const int size = rng() % 10 == 0 ? w : static_cast<int>(rng() % 12);
    // A triangle's box lies below 32768 (makeScreenTriangle), whatever the viewport
    const int x0 = static_cast<int>(rng() % static_cast<unsigned>(std::min(w, 32768)));
    const int y0 = static_cast<int>(rng() % static_cast<unsigned>(h));
    t.x0 = static_cast<std::int16_t>(x0);
    t.y0 = static_cast<std::int16_t>(y0);
    t.x1 = static_cast<std::int16_t>(std::min({w - 1, 32767, x0 + size}));
    t.y1 = static_cast<std::int16_t>(std::min(h - 1, y0 + static_cast<int>(rng() % 12)));
  }
  return tris;
}

TEST(Bins, EveryTriangleInExactlyTheTilesOfItsBoxInOrder) {
  std::mt19937 rng(46);
  std::vector<std::size_t> scratch;
  // 1080p; wide viewports (boxes across every tile of a row); then fewer triangles, the
  // working memory kept from the larger sets
  const int sizes[][3] = {{1920, 1080, 20000}, {9000, 300, 3000}, {33000, 70, 500}, {640, 480, 50}};
  for (const auto& [w, h, n] : sizes) {
    SCOPED_TRACE(::testing::Message() << w << "x" << h << ", " << n << " triangles");
    const std::vector<ScreenTriangle> tris = randomBoxes(rng, w, h, n);
    Bins bins;
    binPrimitives(tris, w, h, bins, scratch);
    EXPECT_EQ(listed(bins), binsByDefinition(tris, w, h, 0.0f));
  }
}

TEST(Bins, LinesWithTheirMarginAndEmptyBoxes) {
  std::mt19937 rng(47);
  std::uniform_real_distribution<float> u(-50.0f, 9100.0f);
  std::vector<ScreenLine> lines(4000);
  for (ScreenLine& l : lines) l = {u(rng), u(rng) * 0.05f, 0, u(rng), u(rng) * 0.05f, 0, 0, 0};
  lines[7] = {-40, -40, 0, -30, -30, 0, 0, 0};  // off the viewport: an empty box
  std::vector<std::size_t> scratch;
  Bins bins;
  binPrimitives(lines, 9000, 400, bins, scratch, 2.5f);
  EXPECT_EQ(listed(bins), binsByDefinition(lines, 9000, 400, 2.5f));
  for (const auto& tile : listed(bins))
    for (std::uint32_t i : tile) EXPECT_NE(i, 7u);
  // A viewport of 40,000 columns, lines across all of it
  for (ScreenLine& l : lines) l.x0 *= 4.4f, l.x1 *= 4.4f;
  binPrimitives(lines, 40000, 400, bins, scratch, 1.0f);
  EXPECT_EQ(listed(bins), binsByDefinition(lines, 40000, 400, 1.0f));
}

}  // namespace
}  // namespace hsr::detail
