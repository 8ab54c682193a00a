// Warnock's area subdivision (warnock.cpp). It shares the z-buffer's coverage, fragment depth
// and tie rule, so its frame must be the z-buffer's bit for bit (ids, depths, colours): its
// entry says zbuffer-frame, and tests/cross/zbuffer_frame_test.cpp holds it to that on the
// agreement scene set, the real models and glass. Here: the notes' invariants hold: the recursion
// is never deeper than ceil(log2(max(W, H))) + 1 levels, and the leaves partition the viewport
// exactly.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/frame.hpp"
#include "cross/compare_with_zbuffer.hpp"
#include "cross/figures.hpp"
#include "cross/random_scenes.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "pipeline/pipeline.hpp"
#include "test_util.hpp"
#include "visibility/warnock.hpp"

namespace hsr {
namespace {

// Counts how often each pixel lies in a leaf, and the deepest level.
class LeafChecker : public detail::WarnockObserver {
 public:
  LeafChecker(int w, int h) : width(w), height(h), hits(static_cast<std::size_t>(w) * h) {}
  void leaf(const detail::PixelBox& a, int level, detail::WarnockStop why) override {
    EXPECT_LE(0, a.x0);
    EXPECT_LE(a.x0, a.x1);
    EXPECT_LT(a.x1, width);
    EXPECT_LE(0, a.y0);
    EXPECT_LE(a.y0, a.y1);
    EXPECT_LT(a.y1, height);
    if (why == detail::WarnockStop::kPixel) {
      EXPECT_TRUE(a.x0 == a.x1 && a.y0 == a.y1);
    }
    for (int y = a.y0; y <= a.y1; ++y)
      for (int x = a.x0; x <= a.x1; ++x) hits[static_cast<std::size_t>(y) * width + x]++;
    deepest = std::max(deepest, level);
    by_why[static_cast<int>(why)]++;
  }
  int width, height, deepest = 0;
  std::vector<std::uint32_t> hits;
  std::uint64_t by_why[detail::kWarnockStops] = {};
};

TEST(Warnock, LeavesPartitionTheViewportWithinTheDepthBound) {
  std::uint64_t by_why[detail::kWarnockStops] = {};
  int deepest = 0;
  auto check = [&](const Scene& scene, const Camera& camera) {
    RenderOptions o;
    o.cull = CullMode::None;
    o.algorithm = "warnock";
    const detail::PreparedScene prepared = detail::prepare(scene, camera, o);
    Frame frame;
    detail::clearFrame(frame, camera.width, camera.height, o);
    LeafChecker leaves(camera.width, camera.height);
    detail::drawWarnockObserved({scene, camera, o, prepared}, frame, &leaves);
    std::uint64_t not_once = 0;
    for (const std::uint32_t h : leaves.hits) not_once += h != 1;
    EXPECT_EQ(not_once, 0u) << "pixels in no leaf or in several";
    // Levels 0 .. ceil(log2(max(W, H))): at most ceil(log2(max(W, H))) + 1 of them.
    const int bound = static_cast<int>(std::ceil(std::log2(std::max(camera.width, camera.height))));
    EXPECT_EQ(detail::warnockDeepestLevel(camera.width, camera.height), bound);
    EXPECT_LE(leaves.deepest, bound);
    deepest = std::max(deepest, leaves.deepest);
    for (int k = 0; k < detail::kWarnockStops; ++k) by_why[k] += leaves.by_why[k];
    const testing::Identity c =
        testing::compareBitForBit(render(scene, camera, o), frame, nullptr, "observed");
    EXPECT_EQ(c.differ, 0u) << c.first;
  };
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    check(testing::agreementScene(seed), testing::agreementCamera(seed, 200, 150));
  }
  const Scene demo = makeBuiltinScene("demo");
  check(demo, frameScene(demo, 333, 201));
  check(demo, frameScene(demo, 1, 77));
  // Every way of stopping occurs.
  for (int k = 0; k < detail::kWarnockStops; ++k) EXPECT_GT(by_why[k], 0u) << "stop " << k;
  testing::printFigures("warnock leaves: " + testing::grouped(by_why[0]) + " nothing there, " +
                        testing::grouped(by_why[1]) + " one polygon, " +
                        testing::grouped(by_why[2]) + " surrounder in front, " +
                        testing::grouped(by_why[3]) + " pixels; deepest level " +
                        std::to_string(deepest));
}

// Quadrants near the top run in parallel; the picture and every count are the same at any
// thread count.
TEST(Warnock, SameFrameAndCountsAtAnyThreadCount) {
  testing::expectSameFrameAndCountsAtAnyThreadCount("warnock");
}

}  // namespace
}  // namespace hsr
