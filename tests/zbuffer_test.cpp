// The z-buffer: depth test and its state, incremental depth, modes, determinism.

#include <gtest/gtest.h>

#include <cmath>

#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using testing::pixelCamera;
using testing::Rng;

// Two overlapping axis-aligned squares at different depths (world z; the pixel camera looks
// down -z from z = 10, so larger z is nearer).
Scene twoSquares(bool near_first) {
  Scene s;
  const std::uint32_t red = s.addMaterial({{1, 0, 0}, 1});
  const std::uint32_t blue = s.addMaterial({{0, 0, 1}, 1});
  auto square = [&](float x, float y, float z, std::uint32_t m) {
    s.addPolygonVertices({{x, y, z}, {x + 20, y, z}, {x + 20, y + 20, z}, {x, y + 20, z}}, m);
  };
  if (near_first) {
    square(4, 4, 2.0f, red);    // id 0: near
    square(14, 14, -2.0f, blue);  // id 1: far
  } else {
    square(14, 14, -2.0f, blue);  // id 0: far
    square(4, 4, 2.0f, red);      // id 1: near
  }
  return s;
}

PolygonId idAt(const Frame& f, int x, int y_up) {
  return f.ids[static_cast<std::size_t>(f.height - 1 - y_up) * f.width + x];
}

TEST(ZBuffer, NearestSurfaceWinsInAnyDrawingOrder) {
  const Camera cam = pixelCamera(40, 40);
  const Frame a = render(twoSquares(true), cam, {});
  const Frame b = render(twoSquares(false), cam, {});
  // The overlap [14,24) is covered by the near square in both orders.
  EXPECT_EQ(idAt(a, 18, 18), 0u);
  EXPECT_EQ(idAt(b, 18, 18), 1u);
  EXPECT_EQ(idAt(a, 30, 30), 1u);
  EXPECT_EQ(idAt(b, 30, 30), 0u);
  EXPECT_EQ(idAt(a, 2, 2), kNoPolygon);
}

TEST(ZBuffer, WithoutDepthTestTheLastDrawnWins) {
  const Camera cam = pixelCamera(40, 40);
  RenderOptions o;
  o.depth_test = false;
  const Frame a = render(twoSquares(true), cam, o);
  EXPECT_EQ(idAt(a, 18, 18), 1u);  // the far square, drawn last, overwrites: wrong order
  // GL: no depth writes while the test is disabled.
  for (float d : a.depth) EXPECT_EQ(d, 1.0f);
  EXPECT_EQ(a.overdraw[static_cast<std::size_t>(40 - 1 - 18) * 40 + 18], 2u);
}

TEST(ZBuffer, DepthFuncGreaterKeepsTheFarthest) {
  const Camera cam = pixelCamera(40, 40);
  RenderOptions o;
  o.depth_func = DepthFunc::Greater;
  o.clear_depth = 0.0f;
  const Frame a = render(twoSquares(true), cam, o);
  EXPECT_EQ(idAt(a, 18, 18), 1u);
}

TEST(ZBuffer, DepthMaskOffLeavesDepthCleared) {
  const Camera cam = pixelCamera(40, 40);
  RenderOptions o;
  o.depth_mask = false;
  const Frame a = render(twoSquares(true), cam, o);
  for (float d : a.depth) EXPECT_EQ(d, 1.0f);
  EXPECT_EQ(idAt(a, 18, 18), 1u);  // nothing stored, so the later far square passes too
}

// Incremental depth along spans equals the plane evaluated directly at each pixel centre.
TEST(ZBuffer, IncrementalDepthMatchesThePlane) {
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  s.addPolygonVertices({{1, 1, -3}, {250, 30, 4}, {40, 200, 0}}, m);
  const Camera cam = pixelCamera(256, 256);
  const Frame f = render(s, cam, {});
  // Window depth of world z under the pixel camera: eye z 10, near 1, far 20, ortho:
  // z_ndc = (-2*(10 - z) + 21) / 19 ... computed through the camera's own matrix instead.
  const glm::mat4 mvp = cam.projection() * cam.view();
  auto windowZ = [&](glm::vec3 p) { return (mvp * glm::vec4(p, 1)).z * 0.5f + 0.5f; };
  const glm::vec3 a(1, 1, -3), b(250, 30, 4), c(40, 200, 0);
  int checked = 0;
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x) {
      const std::size_t k = static_cast<std::size_t>(255 - y) * 256 + x;
      if (f.ids[k] != 0) continue;
      // Barycentric interpolation at the pixel centre (x+0.5, y+0.5) in double.
      const double px = x + 0.5, py = y + 0.5;
      const double d = (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
      const double l0 = ((b.y - c.y) * (px - c.x) + (c.x - b.x) * (py - c.y)) / d;
      const double l1 = ((c.y - a.y) * (px - c.x) + (a.x - c.x) * (py - c.y)) / d;
      const double z = l0 * windowZ(a) + l1 * windowZ(b) + (1 - l0 - l1) * windowZ(c);
      ASSERT_NEAR(f.depth[k], z, 2e-5) << "pixel " << x << "," << y;
      checked++;
    }
  EXPECT_GT(checked, 15000);
}

TEST(ZBuffer, LineModeDrawsOnlyEdges) {
  Scene s;
  s.addPolygonVertices({{8.5f, 8.5f, 0}, {56.5f, 8.5f, 0}, {56.5f, 56.5f, 0}, {8.5f, 56.5f, 0}}, s.addMaterial({}));
  const Camera cam = pixelCamera(64, 64);
  RenderOptions o;
  o.polygon_mode = PolygonMode::Line;
  const Frame f = render(s, cam, o);
  EXPECT_EQ(idAt(f, 32, 32), kNoPolygon);  // interior empty
  EXPECT_EQ(idAt(f, 32, 8), 0u);           // bottom edge
  EXPECT_EQ(idAt(f, 8, 32), 0u);           // left edge
  o.polygon_mode = PolygonMode::Point;
  const Frame p = render(s, cam, o);
  std::size_t drawn = 0;
  for (PolygonId id : p.ids) drawn += id == 0;
  EXPECT_EQ(drawn, 4u);  // the four corners
}

TEST(ZBuffer, OutlineDarkensSilhouetteOnly) {
  Scene s;
  const std::uint32_t m = s.addMaterial({{1, 1, 1}, 1});
  s.addPolygonVertices({{8.5f, 8.5f, 0}, {56.5f, 8.5f, 0}, {56.5f, 56.5f, 0}, {8.5f, 56.5f, 0}}, m);
  const Camera cam = pixelCamera(64, 64);
  RenderOptions o;
  o.outline = true;
  const Frame f = render(s, cam, o);
  auto red = [&](int x, int y) {
    return hsr::testing::channel(f, static_cast<std::size_t>(63 - y) * 64 + x, 0);
  };
  EXPECT_EQ(red(32, 8), 0);    // border edge of an open surface is a silhouette
  EXPECT_GT(red(32, 32), 100);  // interior keeps its shade
}

TEST(ZBuffer, BitIdenticalAtAnyThreadCount) {
  Rng rng(99);
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  for (int i = 0; i < 3000; ++i) {
    const glm::vec3 c(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3));
    s.addPolygonVertices({c, c + glm::vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), 0.3f),
                          c + glm::vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), -0.3f)}, m);
  }
  const Camera cam = frameBounds(s.bounds(), 333, 257);
  RenderOptions o;
  o.threads = 1;
  const Frame a = render(s, cam, o);
  o.threads = 2;
  const Frame b = render(s, cam, o);
  o.threads = 7;
  const Frame c = render(s, cam, o);
  EXPECT_EQ(a.ids, b.ids);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.color, b.color);
  EXPECT_EQ(a.overdraw, c.overdraw);
  EXPECT_EQ(a.ids, c.ids);
}

TEST(ZBuffer, CoplanarTieFirstSubmittedWinsWithLess) {
  // Documented tie rule: with LESS, of two coplanar overlapping polygons the first drawn stays.
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  s.addPolygonVertices({{4, 4, 1}, {40, 4, 1}, {4, 40, 1}}, m);
  s.addPolygonVertices({{4, 4, 1}, {40, 4, 1}, {4, 40, 1}}, m);
  const Frame f = render(s, pixelCamera(48, 48), {});
  for (PolygonId id : f.ids) EXPECT_TRUE(id == kNoPolygon || id == 0u);
}

TEST(ZBuffer, TransparentPolygonBlendsWithoutHidingWhatIsBehind) {
  Scene s;
  const std::uint32_t opaque = s.addMaterial({{1, 0, 0}, 1});
  const std::uint32_t glass = s.addMaterial({{0, 0, 1}, 0.5f});
  s.addPolygonVertices({{4, 4, 3}, {40, 4, 3}, {40, 40, 3}, {4, 40, 3}}, glass);  // near, first
  s.addPolygonVertices({{4, 4, 0}, {40, 4, 0}, {40, 40, 0}, {4, 40, 0}}, opaque);  // behind
  RenderOptions o;
  o.shade = false;
  const Frame f = render(s, pixelCamera(48, 48), o);
  const std::size_t k = static_cast<std::size_t>(47 - 20) * 48 + 20;
  EXPECT_EQ(f.ids[k], 1u);  // the opaque polygon is the visible surface
  EXPECT_NEAR(testing::channel(f, k, 0), 128, 1);  // half red ...
  EXPECT_NEAR(testing::channel(f, k, 2), 128, 1);  // ... half blue
}

}  // namespace
}  // namespace hsr
