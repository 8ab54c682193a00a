// The 3D BSP tree (bsp_tree.cpp) and rendering from it (bsp.cpp). docs/testing.md row 11, BSP
// split consistency: every polygon of the tree lies in its node's plane, on the right side of
// every ancestor's plane; a split polygon's pieces add up to it; and every way of choosing
// splitters gives the same picture (different trees, one answer).

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "cross/random_scenes.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"
#include "visibility/bsp.hpp"
#include "visibility/bsp_tree.hpp"

namespace hsr {
namespace {

using detail::BspBuildOptions;
using detail::BspTree;
using detail::SplitterChoice;

double area(const std::vector<glm::dvec3>& v) {
  glm::dvec3 n(0.0);
  for (std::size_t i = 0; i < v.size(); ++i) n += glm::cross(v[i], v[(i + 1) % v.size()]);
  return 0.5 * glm::length(n);
}

// Row 11: each polygon lies in its node's plane and on its side of every ancestor's plane,
// within the tree's epsilon; the pieces of every scene polygon add up to its area.
void expectConsistent(const Scene& scene, const BspTree& tree) {
  // Walk down from the root with the path of (node, side) taken.
  struct Item {
    std::int32_t node;
    std::vector<std::pair<std::int32_t, int>> path;
  };
  std::vector<Item> stack{{0, {}}};
  std::map<std::pair<PolygonId, std::uint32_t>, double> piece_area;
  std::uint64_t checked = 0;
  while (!stack.empty() && !tree.nodes.empty()) {
    Item item = std::move(stack.back());
    stack.pop_back();
    const detail::BspNode& n = tree.nodes[item.node];
    for (std::uint32_t k = 0; k < n.polygon_count; ++k) {
      const detail::BspPolygon& p = tree.polygons[tree.order[n.first_polygon + k]];
      piece_area[{p.id, p.piece}] += area(p.vertices);
      for (const glm::dvec3& v : p.vertices) {
        ASSERT_LE(std::abs(glm::dot(glm::dvec3(n.plane), v) + n.plane.w), 4 * tree.epsilon)
            << "polygon " << p.id << " off its node's plane";
        for (const auto& [ancestor, side] : item.path) {
          const glm::dvec4& pl = tree.nodes[ancestor].plane;
          ASSERT_GE(side * (glm::dot(glm::dvec3(pl), v) + pl.w), -4 * tree.epsilon)
              << "polygon " << p.id << " on the wrong side of an ancestor's plane";
        }
        ++checked;
      }
    }
    for (const int side : {1, -1}) {
      const std::int32_t child = side > 0 ? n.front : n.back;
      if (child < 0) continue;
      Item next{child, item.path};
      next.path.emplace_back(item.node, side);
      stack.push_back(std::move(next));
    }
  }
  EXPECT_GT(checked, 0u);
  // Pieces add up to their polygon (planar polygons: piece 0 is the whole).
  for (const auto& [key, a] : piece_area) {
    if (key.second != 0) continue;
    std::vector<glm::dvec3> whole;
    for (const std::uint32_t i : scene.polygon(key.first)) whole.emplace_back(scene.position(i));
    const double expected = area(whole);
    if (expected > 0 && scene.polygon(key.first).size() == 3)
      EXPECT_NEAR(a, expected, 1e-9 * expected + 1e-12) << "pieces of polygon " << key.first;
  }
}

TEST(Bsp, TreesAreConsistentForEverySplitterChoice) {
  for (const char* name : {"cyclic", "penetrating", "demo", "soup:400:3"}) {
    SCOPED_TRACE(name);
    const Scene scene = makeBuiltinScene(name);
    for (const SplitterChoice c : {SplitterChoice::kFirst, SplitterChoice::kRandom, SplitterChoice::kFewest,
                                   SplitterChoice::kBalanced, SplitterChoice::kBestOfK}) {
      SCOPED_TRACE(std::string(detail::toString(c)));
      const BspTree tree = detail::buildBspTree(scene, BspBuildOptions{c, 7, 8});
      EXPECT_EQ(tree.stats.polygons, tree.order.size());
      EXPECT_GE(tree.stats.polygons, tree.stats.input_polygons);
      expectConsistent(scene, tree);
    }
  }
  // The notes' cases need splits: the sticks of `cyclic` and the crossing quads.
  EXPECT_GT(detail::buildBspTree(makeBuiltinScene("penetrating"), {}).stats.splits, 0u);
}

// Back to front for the eye: every polygon drawn before any polygon that lies in front of it
// along a ray from the eye cannot be checked cheaply in general, but the picture can: each
// splitter choice builds another tree, and all must paint the z-buffer's ids.
TEST(Bsp, EverySplitterChoicePaintsTheSamePicture) {
  const Scene scene = makeBuiltinScene("demo");
  const Camera camera = frameScene(scene, 320, 240);
  RenderOptions o;
  o.algorithm = "zbuffer";
  const Frame z = render(scene, camera, o);
  o.algorithm = "bsp";
  const Frame b = render(scene, camera, o);
  std::uint64_t differ = 0, drawn = 0;
  for (std::size_t k = 0; k < z.ids.size(); ++k) {
    drawn += z.ids[k] != kNoPolygon;
    differ += z.ids[k] != b.ids[k];
  }
  EXPECT_LE(differ, drawn / 1000) << differ << " of " << drawn << " drawn pixels differ";
  testing::printFigures("bsp on demo 320x240: " + std::to_string(differ) + " of " + std::to_string(drawn) +
                        " drawn pixels show another polygon than the z-buffer");
}

}  // namespace
}  // namespace hsr
