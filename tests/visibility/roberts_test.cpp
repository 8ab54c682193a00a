// Roberts' algorithm (hsr/roberts.hpp, src/visibility/roberts.cpp): its visible segments are
// the edges of the Weiler-Atherton visible set (every segment on a visible-set edge, every
// visible-set edge on a segment, within 1e-6 of the view size; junction lines, which the visible
// set snaps to the grid, within two grid units, their ends within 16 where a crossing meets them at
// a grazing angle); it says which objects are convex solids and why the others are taken face by
// face; its picture agrees with the z-buffer's on the real models of the Mesa test (the agreement
// suite, row 4, it joins through the registry).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "cross/compare_with_zbuffer.hpp"
#include "cross/figures.hpp"
#include "cross/random_scenes.hpp"
#include "hsr/error.hpp"
#include "hsr/explain.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "hsr/roberts.hpp"
#include "hsr/visible_set.hpp"
#include "pipeline/pipeline.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using glm::dvec2;
using testing::grouped;
using testing::randomBoxes;

struct Seg {
  dvec2 a, b;
  bool loose = false;  // a junction line: the visible set snaps it to the grid
};

// The edges of the visible set's regions, in pixels, less those along the picture's border.
std::vector<Seg> visibleSetEdges(const VisibleSet& set) {
  std::vector<Seg> out;
  const double g = kVisibleSetGrid, x0 = -0.5, y0 = -0.5, x1 = set.width - 0.5,
               y1 = set.height - 0.5;
  auto onBorder = [&](dvec2 a, dvec2 b) {
    auto near = [&](double u, double w) { return std::abs(u - w) <= 1.0 / g; };
    return (near(a.x, x0) && near(b.x, x0)) || (near(a.x, x1) && near(b.x, x1)) ||
           (near(a.y, y0) && near(b.y, y0)) || (near(a.y, y1) && near(b.y, y1));
  };
  auto ring = [&](const ExactRing& r) {
    for (std::size_t i = 0; i < r.size(); ++i) {
      const dvec2 a(r[i].xd() / g, r[i].yd() / g),
          b(r[(i + 1) % r.size()].xd() / g, r[(i + 1) % r.size()].yd() / g);
      if (!onBorder(a, b)) out.push_back({a, b});
    }
  };
  for (const VisiblePolygon& v : set.polygons)
    for (const ExactPolygon& p : v.region) {
      ring(p.outer);
      for (const ExactRing& h : p.holes) ring(h);
    }
  return out;
}

// How far an end of a loose segment may fall short, in pixels. A crossing snapped by a grid unit
// moves the point where it meets an edge along that edge by a grid unit over the sine of the
// angle between them, and the crossing may be hidden (it still moves the ends of the edges in
// front of it): randomBoxes(1) has a visible-set edge whose snapped end lies 0.019 px beyond
// Roberts' segment. Sines down to 1/16 are allowed: 16 grid units at each end.
constexpr double kLooseEndSlack = 16.0 / kVisibleSetGrid;

// Length of s that no segment of `by` covers: those lying along s's line within tolerance. A
// loose segment is measured without its ends' slack (kLooseEndSlack), its middle held as tightly.
double uncovered(const Seg& s, const std::vector<Seg>& by, double strict, double loose) {
  const dvec2 d = s.b - s.a;
  const double len2 = glm::dot(d, d);
  if (len2 == 0) return 0;
  const double len = std::sqrt(len2);
  const double slack = s.loose ? std::min(0.5, kLooseEndSlack / len) : 0.0;
  std::vector<std::pair<double, double>> spans;
  for (const Seg& t : by) {
    const double tol = s.loose || t.loose ? loose : strict;
    auto off = [&](dvec2 p) { return std::abs(d.x * (p.y - s.a.y) - d.y * (p.x - s.a.x)) / len; };
    if (off(t.a) > tol || off(t.b) > tol) continue;
    double u0 = glm::dot(t.a - s.a, d) / len2, u1 = glm::dot(t.b - s.a, d) / len2;
    if (u0 > u1) std::swap(u0, u1);
    u0 = std::max(u0, slack), u1 = std::min(u1, 1.0 - slack);
    if (u1 > u0) spans.emplace_back(u0, u1);
  }
  std::sort(spans.begin(), spans.end());
  double covered = 0, reach = 0;
  for (const auto& [u0, u1] : spans) {
    if (u1 <= reach) continue;
    covered += u1 - std::max(u0, reach);
    reach = u1;
  }
  return std::max(0.0, 1 - 2 * slack - covered) * len;
}

struct Agreement {
  std::uint64_t segments = 0, set_edges = 0, junctions = 0, strict = 0, loose = 0,
                along_crossings = 0;
  double length = 0, worst = 0;
  std::string worst_where;
};

double toSegment(dvec2 p, const Seg& s) {
  const dvec2 d = s.b - s.a;
  const double len2 = glm::dot(d, d);
  const double u = len2 > 0 ? std::clamp(glm::dot(p - s.a, d) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (s.a + d * u));
}

// Every Roberts segment lies on the visible set's edges and every visible-set edge on Roberts'
// segments, within 1e-6 of the view size (an end may fall short by twice that). The visible set
// cuts polygons along the lines where two planes cross with that line snapped to the grid
// (within about a grid unit: hsr/visible_set.hpp): along junction lines, and along edges shared
// by two faces of a non-convex object whose pictures overlap. Near those lines (two grid
// units), the tolerance is two grid units; on scenes with such crossings anywhere
// (`crossings`: penetrating or non-convex objects), everywhere, since a crossing hidden from
// view still moves the ends of the edges that pass in front of it by a grid unit.
void expectSameSegments(const Scene& scene, const Camera& camera, const std::string& what,
                        bool crossings_anywhere, Agreement& a) {
  // Back faces culled for both: Roberts removes them anyway, and the visible set would compare
  // each solid's back faces with its front ones, whose planes cross along their shared edges.
  RenderOptions o;
  o.cull = CullMode::Back;
  const RobertsDrawing d = robertsDrawing(scene, camera, o);
  const VisibleSet set = visibleSet(scene, camera, o);
  ASSERT_EQ(set.unresolved, 0u) << what;
  std::vector<bool> solid(scene.objects.size(), false);
  for (const RobertsObject& ro : d.objects) solid[ro.object] = ro.solid;
  std::vector<Seg> roberts, crossings;
  for (const RobertsSegment& s : d.segments) {
    roberts.push_back({{s.x0, s.y0}, {s.x1, s.y1}});
    a.junctions += s.junction;
    if (s.junction || (s.other != kNoPolygon && !solid[scene.object(s.face)]))
      crossings.push_back(roberts.back());
  }
  const double strict = 1e-6 * std::max(camera.width, camera.height), loose = 2.0 / kVisibleSetGrid;
  auto nearCrossing = [&](dvec2 p) {
    for (const Seg& c : crossings)
      if (toSegment(p, c) <= loose) return true;
    return false;
  };
  // A visible-set edge with both ends within two grid units of one crossing's line (and a
  // pixel of the crossing) is that crossing as the visible set snaps it: its split may run on
  // past a corner along the line, as a spike a grid unit wide. It has its Roberts segment
  // nearby, which is all that is asked of it.
  auto alongCrossing = [&](const Seg& e) {
    for (const Seg& c : crossings) {
      const dvec2 dir = c.b - c.a;
      const double len = glm::length(dir);
      if (len == 0) continue;
      auto line = [&](dvec2 p) {
        return std::abs(dir.x * (p.y - c.a.y) - dir.y * (p.x - c.a.x)) / len;
      };
      if (line(e.a) <= loose && line(e.b) <= loose && toSegment(e.a, c) <= 1 &&
          toSegment(e.b, c) <= 1)
        return true;
    }
    return false;
  };
  const std::vector<Seg> all_edges = visibleSetEdges(set);
  std::vector<Seg> edges;  // those held to cover, and be covered by, Roberts' segments
  std::uint64_t along = 0;
  for (const Seg& e : all_edges) {
    if (alongCrossing(e)) {
      along++;
      continue;
    }
    edges.push_back(e);
    edges.back().loose = crossings_anywhere || (nearCrossing(e.a) && nearCrossing(e.b));
  }
  for (Seg& r : roberts) r.loose = crossings_anywhere || nearCrossing(r.a) || nearCrossing(r.b);
  auto check = [&](const std::vector<Seg>& segs, const std::vector<Seg>& by, const char* which) {
    for (const Seg& s : segs) {
      const double miss = uncovered(s, by, strict, loose);
      const double allowed = 2 * (s.loose ? loose : strict);
      (s.loose ? a.loose : a.strict)++;
      if (!s.loose && miss > a.worst) {
        a.worst = miss;
        a.worst_where = what + ": " + which + " (" + std::to_string(s.a.x) + ", " +
                        std::to_string(s.a.y) + ") - (" + std::to_string(s.b.x) + ", " +
                        std::to_string(s.b.y) + ")";
      }
      EXPECT_LE(miss, allowed) << what << ": " << which << " (" << s.a.x << ", " << s.a.y << ") - ("
                               << s.b.x << ", " << s.b.y << ") is uncovered for " << miss << " px";
    }
  };
  check(roberts, all_edges, "Roberts segment");
  check(edges, roberts, "visible-set edge");
  a.segments += roberts.size();
  a.set_edges += edges.size() + along;
  a.along_crossings += along;
  for (const Seg& s : roberts) a.length += glm::length(s.b - s.a);
}

Camera orbit(const Camera& c, double degrees) {
  Camera o = c;
  const double t = degrees * 3.14159265358979323846 / 180.0;
  const glm::vec3 d = c.eye - c.target;
  o.eye = c.target + glm::vec3(static_cast<float>(d.x * std::cos(t) + d.z * std::sin(t)), d.y,
                               static_cast<float>(-d.x * std::sin(t) + d.z * std::cos(t)));
  return o;
}

TEST(Roberts, SegmentsAreTheVisibleSetsEdges) {
  Agreement a;
  int views = 0;
  for (const char* spec : {"solids", "demo"}) {
    const Scene scene = loadScene(spec);
    const Camera base = frameScene(scene, 640, 480);
    for (int k = 0; k < 8; ++k) {
      expectSameSegments(scene, orbit(base, 45.0 * k),
                         std::string(spec) + " at " + std::to_string(45 * k) + " degrees",
                         std::string(spec) != "solids", a);
      ++views;
    }
  }
  const int seeds = 12 * testing::countScale();
  for (int i = 0; i < seeds; ++i) {
    const Scene scene = randomBoxes(static_cast<std::uint64_t>(i));
    expectSameSegments(scene, frameScene(scene, 400, 300), "randomBoxes(" + std::to_string(i) + ")",
                       true, a);
    ++views;
  }
  EXPECT_GT(a.junctions, 0u) << "no junction line was tested";
  testing::printFigures(
      "roberts: " + grouped(views) + " views, " + grouped(a.segments) + " segments (" +
      grouped(static_cast<std::uint64_t>(a.length)) + " px, " + grouped(a.junctions) +
      " on junction lines) against " + grouped(a.set_edges) + " visible-set edges; " +
      grouped(a.strict) + " held to 1e-6 of the view, " + grouped(a.loose) +
      " near crossing lines to two grid units, " + grouped(a.along_crossings) +
      " visible-set edges on crossing lines; largest stretch not covered (1e-6 ones) " +
      [&] {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.3g", a.worst);
        return std::string(buf);
      }() +
      " px" + (a.worst > 0 ? " (" + a.worst_where + ")" : ""));
}

TEST(Roberts, SaysWhichObjectsAreSolidsAndWhyOthersAreNot) {
  {
    const Scene scene = loadScene("solids");
    const Camera camera = frameScene(scene, 640, 480);
    const RobertsDrawing d = robertsDrawing(scene, camera);
    EXPECT_EQ(d.solids, 6u);
    EXPECT_EQ(d.back_faces + d.faces, scene.polygonCount());
    EXPECT_GT(d.back_faces, scene.polygonCount() / 3);
    for (const RobertsObject& o : d.objects)
      EXPECT_TRUE(o.solid) << scene.objects[o.object].name << ": " << o.reason;
    // Every segment bounds a front face: the notes' facing test, counter-clockwise from outside.
    for (const RobertsSegment& s : d.segments) {
      EXPECT_EQ(detail::eyeSpaceOrientation(scene, s.face, camera), 1) << s.face;
      if (s.other != kNoPolygon) {
        EXPECT_EQ(detail::eyeSpaceOrientation(scene, s.other, camera), 1) << s.other;
      }
    }
    // A view from inside the view volume's reach: the near plane cuts the nearest solid.
    Camera close = camera;
    close.eye = camera.target + (camera.eye - camera.target) * 0.3f;
    const RobertsDrawing dc = robertsDrawing(scene, close);
    bool cut = false;
    for (const RobertsObject& o : dc.objects) cut = cut || o.reason == "cut by the view volume";
    EXPECT_TRUE(cut);
  }
  const Scene demo = loadScene("demo");
  const RobertsDrawing d = robertsDrawing(demo, frameScene(demo, 640, 480));
  std::map<std::string, std::string> why;
  for (const RobertsObject& o : d.objects)
    why[demo.objects[o.object].name] = o.solid ? "solid" : o.reason;
  EXPECT_EQ(why["convex dodecahedron"], "solid");
  EXPECT_EQ(why["cube behind glass"], "solid");
  EXPECT_NE(why["non-convex star prism"].find("not convex"), std::string::npos)
      << why["non-convex star prism"];
  EXPECT_NE(why["penetrating quads"].find("open"), std::string::npos) << why["penetrating quads"];
  EXPECT_NE(why["cyclic sticks"].find("open"), std::string::npos) << why["cyclic sticks"];
  EXPECT_EQ(why.count("glass pane"), 0u);  // see-through: hides nothing, not in the drawing
  EXPECT_EQ(d.junctions, 1u);              // the penetrating quads
  RenderOptions line;
  line.polygon_mode = PolygonMode::Line;
  EXPECT_THROW(robertsDrawing(demo, frameScene(demo, 64, 48), line), Error);
}

// The teaching view: solids, back faces, each face with its sections and segments, the end.
TEST(Roberts, ExplainShowsBackFacesSectionsAndSegments) {
  const testing::ScratchDir scratch("hsr_explain_roberts");
  const Scene scene = loadScene("solids");
  const Camera cam = frameScene(scene, 200, 150);
  RenderOptions o;
  o.algorithm = "roberts";
  const Explanation e = explain(scene, cam, o, scratch.path());
  ASSERT_GE(e.steps.size(), 4u);
  EXPECT_EQ(e.steps[0].name, "solids");
  EXPECT_EQ(e.steps[1].name, "back faces");
  EXPECT_EQ(e.steps.back().name, "done");
  int faces = 0;
  for (const ExplainedStep& s : e.steps) faces += s.name == "face";
  EXPECT_GT(faces, 0);
  const Frame f = render(scene, cam, o);
  EXPECT_EQ(e.frame.ids, f.ids);
  EXPECT_EQ(e.frame.color, f.color);
}

// The picture: the visible faces filled through the shared routine, against the z-buffer, on
// the built-in solids from eight sides and on the real models of the Mesa test (taken face by
// face: none is a convex solid). Not the engine: 110,037 faces, each tested against about 80
// volumes, take a minute (README gives its figures).
TEST(Roberts, PicturesAgreeWithTheZBuffer) {
  const Scene solids = loadScene("solids");
  const Camera base = frameScene(solids, 640, 480);
  // Roberts removes the solids' back faces: the z-buffer's equivalent is back-face culling
  // (with cull none, it may show a back face over its front neighbour at a silhouette pixel
  // where their float depths come within rounding).
  RenderOptions back;
  back.cull = CullMode::Back;
  std::uint64_t differ = 0, drawn = 0;
  for (int k = 0; k < 8; ++k) {
    const Camera cam = orbit(base, 45.0 * k);
    const Frame z = render(solids, cam, back);
    back.algorithm = "roberts";
    const Frame f = render(solids, cam, back);
    back.algorithm = "zbuffer";
    const testing::Comparison c = testing::compareFrames(z, f, "roberts");
    EXPECT_EQ(c.wrong, 0u) << c.first_wrong;
    EXPECT_EQ(c.ids_differ, 0u) << 45 * k << " degrees";
    differ += c.ids_differ, drawn += c.drawn;
  }
  testing::printFigures("solids from 8 sides: roberts: " + grouped(differ) + " of " +
                        grouped(drawn) +
                        " drawn pixels show another polygon than the z-buffer (cull back)");
  testing::forEachMesaModelView(
      [](const std::string& label, const Scene& scene, const Camera& camera, RenderOptions& o) {
        if (label.find("Engine") != std::string::npos) return;  // see above
        const Frame z = render(scene, camera, o);
        o.algorithm = "roberts";
        const Frame f = render(scene, camera, o);
        const testing::Comparison c = testing::compareFrames(z, f, "roberts");
        testing::printFigures(label + ": roberts: " + testing::describe(c) + " (" +
                              testing::percent(c.drawn - c.ids_differ, c.drawn) + " agree), " +
                              grouped(f.stats.counter("roberts: face-volume tests")) +
                              " face-volume tests, " +
                              grouped(f.stats.counter("roberts: visible segments")) + " segments");
        EXPECT_EQ(c.wrong, 0u) << c.first_wrong;
        EXPECT_LE(c.ids_differ, c.drawn / 1000);
      });
}

}  // namespace
}  // namespace hsr
