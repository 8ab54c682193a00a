// The scan-line algorithm (scanline.cpp). It shares the z-buffer's coverage, fragment depth
// and tie rule, so its frame must be the z-buffer's bit for bit (ids, depths, colours): its
// entry says zbuffer-frame, and tests/cross/zbuffer_frame_test.cpp holds it to that on the
// agreement scene set, the real models and glass. Here: the notes' invariants hold: spans on a row
// never overlap and lie inside the viewport, and the active edge list is empty after the
// last row.

#include <gtest/gtest.h>

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
#include "visibility/scanline.hpp"

namespace hsr {
namespace {

// Watches the pass: each row is cut into spans that follow each other from column 0 to the
// width, rows in order; at the end no edge is left.
class SpanChecker : public detail::ScanlineObserver {
 public:
  explicit SpanChecker(int width, int height) : width_(width), height_(height) {}
  void span(int y, int x_begin, int x_end, std::size_t polygons) override {
    if (y != row_) {
      EXPECT_EQ(next_x_, row_ < 0 ? 0 : width_) << "row " << row_ << " ended early";
      EXPECT_EQ(y, row_ + 1) << "rows out of order";
      row_ = y;
      next_x_ = 0;
    }
    EXPECT_EQ(x_begin, next_x_) << "row " << y << ": spans overlap or leave a gap";
    EXPECT_LT(x_begin, x_end);
    EXPECT_GE(x_begin, 0);
    EXPECT_LE(x_end, width_);
    next_x_ = x_end;
    spans++;
    several += polygons > 1;
  }
  void finished(std::size_t edges_left) override {
    finished_calls++;
    left = edges_left;
    EXPECT_EQ(row_, height_ - 1);
    EXPECT_EQ(next_x_, width_);
  }
  std::uint64_t spans = 0, several = 0, finished_calls = 0;
  std::size_t left = 1;

 private:
  int width_, height_, row_ = -1, next_x_ = 0;
};

TEST(Scanline, SpansPartitionEveryRowAndTheActiveEdgeListEndsEmpty) {
  std::uint64_t spans = 0, several = 0;
  auto check = [&](const Scene& scene, const Camera& camera) {
    RenderOptions o;
    o.cull = CullMode::None;
    o.algorithm = "scanline";
    const detail::PreparedScene prepared = detail::prepare(scene, camera, o);
    Frame frame;
    detail::clearFrame(frame, camera.width, camera.height, o);
    SpanChecker checker(camera.width, camera.height);
    detail::drawScanlineObserved({scene, camera, o, prepared}, frame, &checker);
    EXPECT_EQ(checker.finished_calls, 1u);
    EXPECT_EQ(checker.left, 0u);
    spans += checker.spans;
    several += checker.several;
    // Observed or not, the same picture.
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
  EXPECT_GT(several, 0u);
  testing::printFigures("scanline invariants: " + testing::grouped(spans) + " spans checked, " +
                        testing::grouped(several) + " inside several polygons");
}

// Bands of rows run in parallel; the picture and every count are the same at any thread count.
TEST(Scanline, SameFrameAndCountsAtAnyThreadCount) {
  const Frame one = testing::expectSameFrameAndCountsAtAnyThreadCount("scanline");
  // The notes' coherence at work: spans wider than two pixels inside several polygons are
  // mostly settled at their ends, many by the previous row's order, few pixel by pixel.
  const std::uint64_t several = one.stats.counter("scanline: spans inside several");
  const std::uint64_t reused = one.stats.counter("scanline: previous row's order reused");
  const std::uint64_t ends = one.stats.counter("scanline: decided at the span's ends");
  const std::uint64_t pixels = one.stats.counter("scanline: compared pixel by pixel");
  const std::uint64_t tiny = one.stats.counter("scanline: one or two pixels, compared at each");
  EXPECT_GT(several, 0u);
  EXPECT_EQ(reused + ends + pixels + tiny, several);
  EXPECT_GT(reused, 0u);
  EXPECT_LT(pixels, (reused + ends + pixels) / 4);
  testing::printFigures("scanline spheres:20000 400x300: " + testing::grouped(several) +
                        " spans inside several polygons: " + testing::grouped(tiny) +
                        " of one or two pixels; of the rest " + testing::grouped(reused) +
                        " previous row's order, " + testing::grouped(ends) + " at the ends, " +
                        testing::grouped(pixels) + " pixel by pixel");
}

}  // namespace
}  // namespace hsr
