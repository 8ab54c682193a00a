// Cross-algorithm agreement, docs/testing.md row 4 (the main oracle): every algorithm in the
// registry renders the random scenes of tests/cross/random_scenes.hpp (interpenetrating pairs,
// a cyclic overlap, coplanar overlaps, convex polygons, slivers), and its polygon-id buffer is
// compared with the double-precision reference z-buffer pixel by pixel. Three-valued, as
// dEQP's verifier: unambiguous pixels must match exactly; ambiguous ones (within 1 px of an
// edge or an intersection line that matters, or a near tie in depth) may differ, are logged,
// and are capped at 0.5 % of the pixels of every scene.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cross/figures.hpp"
#include "cross/random_scenes.hpp"
#include "cross/reference_zbuffer.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using testing::ReferenceFrame;

constexpr double kAmbiguousCap = 0.005;  // of the pixels of a scene (docs/testing.md row 4)
constexpr std::uint64_t kFirstSeed = 1;
constexpr int kReportsPerScene = 5;          // unambiguous mismatches spelled out per scene ...
constexpr std::uint64_t kReportsInAll = 40;  // ... and per algorithm

struct Tally {
  std::uint64_t scenes = 0, triangles = 0, pixels = 0, unambiguous = 0, mismatches = 0;
  std::uint64_t ambiguous = 0, ambiguous_differ = 0;
  std::uint64_t differ_edge = 0, differ_tie = 0, differ_intersection = 0;  // by reason (bits)
  std::uint64_t worst_differ = 0, worst_seed = 0;                          // per scene
  std::uint64_t reported = 0;
};

// One algorithm's frame against the reference; adds to the tally and reports failures.
void compareWithReference(const Scene& scene, const Camera& camera, const Frame& frame,
                          const ReferenceFrame& ref, std::uint64_t seed, Tally& t) {
  ASSERT_EQ(frame.width, ref.width);
  ASSERT_EQ(frame.height, ref.height);
  ASSERT_EQ(frame.ids.size(), ref.ids.size());
  std::uint64_t differ = 0;
  int reported = 0;
  for (int y = 0; y < ref.height; ++y) {
    for (int x = 0; x < ref.width; ++x) {
      const std::size_t k = ref.index(x, y);
      const bool same = frame.ids[k] == ref.ids[k];
      if (ref.ambiguous[k]) {
        t.ambiguous++;
        if (same) continue;
        differ++;
        t.differ_edge += (ref.ambiguous[k] & testing::kRefEdge) != 0;
        t.differ_tie += (ref.ambiguous[k] & testing::kRefTie) != 0;
        t.differ_intersection += (ref.ambiguous[k] & testing::kRefIntersection) != 0;
        continue;
      }
      t.unambiguous++;
      if (same) continue;
      t.mismatches++;
      if (reported++ >= kReportsPerScene || t.reported++ >= kReportsInAll) continue;
      // Spell out what the reference knows about both polygons at this centre.
      auto describe = [&](PolygonId id) {
        if (id == kNoPolygon) return std::string("nothing");
        const testing::RefProbe p = testing::probePolygon(scene, camera, id, x, y);
        char buf[160];
        std::snprintf(buf, sizeof buf, "polygon %u (ref: covers %d, z %.9f, %.3f px from its edge)",
                      id, p.covers ? 1 : 0, p.depth, p.edge_distance);
        return std::string(buf);
      };
      ADD_FAILURE() << "seed " << seed << ": unambiguous pixel (" << x << ", " << y
                    << ") [GL window, y up] expected " << describe(ref.ids[k]) << ", got "
                    << describe(frame.ids[k]) << " at depth " << frame.depth[k];
    }
  }
  t.ambiguous_differ += differ;
  if (differ > t.worst_differ) {
    t.worst_differ = differ;
    t.worst_seed = seed;
  }
  const std::uint64_t pixels = ref.ids.size();
  t.pixels += pixels;
  t.scenes++;
  t.triangles += scene.triangleCount();
  EXPECT_LE(differ, static_cast<std::uint64_t>(std::ceil(kAmbiguousCap * double(pixels))))
      << "seed " << seed << ": " << differ << " ambiguous pixels differ";
}

// One test per algorithm (Agreement.MatchesTheReferenceZBuffer/ALGORITHM), so that CTest runs
// them side by side; each computes the reference of every scene itself.
class Agreement : public testing::EveryAlgorithm {};

TEST_P(Agreement, MatchesTheReferenceZBuffer) {
  // A third of them in the sanitizer leg's tier (testing::legCases)
  const int scenes = testing::legCases(200 * testing::countScale(), 3);
  const AlgorithmInfo& algo = findAlgorithm(GetParam());
  Tally t;
  for (int i = 0; i < scenes; ++i) {
    const std::uint64_t seed = kFirstSeed + static_cast<std::uint64_t>(i);
    SCOPED_TRACE("agreementScene(" + std::to_string(seed) + ")");
    const Scene scene = testing::agreementScene(seed);
    const Camera camera = testing::agreementCamera(seed);
    ASSERT_GE(scene.triangleCount(), 50u);
    ASSERT_LE(scene.triangleCount(), 500u);
    const ReferenceFrame ref = testing::referenceZBuffer(scene, camera);
    ASSERT_TRUE(ref.valid) << ref.problem;
    RenderOptions o;
    o.algorithm = std::string(algo.name);
    o.cull = CullMode::None;
    o.threads = 1 + static_cast<int>(seed % 2);
    const Frame frame = render(scene, camera, o);
    compareWithReference(scene, camera, frame, ref, seed, t);
  }
  // The reference must leave most pixels decidable, or the test proves little.
  EXPECT_GT(t.unambiguous, t.pixels / 2);
  testing::printFigures("row 4 " + std::string(algo.name) + ": " + testing::grouped(t.scenes) +
                        " scenes (" + testing::grouped(t.triangles) + " triangles), " +
                        testing::grouped(t.pixels) + " pixels, " + testing::grouped(t.unambiguous) +
                        " unambiguous, " + testing::grouped(t.mismatches) + " mismatches; " +
                        testing::grouped(t.ambiguous) + " ambiguous, " +
                        testing::grouped(t.ambiguous_differ) + " differ (" +
                        testing::percent(t.ambiguous_differ, t.pixels) + " of pixels)");
  std::printf(
      "  ambiguous differences by reason: edge %s, depth tie %s, intersection %s; "
      "worst scene: seed %llu, %s px (%s)\n",
      testing::grouped(t.differ_edge).c_str(), testing::grouped(t.differ_tie).c_str(),
      testing::grouped(t.differ_intersection).c_str(),
      static_cast<unsigned long long>(t.worst_seed), testing::grouped(t.worst_differ).c_str(),
      testing::percent(t.worst_differ, t.scenes ? t.pixels / t.scenes : 0).c_str());
}

HSR_INSTANTIATE_FOR_EVERY_ALGORITHM(Agreement);

}  // namespace
}  // namespace hsr
