// The octree method (octree.cpp). Its pieces are cut at octant planes, so it is held to the
// object-order standard (row 4: no clearly wrong pixel on the random scenes, depths equal
// wherever the ids agree) and to at least 99.9% id agreement with the z-buffer on the real
// models; and to the notes' claims: each pixel is written at most once, most hidden octants
// are skipped, and one tree serves every view.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>
#include <glm/geometric.hpp>

#include "cross/compare_with_zbuffer.hpp"
#include "cross/figures.hpp"
#include "cross/random_scenes.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"
#include "visibility/octree.hpp"

namespace hsr {
namespace {

using testing::Comparison;
using testing::describe;

TEST(Octree, RandomScenesHaveNoClearlyWrongPixel) {
  std::uint64_t pieces = 0, polygons = 0;
  const Comparison total =
      testing::expectNoWrongPixelOnRandomScenes("octree", [&](const Scene& scene, const Camera&) {
        const detail::Octree tree = detail::buildOctree(scene);
        pieces += tree.stats.entries;
        polygons += tree.stats.polygons;
      });
  testing::printFigures("octree, " + std::to_string(60 * testing::countScale()) +
                        " random scenes: " + describe(total) + "; " + testing::grouped(polygons) +
                        " polygons held as " + testing::grouped(pieces) + " pieces");
}

TEST(Octree, RealModelsAgreeWithTheZBuffer) {
  testing::expectRealModelsAgreeWithTheZBuffer(
      "octree",
      [](const Scene& scene, const Camera& camera, RenderOptions o) {
        o.algorithm = "octree";
        return render(scene, camera, o);
      },
      [](const Frame& f) {
        return "; " + testing::grouped(f.stats.counter("octree: pixels rewritten on a float tie")) +
               " pixels rewritten on a float tie";
      });
}

// Under an orthographic camera the octants' front-to-back order comes from the view direction,
// not from where the eye lies: the octree must show what the z-buffer shows from all eight
// diagonal directions (every sign of the direction's three components, so that each axis's
// order is taken both ways), on a scene large enough to subdivide and skip covered octants and
// on the real models.
TEST(Octree, OrthographicViewsAgreeWithTheZBuffer) {
  std::vector<std::pair<std::string, Scene>> scenes;
  scenes.emplace_back("spheres:20000", makeBuiltinScene("spheres:20000"));
  for (const char* model : testing::kMesaTestModels)
    scenes.emplace_back(model,
                        loadScene((std::filesystem::path(HSR_TEST_MODELS) / model).string()));
  Comparison total;
  std::uint64_t views = 0, skipped = 0;
  for (const auto& [name, scene] : scenes) {
    SCOPED_TRACE(name);
    // Framed on the bounds (not by a file's own camera, which may look from anywhere)
    const Camera framed = frameBounds(scene.bounds(), 320, 240);
    const float distance = glm::length(framed.eye - framed.target);
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 dir((k & 1) ? 1.0f : -1.0f, (k & 2) ? 0.8f : -0.8f, (k & 4) ? 0.6f : -0.6f);
      Camera c = framed;
      c.eye = c.target + glm::normalize(dir) * distance;
      c.ortho = true;
      fitNearFar(c, scene.bounds());
      c.ortho_half_height = orthoHalfHeightFor(c, scene.bounds());
      RenderOptions o;
      const Frame z = render(scene, c, o);
      o.algorithm = "octree";
      const Frame f = render(scene, c, o);
      const Comparison cmp = testing::compareFrames(z, f, "octree");
      EXPECT_EQ(cmp.wrong, 0u) << "view " << k << ": " << cmp.first_wrong;
      EXPECT_LE(cmp.ids_differ, cmp.drawn / 1000) << "view " << k;
      EXPECT_EQ(cmp.depth_differs_same_id, 0u) << "view " << k;
      EXPECT_GT(cmp.drawn, 1000u) << "view " << k;
      total.add(cmp);
      ++views;
      skipped += f.stats.counter("octree: octants skipped, covered");
    }
  }
  EXPECT_GT(skipped, 0u) << "no covered octant was skipped: the order was never put to the test";
  testing::printFigures("octree, orthographic, 8 diagonal views of spheres:20000 and " +
                        std::to_string(std::size(testing::kMesaTestModels)) + " real models (" +
                        std::to_string(views) + " views): " + describe(total) + "; " +
                        testing::grouped(skipped) + " covered octants skipped");
}

// Every pixel is written once at most (the overdraw buffer counts writes), most hidden
// octants are skipped whole, and the next view of the same scene reuses the tree.
TEST(Octree, WritesEachPixelOnceSkipsHiddenOctantsAndReusesTheTree) {
  const Scene scene = makeBuiltinScene("spheres:20000");
  Camera camera = frameScene(scene, 400, 300);
  RenderOptions o;
  o.algorithm = "octree";
  Frame frame;
  render(scene, camera, o, frame);
  EXPECT_EQ(frame.stats.counter("octree: built for this frame"), 1u);
  std::uint64_t drawn = 0, again = 0;
  for (std::size_t k = 0; k < frame.ids.size(); ++k) {
    drawn += frame.ids[k] != kNoPolygon;
    again += frame.overdraw[k] > 1 ? frame.overdraw[k] - 1 : 0;
  }
  EXPECT_EQ(frame.stats.counter("octree: pixels written once"), drawn);
  // The one exception: a float tie with a nearer octant, settled by the z-buffer's rule.
  EXPECT_EQ(frame.stats.counter("octree: pixels rewritten on a float tie"), again);
  EXPECT_LE(again, drawn / 1000);
  const std::uint64_t skipped = frame.stats.counter("octree: leaves under covered octants");
  const std::uint64_t hidden = frame.stats.counter("octree: leaves drawn, hidden");
  EXPECT_GT(skipped, hidden) << "most hidden octants must be skipped";
  testing::printFigures("octree spheres:20000 400x300: " + testing::grouped(skipped) +
                        " leaves skipped under covered octants, " + testing::grouped(hidden) +
                        " drawn and found hidden: " + testing::percent(skipped, skipped + hidden) +
                        " of the hidden leaves skipped");
  // Another view of the same scene: the same tree.
  camera.eye =
      camera.target + glm::vec3(1.0f, 0.3f, 0.2f) * glm::length(camera.eye - camera.target);
  render(scene, camera, o, frame);
  EXPECT_EQ(frame.stats.counter("octree: built for this frame"), 0u);
  // A changed scene: a new tree.
  Scene moved = scene;
  moved.addPolygonVertices({glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)}, 0);
  render(moved, camera, o, frame);
  EXPECT_EQ(frame.stats.counter("octree: built for this frame"), 1u);
}

// Bands of rows are drawn in parallel; the picture and every count are the same at any thread
// count.
TEST(Octree, SameFrameAndCountsAtAnyThreadCount) {
  testing::expectSameFrameAndCountsAtAnyThreadCount("octree");
}

// Every polygon is held by some leaf, and only by leaves its bounding box reaches.
TEST(Octree, TreeHoldsEveryPolygonInTheOctantsItReaches) {
  const Scene scene = testing::agreementScene(7);
  const detail::Octree tree = detail::buildOctree(scene);
  ASSERT_FALSE(tree.nodes.empty());
  std::vector<int> held(scene.polygonCount(), 0);
  for (const detail::OctreeNode& n : tree.nodes) {
    if (n.first_child >= 0) continue;
    for (std::uint32_t k = 0; k < n.entry_count; ++k) {
      const detail::OctreeEntry& e = tree.entries[n.first_entry + k];
      held[e.polygon]++;
      // The polygon's bounding box reaches the leaf's box.
      for (int a = 0; a < 3; ++a) {
        float lo = INFINITY, hi = -INFINITY;
        for (const std::uint32_t v : scene.polygon(e.polygon))
          lo = std::min(lo, scene.position(v)[a]), hi = std::max(hi, scene.position(v)[a]);
        const double eps = 1e-5 * glm::length(tree.nodes[0].hi - tree.nodes[0].lo);
        EXPECT_LE(lo, n.hi[a] + eps);
        EXPECT_GE(hi, n.lo[a] - eps);
      }
    }
  }
  for (PolygonId p = 0; p < scene.polygonCount(); ++p) EXPECT_GE(held[p], 1) << "polygon " << p;
  EXPECT_GT(tree.stats.leaves, 1u);
  EXPECT_LE(tree.stats.depth, static_cast<std::uint64_t>(detail::kOctreeMaxDepth));
}

}  // namespace
}  // namespace hsr
