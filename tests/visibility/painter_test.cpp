// The painter's algorithm (painter.cpp, Newell's depth sort) and its naive sibling
// (painter_naive.cpp): what the sort decides, measured against the z-buffer pixel by pixel
// (cross/compare_with_zbuffer.hpp says when a pixel is wrong: not a tie of two depths, a wrong
// order).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "cross/compare_with_zbuffer.hpp"
#include "cross/figures.hpp"
#include "cross/random_scenes.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using testing::pixelCamera;

using testing::compareWithZBuffer;
using testing::Comparison;
using testing::describe;

// The notes' two cases no plain order can paint: the naive sort is wrong somewhere on each,
// Newell's sort is wrong nowhere.
TEST(Painter, NewellFixesWhatTheNaiveSortGetsWrong) {
  for (const char* spec : {"cyclic", "penetrating", "demo"}) {
    SCOPED_TRACE(spec);
    const Scene scene = loadScene(spec);
    const Camera camera = frameScene(scene, 320, 240);
    const Comparison naive = compareWithZBuffer(scene, camera, "painter-naive");
    const Comparison newell = compareWithZBuffer(scene, camera, "painter");
    testing::printFigures(std::string(spec) + " 320x240: painter-naive: " + describe(naive) +
                          "; painter: " + describe(newell));
    if (std::string(spec) != "demo") {
      EXPECT_GT(naive.wrong, 0u) << "the naive sort should fail here";
    }
    EXPECT_EQ(newell.wrong, 0u) << newell.first_wrong;
    EXPECT_EQ(newell.depth_differs_same_id, 0u);
    EXPECT_LE(newell.ids_differ, newell.drawn / 1000);
  }
}

TEST(Painter, CyclicAndPenetratingPolygonsAreSplit) {
  RenderOptions o;
  o.algorithm = "painter";
  {
    const Scene scene = loadScene("cyclic");
    const Frame f = render(scene, frameScene(scene, 320, 240), o);
    // Each pair of sticks already fails every test both ways (each crosses the plane of the
    // next), so they are split as pairs before the cycle can close.
    EXPECT_GE(f.stats.counter("painter: splits"), 1u);
    EXPECT_EQ(f.stats.counter("painter: unresolved"), 0u);
  }
  {
    const Scene scene = loadScene("penetrating");
    const Frame f = render(scene, frameScene(scene, 320, 240), o);
    EXPECT_GE(f.stats.counter("painter: splits"), 1u);
    EXPECT_EQ(f.stats.counter("painter: unresolved"), 0u);
  }
}

// A painter has no depth test: every fragment it paints is counted, the far ones first.
TEST(Painter, OverdrawCountsEveryPaintedFragment) {
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  auto rect = [&](float x0, float y0, float x1, float y1, float z) {
    s.addPolygonVertices({{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}}, m);
  };
  rect(2, 2, 20, 12, -2);  // far
  rect(4, 6, 14, 10, 3);   // near
  rect(8, 4, 28, 14, 1);   // middle
  RenderOptions o;
  o.algorithm = "painter";
  const Frame f = render(s, pixelCamera(32, 16), o);
  std::uint64_t painted = 0;
  for (int row = 0; row < 16; ++row) {
    for (int col = 0; col < 32; ++col) {
      const float x = col + 0.5f, y = 16 - row - 0.5f;  // world = GL window under pixelCamera
      auto in = [&](float x0, float y0, float x1, float y1) {
        return x > x0 && x < x1 && y > y0 && y < y1;
      };
      const std::uint32_t covering = in(2, 2, 20, 12) + in(4, 6, 14, 10) + in(8, 4, 28, 14);
      const PolygonId nearest = in(4, 6, 14, 10)   ? 1
                                : in(8, 4, 28, 14) ? 2
                                : in(2, 2, 20, 12) ? 0
                                                   : kNoPolygon;
      const std::size_t k = static_cast<std::size_t>(row) * 32 + col;
      EXPECT_EQ(f.overdraw[k], covering) << "row " << row << " col " << col;
      EXPECT_EQ(f.ids[k], nearest) << "row " << row << " col " << col;
      painted += covering;
    }
  }
  EXPECT_EQ(f.stats.fragments_tested, painted);
  EXPECT_EQ(f.stats.fragments_written, painted);
}

// Seeded random scenes with interpenetrating pairs, cyclic overlaps and coplanar polygons:
// no clearly wrong pixel, cycles closed and broken, and nothing left unresolved.
TEST(Painter, RandomScenesHaveNoClearlyWrongPixel) {
  std::uint64_t splits = 0, cycles = 0, unresolved = 0;
  const Comparison total = testing::expectNoWrongPixelOnRandomScenes(
      "painter", [&](const Scene& scene, const Camera& camera) {
        RenderOptions o;
        o.algorithm = "painter";
        const Frame f = render(scene, camera, o);
        splits += f.stats.counter("painter: splits");
        cycles += f.stats.counter("painter: cycles broken");
        unresolved += f.stats.counter("painter: unresolved");
      });
  EXPECT_EQ(unresolved, 0u);
  EXPECT_GT(cycles, 0u) << "the scenes' cyclic overlaps should close cycles";
  testing::printFigures("painter, " + std::to_string(60 * testing::countScale()) +
                        " random scenes: " + describe(total) + "; " + testing::grouped(splits) +
                        " splits, " + testing::grouped(cycles) + " cycles broken");
}

// The real models of the Mesa test: ids agree with the z-buffer's on at least 99.9% of the
// drawn pixels, and no pixel is clearly wrong.
TEST(Painter, RealModelsAgreeWithTheZBuffer) {
  testing::expectRealModelsAgreeWithTheZBuffer("painter");
}

}  // namespace
}  // namespace hsr
