// The polygon table two ways: numberPolygons (an index per triangle) and PolygonStarts (a bit
// per triangle, what the scan-line keeps). Runs of every length, across word (64) and summary
// (4096) boundaries, must give every triangle the same polygon both ways.

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "raster/primitives.hpp"

namespace hsr::detail {
namespace {

// Triangles in runs of the given lengths: a run shares id, colour and plane.
ScreenTriangles runsOf(const std::vector<std::size_t>& lengths) {
  ScreenTriangles tris;
  PolygonId id = 0;
  for (const std::size_t n : lengths) {
    for (std::size_t k = 0; k < n; ++k) {
      ScreenTriangle t{};
      t.id = id;
      t.rgba = 0xFF000000u | id;
      t.depth = {0.001 * id, 0.0, 0.5};
      tris.push_back(t);
    }
    ++id;
  }
  return tris;
}

void expectSameNumbering(const ScreenTriangles& tris) {
  std::vector<std::uint32_t> polygon_of;
  const std::uint64_t n = numberPolygons(tris, polygon_of);
  PolygonStarts starts;
  EXPECT_EQ(starts.build(tris), n);
  for (std::size_t i = 0; i < tris.size(); ++i)
    ASSERT_EQ(starts.polygonOf(static_cast<std::uint32_t>(i)), polygon_of[i]) << "triangle " << i;
}

TEST(PolygonStarts, AgreesWithTheIndexPerTriangleOnRunsAcrossWordBoundaries) {
  expectSameNumbering(runsOf({1}));
  expectSameNumbering(runsOf({64, 1, 63, 2, 65}));
  expectSameNumbering(runsOf({4096, 1, 4095, 4097, 3}));
  expectSameNumbering(runsOf({20000, 1, 9000}));  // runs spanning several summary words
}

TEST(PolygonStarts, AgreesWithTheIndexPerTriangleOnRandomRuns) {
  std::mt19937 rng(7);
  for (int scene = 0; scene < 20; ++scene) {
    std::vector<std::size_t> lengths;
    for (int r = 0; r < 200; ++r) lengths.push_back(1 + rng() % (rng() % 4 == 0 ? 300 : 3));
    expectSameNumbering(runsOf(lengths));
  }
}

TEST(PolygonStarts, SizeIsABitPerTriangle) {
  const ScreenTriangles tris = runsOf({100000});
  PolygonStarts starts;
  EXPECT_EQ(starts.build(tris), 1u);
  // a bit each, and one per 64
  EXPECT_LE(starts.bytes(), std::size_t{100000 / 8 + 100000 / 512 + 16});
  EXPECT_EQ(starts.polygonOf(99999), 0u);
}

}  // namespace
}  // namespace hsr::detail
