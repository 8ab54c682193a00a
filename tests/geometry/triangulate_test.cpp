// Triangulation: every polygon becomes triangles that cover exactly its area, keep its
// winding, and never fill a hole. Pinned by the literal keyhole polygons of assimp-testmodels
// (OBJ/concave_polygon.obj, Collada/ConcavePolygon.dae), which once rendered as filled discs.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "cross/figures.hpp"
#include "geometry/predicates.hpp"
#include "geometry/triangulate.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using Tri = std::array<std::uint32_t, 3>;

double area2(std::span<const glm::dvec2> p) {
  double a = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    a += p[i].x * p[(i + 1) % p.size()].y - p[(i + 1) % p.size()].x * p[i].y;
  return a;
}

double triangleArea2(std::span<const glm::dvec2> p, const Tri& t) {
  const glm::dvec2 a = p[t[0]], b = p[t[1]], c = p[t[2]];
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

bool inside(std::span<const glm::dvec2> p, const Tri& t, const glm::dvec2& q) {
  const int o = detail::orient2d(p[t[0]], p[t[1]], p[t[2]]);
  return detail::orient2d(p[t[0]], p[t[1]], q) * o > 0 &&
         detail::orient2d(p[t[1]], p[t[2]], q) * o > 0 &&
         detail::orient2d(p[t[2]], p[t[0]], q) * o > 0;
}

// A square ring: the outer square counter-clockwise, a zero-width bridge to the inner
// square, around it clockwise, and back along the bridge (its two vertices appear twice).
std::vector<glm::dvec2> squareKeyhole() {
  return {{0, 0}, {10, 0}, {10, 10}, {5, 10}, {5, 7},  {7, 7},
          {7, 3}, {3, 3},  {3, 7},   {5, 7},  {5, 10}, {0, 10}};
}

TEST(Triangulate, LiteralKeyholeCoversTheRingAndLeavesTheHole) {
  const std::vector<glm::dvec2> p = squareKeyhole();
  std::vector<Tri> tris;
  detail::triangulate2d(p, tris);
  double sum = 0.0;
  for (const Tri& t : tris) {
    EXPECT_GT(triangleArea2(p, t), 0.0) << "every triangle keeps the polygon's winding";
    EXPECT_FALSE(inside(p, t, {5, 5})) << "a triangle covers the hole";
    sum += triangleArea2(p, t);
  }
  EXPECT_EQ(sum, area2(p));  // 2 * (100 - 16)
  EXPECT_EQ(sum, 168.0);
}

TEST(Triangulate, KeyholeModelsFromAssimpTestModelsAreRingsNotDiscs) {
  for (const char* file : {"OBJ/concave_polygon.obj", "Collada/ConcavePolygon.dae"}) {
    SCOPED_TRACE(file);
    const Scene scene = loadScene((std::filesystem::path(HSR_TEST_MODELS) / file).string());
    ASSERT_EQ(scene.polygonCount(), 1u);
    const std::span<const std::uint32_t> poly = scene.polygon(0);
    EXPECT_EQ(poly.size(), 66u);
    // The polygon lies in a plane x = const: its (y, z) coordinates as 2D points.
    std::vector<glm::dvec2> p;
    glm::dvec2 lo(1e30), hi(-1e30);
    for (std::uint32_t v : poly) {
      p.emplace_back(scene.position(v).y, scene.position(v).z);
      lo = glm::min(lo, p.back());
      hi = glm::max(hi, p.back());
    }
    std::vector<detail::Triangle> tris;
    detail::triangulatePolygon(scene, 0, tris);
    double sum = 0.0;
    const glm::dvec2 centre = (lo + hi) * 0.5;  // the middle of the hole
    for (const detail::Triangle& t : tris) {
      Tri local{};
      for (int k = 0; k < 3; ++k)
        local[k] =
            static_cast<std::uint32_t>(std::find(poly.begin(), poly.end(), t.v[k]) - poly.begin());
      sum += std::abs(triangleArea2(p, local));
      EXPECT_FALSE(inside(p, local, centre)) << "a triangle fills the hole";
    }
    EXPECT_NEAR(sum, std::abs(area2(p)), 1e-9 * std::abs(area2(p)));
    // And as a picture: the hole's centre shows the background, the ring is drawn.
    const Camera cam = frameScene(scene, 200, 200);
    const Frame f = render(scene, cam, {});
    const std::size_t middle = static_cast<std::size_t>(100) * 200 + 100;
    EXPECT_EQ(f.ids[middle], kNoPolygon) << "the hole is filled";
    std::size_t drawn = 0;
    for (PolygonId id : f.ids) drawn += id == 0;
    EXPECT_GT(drawn, 500u);
  }
}

// Random star-shaped polygons, some with repeated and straight vertices: the triangles cover
// exactly the polygon's area, each keeps its winding, and there are at most n - 2.
TEST(Triangulate, StarShapedPolygonsAreCoveredExactly) {
  testing::Rng rng(0x57A2);
  const int cases = 2000 * testing::countScale();
  std::uint64_t triangles = 0;
  for (int c = 0; c < cases; ++c) {
    const int n = 4 + static_cast<int>(rng.next() % 60);
    std::vector<glm::dvec2> p;
    for (int k = 0; k < n; ++k) {
      const double angle = 2.0 * 3.14159265358979 * (k + 0.5 * rng.uniform()) / n;
      // Integer coordinates keep the areas exact in double.
      const double r = 10 + std::floor(90 * rng.uniform());
      p.emplace_back(std::round(r * std::cos(angle)), std::round(r * std::sin(angle)));
      if (rng.uniform() < 0.05f) p.push_back(p.back());  // a repeated vertex
    }
    if (rng.next() % 2) std::reverse(p.begin(), p.end());
    const double want = area2(p);
    std::vector<Tri> tris;
    detail::triangulate2d(p, tris);
    EXPECT_LE(tris.size(), p.size() - 2);
    double sum = 0.0;
    for (const Tri& t : tris) {
      const double a = triangleArea2(p, t);
      EXPECT_TRUE(want >= 0 ? a > 0 : a < 0) << "case " << c << ": a triangle flipped";
      sum += a;
    }
    EXPECT_EQ(sum, want) << "case " << c;
    triangles += tris.size();
  }
  testing::printFigures("triangulation: " + testing::grouped(cases) + " star-shaped polygons, " +
                        testing::grouped(triangles) + " triangles, areas exact");
}

// Polygons of 32,767 vertices (an OBJ face holds that many): a circle whose float vertices make
// thousands of tiny reflex turns, and a star of 16,384 spikes. Ear clipping that scans every
// vertex for every corner needs n^2/2 (5e8) tests and seconds; here the work stays within 256
// tests a vertex (measured: 63 for the circle, 128 for the star), and the triangles cover the
// area exactly.
TEST(Triangulate, HugePolygonsCostAboutLinearWork) {
  constexpr int n = 32767;
  for (const bool star : {false, true}) {
    std::vector<glm::dvec2> p;
    for (int k = 0; k < n; ++k) {
      const double angle = 2.0 * 3.14159265358979 * k / n;
      const double r = star && k % 2 ? 0.5 : 1.0;
      // Float coordinates, as a model file gives them
      p.emplace_back(static_cast<float>(r * std::cos(angle)),
                     static_cast<float>(r * std::sin(angle)));
    }
    std::vector<Tri> tris;
    std::uint64_t tests = 0;
    detail::triangulate2d(p, tris, &tests);
    double sum = 0.0;
    for (const Tri& t : tris) sum += triangleArea2(p, t);
    EXPECT_NEAR(sum, area2(p), 1e-9 * area2(p)) << (star ? "star" : "circle");
    EXPECT_LE(tris.size(), static_cast<std::size_t>(n - 2));
    EXPECT_LT(tests, 256ull * n) << (star ? "star" : "circle");
    testing::printFigures(std::string("triangulation of a ") + (star ? "star" : "circle") +
                          " of 32,767 vertices: " + testing::grouped(tests) +
                          " vertex tests (n^2/2 = 536,821,144)");
  }
}

}  // namespace
}  // namespace hsr
