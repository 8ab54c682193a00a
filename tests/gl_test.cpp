// The GL-style facade replays the notes' snippets.

#include <gtest/gtest.h>

#include <set>

#include "hsr/gl.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

// A unit cube, CCW outward, centred at c with half-size h.
void addCube(Scene& s, glm::vec3 c, float h, std::uint32_t m) {
  s.beginObject("cube");
  for (int i = 0; i < 8; ++i)
    s.addVertex(c + h * glm::vec3((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1));
  const std::uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) s.addPolygon({f[0], f[1], f[2], f[3]}, m);
}

Camera cubeCamera() {
  Camera c;
  c.eye = {3, 2.5f, 4};
  c.target = {0, 0, 0};
  c.width = 96;
  c.height = 96;
  c.near = 1;
  c.far = 20;
  return c;
}

std::set<PolygonId> visibleIds(const Frame& f) {
  std::set<PolygonId> s;
  for (PolygonId id : f.ids)
    if (id != kNoPolygon) s.insert(id);
  return s;
}

// glEnable(GL_DEPTH_TEST); glClear(...); DrawScene(): a convex cube shows its 3 front faces.
TEST(GlFacade, DepthTestShowsFrontFacesOfCube) {
  Scene s;
  addCube(s, {0, 0, 0}, 1, s.addMaterial({}));
  gl::Context ctx(cubeCamera());
  ctx.enable(gl::DEPTH_TEST);
  ctx.depthMask(true);
  ctx.clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
  ctx.draw(s);
  // Eye at (+x, +y, +z): faces +x (5), +y (3), +z (1) are visible.
  EXPECT_EQ(visibleIds(ctx.frame()), (std::set<PolygonId>{1, 3, 5}));
}

// Without the depth test the last drawn face wins: the back faces show through.
TEST(GlFacade, WithoutDepthTestDrawingOrderDecides) {
  Scene s;
  addCube(s, {0, 0, 0}, 1, s.addMaterial({}));
  gl::Context ctx(cubeCamera());
  ctx.clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
  ctx.draw(s);
  EXPECT_NE(visibleIds(ctx.frame()), (std::set<PolygonId>{1, 3, 5}));
}

// glEnable(GL_CULL_FACE); glCullFace(GL_BACK): back-face culling alone solves a convex cube,
// even without the depth test (the notes' "for a single convex polyhedron").
TEST(GlFacade, CullBackAloneSolvesConvexCube) {
  Scene s;
  addCube(s, {0, 0, 0}, 1, s.addMaterial({}));
  gl::Context ctx(cubeCamera());
  ctx.enable(gl::CULL_FACE);
  ctx.cullFace(gl::BACK);
  ctx.clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
  ctx.draw(s);
  EXPECT_EQ(visibleIds(ctx.frame()), (std::set<PolygonId>{1, 3, 5}));
  // glCullFace(GL_FRONT) shows the inside: the three back faces.
  ctx.cullFace(gl::FRONT);
  ctx.enable(gl::DEPTH_TEST);
  ctx.clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
  ctx.draw(s);
  EXPECT_EQ(visibleIds(ctx.frame()), (std::set<PolygonId>{0, 2, 4}));
  // glFrontFace(GL_CW) swaps which side is "front".
  ctx.frontFace(gl::CW);
  ctx.clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
  ctx.draw(s);
  EXPECT_EQ(visibleIds(ctx.frame()), (std::set<PolygonId>{1, 3, 5}));
  ctx.cullFace(gl::FRONT_AND_BACK);
  ctx.clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
  ctx.draw(s);
  EXPECT_TRUE(visibleIds(ctx.frame()).empty());
}

// The depth buffer persists between draws until cleared: a far object drawn in a second call
// stays hidden; after glClear(GL_DEPTH_BUFFER_BIT) alone it is drawn over the old colour.
TEST(GlFacade, DepthPersistsUntilCleared) {
  Scene near_scene, far_scene;
  addCube(near_scene, {0, 0, 0}, 1, near_scene.addMaterial({{1, 0, 0}, 1}));
  addCube(far_scene, {-1.5f, -1.5f, -3}, 1, far_scene.addMaterial({{0, 1, 0}, 1}));
  gl::Context ctx(cubeCamera());
  ctx.enable(gl::DEPTH_TEST);
  ctx.clear(gl::COLOR_BUFFER_BIT | gl::DEPTH_BUFFER_BIT);
  ctx.draw(near_scene);
  const Frame first = ctx.frame();
  ctx.draw(far_scene);
  const std::size_t centre = static_cast<std::size_t>(48) * 96 + 48;
  EXPECT_EQ(ctx.frame().color[centre], first.color[centre]);  // still red in the middle
  ctx.clear(gl::DEPTH_BUFFER_BIT);
  ctx.draw(far_scene);
  std::size_t green_over_red = 0;
  for (std::size_t k = 0; k < first.ids.size(); ++k)
    green_over_red += first.ids[k] != kNoPolygon &&
                      testing::channel(ctx.frame(), k, 1) > testing::channel(ctx.frame(), k, 0);
  EXPECT_GT(green_over_red, 0u);
}

// glDepthMask(GL_FALSE) also masks glClear(GL_DEPTH_BUFFER_BIT), as in OpenGL.
TEST(GlFacade, DepthMaskMasksClear) {
  Scene s;
  addCube(s, {0, 0, 0}, 1, s.addMaterial({}));
  gl::Context ctx(cubeCamera());
  ctx.enable(gl::DEPTH_TEST);
  ctx.draw(s);
  const FrameBuffer<float> depth = ctx.frame().depth;
  ctx.depthMask(false);
  ctx.clear(gl::DEPTH_BUFFER_BIT);
  EXPECT_EQ(ctx.frame().depth, depth);
  ctx.depthMask(true);
  ctx.clear(gl::DEPTH_BUFFER_BIT);
  for (float d : ctx.frame().depth) ASSERT_EQ(d, 1.0f);
}

}  // namespace
}  // namespace hsr
