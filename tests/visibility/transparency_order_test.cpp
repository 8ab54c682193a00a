// Transparent polygons blended in drawing order: the painter's algorithm (painter.cpp) and the
// BSP tree (bsp.cpp) both paint back to front, each in its own order and with its own splits,
// and must give the same picture: within one colour level per channel on at least 99.9% of
// the pixels, on the demo's glass pane and on random scenes of overlapping, tilted and
// interpenetrating transparent layers over an opaque floor.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>

#include "cross/figures.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

struct ColourAgreement {
  std::uint64_t pixels = 0, within_one = 0, blended = 0;
  int worst = 0;
};

ColourAgreement compareColours(const Scene& scene, const Camera& camera) {
  RenderOptions o;
  o.algorithm = "painter";
  const Frame p = render(scene, camera, o);
  o.algorithm = "bsp";
  const Frame b = render(scene, camera, o);
  ColourAgreement a;
  for (std::size_t k = 0; k < p.color.size(); ++k) {
    int worst = 0;
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(testing::channel(p, k, c) - testing::channel(b, k, c)));
    a.pixels++;
    a.within_one += worst <= 1;
    a.blended += p.overdraw[k] > 1;
    a.worst = std::max(a.worst, worst);
  }
  return a;
}

// Layers: `n` quads of alpha 0.3-0.7 across the view at random depths, tilted up to 40
// degrees (tilted ones cross each other: interpenetration, split by both), over an opaque
// floor quad.
Scene transparentLayers(std::uint64_t seed, int n) {
  testing::Rng rng(seed);
  Scene s;
  const std::uint32_t floor = s.addMaterial({{0.3f, 0.5f, 0.3f}, 1.0f});
  s.addPolygonVertices({{-3, -3, -2}, {3, -3, -2}, {3, 3, -2}, {-3, 3, -2}}, floor);
  for (int i = 0; i < n; ++i) {
    const std::uint32_t m =
        s.addMaterial({{rng.uniform(0.1f, 1.0f), rng.uniform(0.1f, 1.0f), rng.uniform(0.1f, 1.0f)},
                       rng.uniform(0.3f, 0.7f)});
    const float z = rng.uniform(-1.5f, 1.5f), tx = rng.uniform(-0.7f, 0.7f),
                ty = rng.uniform(-0.7f, 0.7f);
    const float x0 = rng.uniform(-2.5f, 0.0f), x1 = rng.uniform(0.5f, 2.5f);
    const float y0 = rng.uniform(-2.5f, 0.0f), y1 = rng.uniform(0.5f, 2.5f);
    auto at = [&](float x, float y) { return glm::vec3(x, y, z + tx * x + ty * y); };
    s.addPolygonVertices({at(x0, y0), at(x1, y0), at(x1, y1), at(x0, y1)}, m);
  }
  return s;
}

TEST(TransparencyOrder, PainterAndBspBlendTheSamePicture) {
  {
    const Scene demo = loadScene("demo");
    const ColourAgreement a = compareColours(demo, frameScene(demo, 320, 240));
    testing::printFigures("demo 320x240 transparent glass: painter vs bsp: " +
                          testing::percent(a.within_one, a.pixels) +
                          " of pixels within one level, worst " + std::to_string(a.worst));
    EXPECT_GE(a.within_one * 1000, a.pixels * 999);
  }
  ColourAgreement total;
  const int scenes = 20 * testing::countScale();
  for (int i = 0; i < scenes; ++i) {
    const std::uint64_t seed = 500 + static_cast<std::uint64_t>(i);
    const Scene scene = transparentLayers(seed, 6);
    Camera camera;
    camera.width = 200, camera.height = 150;
    camera.eye = {0.8f, -1.2f, 9.0f};
    camera.target = {0, 0, 0};
    camera.near = 3.0f, camera.far = 16.0f;
    const ColourAgreement a = compareColours(scene, camera);
    EXPECT_GE(a.within_one * 1000, a.pixels * 999) << "seed " << seed << ": worst " << a.worst;
    EXPECT_GT(a.blended, a.pixels / 10) << "seed " << seed << ": the layers should overlap";
    total.pixels += a.pixels, total.within_one += a.within_one, total.blended += a.blended;
    total.worst = std::max(total.worst, a.worst);
  }
  testing::printFigures(
      std::to_string(scenes) + " scenes of 6 transparent layers: painter vs bsp: " +
      testing::percent(total.within_one, total.pixels) + " of pixels within one level (" +
      testing::grouped(total.blended) + " blended), worst " + std::to_string(total.worst));
}

}  // namespace
}  // namespace hsr
