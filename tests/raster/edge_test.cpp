// RowSpans (raster/edge.hpp) against spanOfRow, its definition: the same span on every row of
// random triangles, from tiny to 2^20 pixels across, with horizontal, vertical and nearly
// horizontal edges, starting at rows above, inside and below them.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>

#include "raster/edge.hpp"

namespace hsr::detail {
namespace {

// A screen triangle through three 24.8 fixed-point vertices, wound for positive y-down area.
bool triangleOf(std::int32_t x[3], std::int32_t y[3], ScreenTriangle* t) {
  const std::int64_t area =
      std::int64_t(x[1] - x[0]) * (y[2] - y[0]) - std::int64_t(y[1] - y[0]) * (x[2] - x[0]);
  if (area == 0) return false;
  const int o[3] = {0, area > 0 ? 1 : 2, area > 0 ? 2 : 1};
  for (int k = 0; k < 3; ++k) {
    t->x[k] = x[o[k]];
    t->y[k] = y[o[k]];
  }
  return true;
}

TEST(Edge, RowSpansAreSpanOfRowOnEveryRow) {
  std::mt19937_64 rng(7);
  std::uint64_t rows = 0, filled = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    // Scales from a few sub-pixel units to 2^20 pixels; some coordinates shared to make
    // horizontal and vertical edges.
    const int scale_bits = 2 + static_cast<int>(rng() % 27);
    std::uniform_int_distribution<std::int32_t> coord(-(1 << scale_bits), 1 << scale_bits);
    std::int32_t x[3], y[3];
    for (int k = 0; k < 3; ++k) {
      x[k] = coord(rng);
      y[k] = coord(rng);
    }
    if (trial % 5 == 1) y[1] = y[0];
    if (trial % 7 == 2) x[2] = x[1];
    if (trial % 11 == 3) y[2] = y[0] + static_cast<std::int32_t>(rng() % 3);  // nearly horizontal
    ScreenTriangle t{};
    if (!triangleOf(x, y, &t)) continue;
    const std::int64_t top = std::min({y[0], y[1], y[2]}) >> kSubpixelBits;
    const std::int64_t bottom = std::max({y[0], y[1], y[2]}) >> kSubpixelBits;
    // Near the top row, or (every third trial) anywhere down the triangle.
    const int first_row = static_cast<int>(
        trial % 3 == 0 ? top + static_cast<std::int64_t>(rng() % (bottom - top + 1))
                       : top - 3 + static_cast<std::int64_t>(rng() % 5));
    TriangleSetup s = setupTriangle(t, first_row);
    RowSpans spans(s);
    const int x_lo = static_cast<int>(std::min({x[0], x[1], x[2]}) >> kSubpixelBits) - 2;
    const int x_hi = static_cast<int>(std::max({x[0], x[1], x[2]}) >> kSubpixelBits) + 2;
    const int count = static_cast<int>(std::min<std::int64_t>(200, bottom - first_row + 4));
    for (int row = 0; row < count; ++row, nextRow(s), spans.next()) {
      int lo = x_lo, hi = x_hi, lo2 = x_lo, hi2 = x_hi;
      const bool any = spanOfRow(s, &lo, &hi);
      ASSERT_EQ(spans.span(&lo2, &hi2), any) << "trial " << trial << " row " << row;
      if (any) {
        ASSERT_EQ(lo2, lo) << "trial " << trial << " row " << row;
        ASSERT_EQ(hi2, hi) << "trial " << trial << " row " << row;
        filled++;
      }
      rows++;
    }
  }
  // The trials reached both kinds of row.
  EXPECT_GT(filled, 100000u);
  EXPECT_GT(rows - filled, 10000u);
}

}  // namespace
}  // namespace hsr::detail
