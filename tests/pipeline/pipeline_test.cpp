// The shared pipeline: facing tests, clipping, culling, degenerate input.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "hsr/error.hpp"
#include "hsr/render.hpp"
#include "pipeline/pipeline.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using testing::Rng;

Scene randomSoup(std::uint64_t seed, int n, float spread) {
  Rng rng(seed);
  Scene s;
  s.beginObject("soup");
  const std::uint32_t m = s.addMaterial({});
  for (int i = 0; i < n; ++i) {
    const glm::vec3 c(rng.uniform(-spread, spread), rng.uniform(-spread, spread),
                      rng.uniform(-spread, spread));
    glm::vec3 v[3];
    for (glm::vec3& p : v)
      p = c + glm::vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    s.addPolygonVertices({v[0], v[1], v[2]}, m);
  }
  return s;
}

// The notes' eye-space test and OpenGL's window-area test must agree on every polygon that
// is not edge-on, in perspective and in parallel projection.
TEST(Pipeline, EyePlaneAndWindowAreaFacingAgree) {
  for (bool ortho : {false, true}) {
    const Scene s = randomSoup(ortho ? 11 : 7, 2000 * testing::countScale(), 3.0f);
    Camera cam = frameBounds(s.bounds(), 320, 240, 50.0f, ortho);
    const glm::mat4 mvp = cam.projection() * cam.view();
    int compared = 0, edge_on = 0;
    for (PolygonId id = 0; id < s.polygonCount(); ++id) {
      const auto poly = s.polygon(id);
      // Window-space orientation from the exact projected vertices (all in front of the eye
      // for this framing), in double, y up.
      double x[3], y[3];
      bool behind = false;
      for (int k = 0; k < 3; ++k) {
        const glm::vec4 c = mvp * glm::vec4(s.position(poly[k]), 1.0f);
        if (c.w <= 0.0f) behind = true;
        x[k] = c.x / c.w;
        y[k] = c.y / c.w;
      }
      if (behind) continue;
      const double area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
      const int eye = detail::eyeSpaceOrientation(s, id, cam);
      // Edge-on: the projected area is tiny relative to the triangle's extent.
      const double scale = std::abs(x[1] - x[0]) + std::abs(x[2] - x[0]) + std::abs(y[1] - y[0]) +
                           std::abs(y[2] - y[0]);
      if (std::abs(area) < 1e-5 * scale * scale) {
        edge_on++;
        continue;
      }
      compared++;
      EXPECT_EQ(area > 0 ? 1 : -1, eye) << "polygon " << id << (ortho ? " ortho" : " persp");
    }
    EXPECT_GT(compared, 1000);
    std::printf("facing agreement (%s): %d polygons compared, %d edge-on skipped\n",
                ortho ? "ortho" : "perspective", compared, edge_on);
  }
}

// Both facing tests cull the same polygons (ids buffers equal) with cull back.
TEST(Pipeline, CullBackSameWithEitherFacingTest) {
  const Scene s = randomSoup(3, 500, 2.0f);
  const Camera cam = frameBounds(s.bounds(), 200, 150);
  RenderOptions a;
  a.cull = CullMode::Back;
  RenderOptions b = a;
  b.facing_test = FacingTest::EyePlane;
  const Frame fa = render(s, cam, a), fb = render(s, cam, b);
  std::size_t diff = 0;
  for (std::size_t i = 0; i < fa.ids.size(); ++i) diff += fa.ids[i] != fb.ids[i];
  EXPECT_LE(diff, fa.ids.size() / 1000) << "ids differ on " << diff << " pixels";
  EXPECT_EQ(fa.stats.culled_backface, fb.stats.culled_backface);
}

// A triangle wholly behind the eye draws nothing (no inverted "ghost"); one crossing the near
// plane draws only its visible part.
TEST(Pipeline, TriangleBehindEyeDrawsNothing) {
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  s.addPolygonVertices({{-5, -5, 10}, {5, -5, 10}, {0, 5, 10}},
                       m);  // behind (eye at z=5, looks -z)
  Camera cam;
  cam.eye = {0, 0, 5};
  cam.target = {0, 0, 0};
  cam.width = 64;
  cam.height = 64;
  const Frame f = render(s, cam, {});
  for (PolygonId id : f.ids) ASSERT_EQ(id, kNoPolygon);
  EXPECT_EQ(f.stats.fragments_tested, 0u);
}

TEST(Pipeline, TriangleThroughNearPlaneIsClippedNotInverted) {
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  // One vertex behind the eye (z = 8 > 5), two in front, large on screen.
  s.addPolygonVertices({{-2, -2, 0}, {2, -2, 0}, {0, 0, 8}}, m);
  Camera cam;
  cam.eye = {0, 0, 5};
  cam.width = 64;
  cam.height = 64;
  const Frame f = render(s, cam, {});
  EXPECT_EQ(f.stats.clipped, 1u);
  std::size_t drawn = 0;
  for (PolygonId id : f.ids) drawn += id == 0;
  EXPECT_GT(drawn, 0u);
  // The visible part lies below the horizon (the vertex behind the eye is at y=0, the
  // others at y=-2): nothing may appear in the top rows.
  for (int x = 0; x < 64; ++x) EXPECT_EQ(f.ids[x], kNoPolygon) << "ghost at column " << x;
  for (float v : f.depth) ASSERT_TRUE(std::isfinite(v));
}

// The pipeline works in chunks of polygons, each writing right after the chunk before it when
// that one is done, else into its own slot of the output, closed up afterwards; or joined from
// vectors of their own where clipping made a chunk overflow the room it had. Either way the
// output must be what each polygon makes alone, in order.
void expectSameAsPolygonByPolygon(const Scene& scene, const Camera& cam, const RenderOptions& o) {
  const detail::PreparedScene whole = detail::prepare(scene, cam, o);
  std::vector<detail::ScreenTriangle> alone;
  for (PolygonId id = 0; id < scene.polygonCount(); ++id) {
    Scene one;
    for (const Material& m : scene.materials) one.addMaterial(m);
    std::vector<glm::vec3> v;
    for (std::uint32_t k : scene.polygon(id)) v.push_back(scene.position(k));
    one.addPolygonVertices(v, scene.material(id));
    for (detail::ScreenTriangle t : detail::prepare(one, cam, o).triangles) {
      t.id = id;
      alone.push_back(t);
    }
  }
  ASSERT_EQ(whole.triangles.size(), alone.size());
  for (std::size_t i = 0; i < alone.size(); ++i)
    ASSERT_EQ(std::memcmp(&whole.triangles[i], &alone[i], sizeof alone[i]), 0) << "triangle " << i;
}

TEST(Pipeline, ChunksJoinAsPolygonByPolygon) {
  // Large triangles around an eye inside the soup: most are clipped, many into several
  // triangles, so the output outgrows the input (some chunk overflowed its slot).
  const Camera inside = testing::cameraAtOrigin(160, 120);
  Scene clipped;
  {
    Rng rng(11);
    const std::uint32_t m = clipped.addMaterial({});
    for (int i = 0; i < 5000; ++i) {
      const glm::vec3 c(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-6, -2));
      glm::vec3 v[3];
      for (glm::vec3& q : v)
        q = c + glm::vec3(rng.uniform(-8, 8), rng.uniform(-8, 8), rng.uniform(-1, 1));
      clipped.addPolygonVertices({v[0], v[1], v[2]}, m);
    }
  }
  const detail::PreparedScene p = detail::prepare(clipped, inside, {});
  ASSERT_GT(p.triangles.size(), clipped.polygonCount());
  expectSameAsPolygonByPolygon(clipped, inside, {});
  // Seen from outside with back faces culled: triangles are only dropped, and the chunks'
  // slots are closed up in place.
  Camera outside;
  outside.eye = {0, 0, 40};
  outside.width = 160;
  outside.height = 120;
  RenderOptions cull;
  cull.cull = CullMode::Back;
  const detail::PreparedScene q = detail::prepare(clipped, outside, cull);
  ASSERT_GT(q.stats.culled_backface, 1000u);
  ASSERT_LT(q.triangles.size(), clipped.polygonCount());
  expectSameAsPolygonByPolygon(clipped, outside, cull);
}

TEST(Pipeline, ChunksThatFollowOnUseTheRoomLeftBeforeThem) {
  // Chunks of 2048 polygons in turn wholly behind the eye (they make nothing) and clipped
  // around it (they make more triangles than they have polygons): a chunk that follows on
  // writes into the room its predecessor left; at any thread count the output is the same.
  const Camera inside = testing::cameraAtOrigin(96, 64);
  Scene s;
  Rng rng(5);
  const std::uint32_t m = s.addMaterial({});
  for (int chunk = 0; chunk < 6; ++chunk)
    for (int i = 0; i < 2048; ++i) {
      const bool behind = chunk % 2 == 0;
      const glm::vec3 c(rng.uniform(-1, 1), rng.uniform(-1, 1),
                        behind ? rng.uniform(3, 6) : rng.uniform(-6, -2));
      const float r = behind ? 0.5f : 8.0f;
      glm::vec3 v[3];
      for (glm::vec3& q : v)
        q = c + glm::vec3(rng.uniform(-r, r), rng.uniform(-r, r), rng.uniform(-1, 1));
      s.addPolygonVertices({v[0], v[1], v[2]}, m);
    }
  const detail::PreparedScene p = detail::prepare(s, inside, {});
  ASSERT_GT(p.stats.clipped_away, 5000u);
  ASSERT_GT(p.triangles.size(), s.polygonCount() / 2 + 1000);
  expectSameAsPolygonByPolygon(s, inside, {});
  for (const int threads : {1, 2, 5}) {
    RenderOptions o;
    o.threads = threads;
    Frame a = render(s, inside, o);
    o.threads = 1;
    Frame b = render(s, inside, o);
    EXPECT_EQ(a.ids, b.ids) << threads << " threads";
    EXPECT_EQ(a.stats.triangles_rasterized, p.stats.triangles_rasterized);
  }
}

TEST(Pipeline, DegeneratePolygonsAreDroppedAndCounted) {
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  const float nan = std::nanf("");
  s.addPolygonVertices({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}, m);         // collinear
  s.addPolygonVertices({{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, m);         // repeated
  s.addPolygonVertices({{0, 0, 0}, {nan, 0, 0}, {0, 1, 0}}, m);       // NaN
  s.addPolygonVertices({{0, 0, 0}, {INFINITY, 0, 0}, {0, 1, 0}}, m);  // Inf
  s.addPolygonVertices({{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}}, m);      // fine
  Camera cam;
  cam.width = 32;
  cam.height = 32;
  const Frame f = render(s, cam, {});
  EXPECT_EQ(f.stats.degenerate_dropped, 4u);
  for (PolygonId id : f.ids) EXPECT_TRUE(id == kNoPolygon || id == 4u);
}

TEST(Pipeline, FrustumCullingSkipsObjectsOutsideTheView) {
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  s.beginObject("visible");
  s.addPolygonVertices({{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}}, m);
  s.beginObject("behind");
  s.addPolygonVertices({{-1, -1, 20}, {1, -1, 20}, {0, 1, 20}}, m);
  s.beginObject("left");
  s.addPolygonVertices({{-100, -1, 0}, {-98, -1, 0}, {-99, 1, 0}}, m);
  Camera cam;
  cam.width = 32;
  cam.height = 32;
  const Frame f = render(s, cam, {});
  EXPECT_EQ(f.stats.culled_frustum, 2u);
  RenderOptions no_cull;
  no_cull.frustum_cull = false;
  const Frame g = render(s, cam, no_cull);
  EXPECT_EQ(g.stats.culled_frustum, 0u);
  EXPECT_EQ(f.ids, g.ids);  // culling by bounds never changes the picture
}

TEST(Pipeline, BadCameraIsRefused) {
  Scene s;
  s.addPolygonVertices({{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}}, s.addMaterial({}));
  Camera c;
  c.near = 0.0f;
  EXPECT_THROW(render(s, c, {}), Error);
  c = Camera{};
  c.far = c.near;
  EXPECT_THROW(render(s, c, {}), Error);
  c = Camera{};
  c.eye = {NAN, 0, 0};
  EXPECT_THROW(render(s, c, {}), Error);
  c = Camera{};
  c.width = 100000;
  c.height = 100000;
  try {
    render(s, c, {});
    FAIL() << "100000x100000 was attempted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("GiB"), std::string::npos) << e.what();
  }
  c = Camera{};
  c.width = 0;
  EXPECT_THROW(render(s, c, {}), Error);
  c = Camera{};
  c.up = glm::vec3(0, 0, 1);  // parallel to the view direction
  EXPECT_THROW(render(s, c, {}), Error);
}

}  // namespace
}  // namespace hsr
