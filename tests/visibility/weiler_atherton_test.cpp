// The Weiler-Atherton visible set (hsr/visible_set.hpp, src/visibility/weiler_atherton.cpp):
// its regions never overlap (the area of every pairwise intersection is exactly 0), they add
// up exactly to the union of the snapped polygons and, within the squares its outline crosses,
// to the pixels the z-buffer covers, nothing is left unresolved on these scenes; and on the real
// models of the Mesa test its frame agrees with the z-buffer's (docs/testing.md row 4 is the
// agreement suite, which it joins through the registry).

#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <cmath>
#include <string>
#include <vector>

#include <gmpxx.h>

#include "cross/compare_with_zbuffer.hpp"
#include "cross/figures.hpp"
#include "cross/random_scenes.hpp"
#include "hsr/explain.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "hsr/visible_set.hpp"
#include "pipeline/pipeline.hpp"
#include "raster/primitives.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using testing::grouped;

struct Box {
  double x0, y0, x1, y1;
};
Box boxOf(const ExactRegion& r) {
  Box b{INFINITY, INFINITY, -INFINITY, -INFINITY};
  for (const ExactPolygon& p : r)
    for (const ExactPoint& v : p.outer)
      b = {std::min(b.x0, v.xd()), std::min(b.y0, v.yd()), std::max(b.x1, v.xd()),
           std::max(b.y1, v.yd())};
  return b;
}

// The union of the scene's opaque polygons as the visible set takes them (snapped to the grid).
ExactRegion snappedUnion(const Scene& scene, const Camera& camera, const RenderOptions& o) {
  const detail::PreparedScene ps = detail::prepare(scene, camera, o, {.window_polygons = true});
  ExactRegion all;
  for (const detail::WindowPolygon& w : ps.polygons) {
    if (w.transparent) continue;
    GridRing ring;
    for (const glm::dvec3& v : w.vertices) {
      const GridPoint g{std::llrint(v.x * detail::kSubpixelOne),
                        std::llrint(v.y * detail::kSubpixelOne)};
      if (ring.empty() || !(ring.back() == g)) ring.push_back(g);
    }
    while (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
    const GridRegion r{{ring, {}}};
    if (ring.size() < 3 || !invalidRegionReason(r).empty()) continue;
    all = booleanOp(all, exactRegion(r), BooleanOp::Union);
  }
  return all;
}

struct Tally {
  std::uint64_t scenes = 0, polygons = 0, pairs = 0, overlapping = 0;
  double worst_share = 0;  // the largest |area - covered pixels| as a share of its bound
};

// The pixel squares the outline of a region passes through, counted with repetition (at most
// ceil|dx| + ceil|dy| + 1 per edge, in pixels): only such a square can hold a pixel centre on the
// other side of the outline from most of its area, and each is off by less than one. So the
// count of pixel centres inside the region differs from its area by less than this.
double squaresOnTheOutline(const ExactRegion& region) {
  double squares = 0;
  auto ring = [&](const ExactRing& points) {
    for (std::size_t i = 0; i < points.size(); ++i) {
      const ExactPoint &a = points[i], &b = points[(i + 1) % points.size()];
      squares += std::ceil(std::abs(b.xd() - a.xd()) / detail::kSubpixelOne) +
                 std::ceil(std::abs(b.yd() - a.yd()) / detail::kSubpixelOne) + 1;
    }
  };
  for (const ExactPolygon& p : region) {
    ring(p.outer);
    for (const ExactRing& h : p.holes) ring(h);
  }
  return squares;
}

// One view: no two visible regions overlap; their exact areas add up to the union's; the
// covered pixels of the z-buffer's frame are the summed area to within the pixel squares the
// union's outline passes through (squaresOnTheOutline: sampling at pixel centres can be off by
// no more). An earlier bound of 0.1% of the covered pixels was a figure seen on some scenes, not
// a property: scene 12's centres fall 0.14% short of its area.
void checkView(const Scene& scene, const Camera& camera, const RenderOptions& o,
               const std::string& what, Tally& t, bool union_check) {
  const VisibleSet set = visibleSet(scene, camera, o);
  EXPECT_EQ(set.unresolved, 0u) << what;
  t.scenes++;
  t.polygons += set.polygons.size();
  std::vector<Box> boxes;
  for (const VisiblePolygon& v : set.polygons) boxes.push_back(boxOf(v.region));
  mpq_class sum = 0;
  for (std::size_t i = 0; i < set.polygons.size(); ++i) {
    sum += mpq_class(exactArea(set.polygons[i].region));
    for (std::size_t j = 0; j < i; ++j) {
      const Box &a = boxes[i], &b = boxes[j];
      if (a.x0 >= b.x1 || b.x0 >= a.x1 || a.y0 >= b.y1 || b.y0 >= a.y1) continue;
      t.pairs++;
      const std::string shared = exactArea(
          booleanOp(set.polygons[i].region, set.polygons[j].region, BooleanOp::Intersection));
      if (shared != "0" && t.overlapping++ < 5)
        ADD_FAILURE() << what << ": visible polygons " << set.polygons[i].id << " and "
                      << set.polygons[j].id << " overlap by " << shared << " square grid units";
    }
  }
  const ExactRegion all = snappedUnion(scene, camera, o);
  if (union_check) {
    EXPECT_EQ(sum, mpq_class(exactArea(all))) << what << ": areas add up to the union";
  }
  RenderOptions z = o;
  z.algorithm = "zbuffer";
  const Frame f = render(scene, camera, z);
  std::uint64_t covered = 0;
  for (const PolygonId id : f.ids) covered += id != kNoPolygon;
  const double area = sum.get_d() / (double{detail::kSubpixelOne} * detail::kSubpixelOne);
  const double off = std::abs(area - static_cast<double>(covered)),
               bound = squaresOnTheOutline(all);
  EXPECT_LT(off, bound) << what << ": " << covered << " pixels covered, visible area " << area;
  t.worst_share = std::max(t.worst_share, off / bound);
}

TEST(WeilerAtherton, VisibleRegionsNeverOverlapAndAddUp) {
  Tally t;
  for (int i = 0; i < 20 * testing::countScale(); ++i) {
    const std::uint64_t seed = 1 + static_cast<std::uint64_t>(i);
    RenderOptions o;
    o.cull = i % 3 == 0 ? CullMode::Back : CullMode::None;
    checkView(testing::agreementScene(seed), testing::agreementCamera(seed), o,
              "scene " + std::to_string(seed), t, true);
  }
  for (const char* spec : {"demo", "cyclic", "penetrating"}) {
    const Scene scene = loadScene(spec);
    checkView(scene, frameScene(scene, 640, 480), {}, spec, t, true);
  }
  {
    const Scene scene = loadScene("spheres:300");
    checkView(scene, frameScene(scene, 640, 480), {}, "spheres:300", t, false);
  }
  EXPECT_EQ(t.overlapping, 0u);
  testing::printFigures("weiler-atherton visible set: " + grouped(t.scenes) + " views, " +
                        grouped(t.polygons) + " visible polygons, " + grouped(t.pairs) +
                        " pairs with overlapping boxes, " + grouped(t.overlapping) +
                        " overlapping (exact areas); covered pixels within " +
                        std::to_string(static_cast<int>(std::lround(100 * t.worst_share))) +
                        "% of their bound from the area");
}

// The notes' hard cases: the three sticks that overlap cyclically, and polygons that pierce one
// another. Both need the inside pieces in front of the clip polygon (cyclic) and splits along
// the line where two planes cross (penetrating); both must come out as the z-buffer's picture.
TEST(WeilerAtherton, CyclicAndPenetratingScenesSplitAndAgree) {
  for (const char* spec : {"cyclic", "penetrating"}) {
    const Scene scene = loadScene(spec);
    const Camera camera = frameScene(scene, 640, 480);
    const VisibleSet set = visibleSet(scene, camera);
    if (std::string(spec) == "penetrating") {
      EXPECT_GT(set.splits, 0u) << spec;
    }
    const testing::Comparison c = testing::compareWithZBuffer(scene, camera, "weiler-atherton");
    EXPECT_EQ(c.wrong, 0u) << spec << ": " << c.first_wrong;
    EXPECT_EQ(c.ids_differ, 0u) << spec;
    testing::printFigures(std::string("weiler-atherton ") + spec + ": " +
                          grouped(set.polygons.size()) + " visible polygons, " +
                          grouped(set.clips) + " clips, " + grouped(set.splits) + " splits; " +
                          testing::describe(c));
  }
}

// The teaching view: the sort, each clip polygon, the inside lists (behind, in front, split)
// and each visible part, ending on the frame render() gives.
TEST(WeilerAtherton, ExplainShowsClipPolygonsAndInsideLists) {
  const testing::ScratchDir scratch("hsr_explain_wa");
  for (const char* spec : {"cyclic", "penetrating"}) {
    SCOPED_TRACE(spec);
    const Scene scene = loadScene(spec);
    const Camera cam = frameScene(scene, 200, 150);
    RenderOptions o;
    o.algorithm = "weiler-atherton";
    const Explanation e = explain(scene, cam, o, scratch / spec);
    ASSERT_GE(e.steps.size(), 4u);
    EXPECT_EQ(e.steps.front().name, "sort");
    EXPECT_EQ(e.steps.back().name, "done");
    std::map<std::string, int> count;
    bool split = false, in_front = false;
    for (const ExplainedStep& s : e.steps) {
      count[s.name]++;
      split = split || s.caption.find("split") != std::string::npos;
      in_front = in_front || s.caption.find("in front") != std::string::npos;
    }
    EXPECT_GT(count["clip polygon"], 0);
    EXPECT_GT(count["inside list"], 0);
    EXPECT_GT(count["visible"], 0);
    if (std::string(spec) == "penetrating") {
      EXPECT_TRUE(split);
    }
    if (std::string(spec) == "cyclic") {
      EXPECT_TRUE(in_front);  // the sticks hide one another in turn
    }
    const Frame f = render(scene, cam, o);
    EXPECT_EQ(e.frame.ids, f.ids);
    EXPECT_EQ(e.frame.color, f.color);
  }
}

// The real models of the Mesa test: ids agree with the z-buffer's on at least 99.9% of the
// drawn pixels, no pixel clearly wrong, nothing unresolved. The engine (110,037 polygons, 27 s
// with cull none in Release) is drawn with cull back only, and under the sanitizers not at all:
// its clipping is what the three others exercise, 5 times slower there.
TEST(WeilerAtherton, RealModelsAgreeWithTheZBuffer) {
  for (const char* model : testing::kMesaTestModels) {
    const bool engine = std::string(model).find("Engine") != std::string::npos;
#ifdef HSR_SANITIZER_BUILD
    if (engine) continue;
#endif
    SCOPED_TRACE(model);
    const Scene scene = loadScene((std::filesystem::path(HSR_TEST_MODELS) / model).string());
    const Camera camera = frameScene(scene, 640, 480);
    for (const CullMode cull : {CullMode::None, CullMode::Back}) {
      if (engine && cull == CullMode::None) continue;
      RenderOptions o;
      o.cull = cull;
      const Frame z = render(scene, camera, o);
      o.algorithm = "weiler-atherton";
      const auto t0 = std::chrono::steady_clock::now();
      const Frame f = render(scene, camera, o);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      const testing::Comparison c = testing::compareFrames(z, f, "weiler-atherton");
      testing::printFigures(std::string(model) +
                            (cull == CullMode::None ? " cull none" : " cull back") +
                            ": weiler-atherton: " + testing::describe(c) + " (" +
                            testing::percent(c.drawn - c.ids_differ, c.drawn) + " agree), " +
                            grouped(f.stats.counter("weiler-atherton: clips")) + " clips, " +
                            std::to_string(static_cast<int>(ms)) + " ms");
      EXPECT_EQ(c.wrong, 0u) << c.first_wrong;
      EXPECT_LE(c.ids_differ, c.drawn / 1000);
      EXPECT_EQ(f.stats.counter("weiler-atherton: left to the depth test"), 0u);
    }
  }
}

}  // namespace
}  // namespace hsr
