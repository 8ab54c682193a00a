// Shading: one light direction per view (a headlight along the view axis) and one shading
// function for every path, so that a flat face has one colour however it was cut into
// triangles, clipped or not. Pinned by the box models of assimp-testmodels whose square faces
// are two triangles each (a diagonal seam showed on every one of them).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>

#include <glm/geometric.hpp>

#include "cross/figures.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

// The colour each visible polygon was drawn with (flat shading: one per polygon; a polygon
// drawn in two colours fails here).
std::map<PolygonId, std::uint32_t> colourOfEachPolygon(const Frame& f) {
  std::map<PolygonId, std::uint32_t> colour;
  for (std::size_t k = 0; k < f.ids.size(); ++k) {
    if (f.ids[k] == kNoPolygon) continue;
    const auto [it, fresh] = colour.try_emplace(f.ids[k], f.color[k]);
    EXPECT_EQ(it->second, f.color[k]) << "polygon " << f.ids[k] << " has two colours";
  }
  return colour;
}

glm::dvec4 planeOf(const Scene& s, PolygonId id) {
  const auto p = s.polygon(id);
  const glm::dvec3 a(s.position(p[0])), b(s.position(p[1])), c(s.position(p[2]));
  const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
  return {n, -glm::dot(n, a)};
}

// Every two visible polygons in one plane, facing the same way, have the same colour.
void expectCoplanarPolygonsShareAColour(const Scene& scene, const Frame& f, int* pairs) {
  const std::map<PolygonId, std::uint32_t> colour = colourOfEachPolygon(f);
  for (auto i = colour.begin(); i != colour.end(); ++i)
    for (auto j = std::next(i); j != colour.end(); ++j) {
      const glm::dvec4 a = planeOf(scene, i->first), b = planeOf(scene, j->first);
      if (glm::dot(glm::dvec3(a), glm::dvec3(b)) < 1.0 - 1e-9 || std::abs(a.w - b.w) > 1e-6)
        continue;
      ++*pairs;
      EXPECT_EQ(i->second, j->second)
          << "coplanar polygons " << i->first << " and " << j->first << " differ in colour: a seam";
    }
}

TEST(Shading, SquareFacesOfBoxModelsShowNoSeam) {
  int pairs = 0;
  for (const char* model :
       {"glTF2/BoxTextured-glTF/BoxTextured.gltf", "Collada/cube_triangulate.dae",
        "3DS/cube_with_specular_texture.3DS", "OFF/Cube.off"}) {
    SCOPED_TRACE(model);
    const Scene scene = loadScene((std::filesystem::path(HSR_TEST_MODELS) / model).string());
    const Camera cam = frameScene(scene, 240, 240);
    expectCoplanarPolygonsShareAColour(scene, render(scene, cam, {}), &pairs);
  }
  // An STL-style box: 12 triangles with unshared vertices, in a close perspective view.
  Scene box;
  const std::uint32_t m = box.addMaterial({{0.7f, 0.5f, 0.3f}, 1.0f});
  const glm::vec3 c[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                          {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                           {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  for (const auto& q : quads) {
    box.addPolygonVertices({c[q[0]], c[q[1]], c[q[2]]}, m);
    box.addPolygonVertices({c[q[0]], c[q[2]], c[q[3]]}, m);
  }
  Camera cam = frameScene(box, 240, 240);
  cam.eye = {2.2f, 1.7f, 2.9f};  // close: the eye-to-vertex directions differ a lot
  expectCoplanarPolygonsShareAColour(box, render(box, cam, {}), &pairs);
  EXPECT_GE(pairs, 12) << "the visible faces should each show both triangles";
}

// The same triangle shades the same whether the pipeline takes its fast path (wholly inside
// the view) or clips it at the near plane: 1,000 random materials and orientations.
TEST(Shading, ClippedAndUnclippedTrianglesShadeTheSame) {
  testing::Rng rng(0x5ADE);
  Scene s;
  for (int i = 0; i < 1000; ++i) {
    const std::uint32_t m = s.addMaterial({{rng.uniform(), rng.uniform(), rng.uniform()}, 1.0f});
    // Triangles around the view axis from z = -0.5 to z = -3 (the eye at the origin looks
    // down -z), each tilted at random, spread over a 40 x 25 grid.
    const float x = -2.0f + 0.1f * static_cast<float>(i % 40),
                y = -1.2f + 0.1f * static_cast<float>(i / 40);
    const glm::vec3 base(x * 1.5f, y * 1.5f, -1.75f);
    const glm::vec3 d1(0.12f, rng.uniform(-0.05f, 0.05f), rng.uniform(-1.2f, 1.2f));
    const glm::vec3 d2(rng.uniform(-0.05f, 0.05f), 0.12f, rng.uniform(-1.2f, 1.2f));
    s.addPolygonVertices({base - d1 - d2, base + d1, base + d2}, m);
  }
  Camera far_near;
  far_near.eye = {0, 0, 0};
  far_near.target = {0, 0, -1};
  far_near.width = 800;
  far_near.height = 500;
  far_near.fov_deg = 100;
  far_near.near = 0.05f;  // nothing clipped
  far_near.far = 10.0f;
  Camera cutting = far_near;
  cutting.near = 1.75f;  // cuts through every triangle
  const Frame whole = render(s, far_near, {});
  const Frame cut = render(s, cutting, {});
  std::uint64_t compared = 0;
  for (std::size_t k = 0; k < whole.ids.size(); ++k) {
    if (whole.ids[k] == kNoPolygon || whole.ids[k] != cut.ids[k]) continue;
    ASSERT_EQ(whole.color[k], cut.color[k]) << "polygon " << whole.ids[k];
    ++compared;
  }
  EXPECT_GT(cut.stats.clipped, 900u);
  EXPECT_GT(compared, 10000u);
  testing::printFigures("shading: " + testing::grouped(compared) +
                        " pixels of 1,000 triangles, clipped and unclipped, one colour each");
}

}  // namespace
}  // namespace hsr
