// The algorithms whose registry entry says `zbuffer-frame` (kZBufferFrame) draw the reference
// z-buffer's frame bit for bit: ids, depths and colours at every pixel, on the agreement scene
// set, on the real models of the Mesa test and, for those that blend in submission order as
// the z-buffer does, on glass with the outline pen. One suite over the table: an algorithm that
// claims the capability joins it, and one that loses the frame fails here.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cross/compare_with_zbuffer.hpp"
#include "cross/figures.hpp"
#include "hsr/algorithms.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

// The algorithms the frame is claimed for, but the reference itself (listed as not
// applicable: it is what they are compared with), and of those, when `blend_in_order`, the
// ones that do not blend back to front.
std::vector<std::string> claimants(std::string_view suite, bool blend_in_order) {
  std::vector<std::string> names;
  for (const AlgorithmInfo* a : testing::algorithmsWith(suite, kZBufferFrame)) {
    const char* lacks = a->reference                             ? "(the reference)"
                        : blend_in_order && a->has(kBackToFront) ? "(blends back to front)"
                                                                 : nullptr;
    if (lacks)
      testing::notApplicable().push_back({std::string(suite), std::string(a->name), lacks});
    else
      names.emplace_back(a->name);
  }
  return names;
}

class ZBufferFrame : public testing::EveryAlgorithm {
 protected:
  int samples() const { return options().samples; }  // one for an antialiasing algorithm
};

TEST_P(ZBufferFrame, OnTheAgreementScenes) {
  const testing::Identity c = testing::expectBitForBitWithZBuffer(GetParam(), samples());
  testing::printFigures(GetParam() + ", " + testing::grouped(200 * testing::countScale()) +
                        " agreement scenes: " + testing::describe(c));
  EXPECT_EQ(c.differ, 0u) << c.first;
  EXPECT_GT(c.unambiguous, c.pixels / 2);
}

TEST_P(ZBufferFrame, OnRealModels) {
  const testing::Identity c = testing::expectBitForBitOnRealModels(GetParam(), 640, 480, samples());
  EXPECT_EQ(c.differ, 0u) << c.first;
}

INSTANTIATE_TEST_SUITE_P(, ZBufferFrame, ::testing::ValuesIn(claimants("ZBufferFrame", false)),
                         testing::testNameOf);

// Glass over opaque polygons (the demo) and the outline pen: colours too are the z-buffer's.
class ZBufferFrameBlends : public testing::EveryAlgorithm {};

TEST_P(ZBufferFrameBlends, GlassAndOutlinesAsTheZBuffer) {
  testing::expectBlendsAndOutlinesAsTheZBuffer(GetParam());
}

INSTANTIATE_TEST_SUITE_P(, ZBufferFrameBlends,
                         ::testing::ValuesIn(claimants("ZBufferFrameBlends", true)),
                         testing::testNameOf);

}  // namespace
}  // namespace hsr
