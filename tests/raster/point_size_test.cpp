// glPointSize for polygon mode POINT (raster/lines.hpp drawPoint): a point of size s covers the
// pixels whose centres lie in the square of side s centred on it, half-open, as OpenGL draws
// points without antialiasing; the tiled z-buffer bins the larger squares and draws the same
// pixels as the textbook one; sizes outside 1..64 are refused.

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <utility>

#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"

namespace hsr {
namespace {

// An orthographic camera at 1 scene unit a pixel: window x = x + 32, window y = y + 24.
Camera pixelCamera() {
  Camera c;
  c.eye = {0, 0, 5}, c.target = {0, 0, 0};
  c.ortho = true, c.ortho_half_height = 24.0f;
  c.width = 64, c.height = 48, c.near = 1, c.far = 10;
  return c;
}

TEST(PointSize, SquaresOfCentresInsideTheSquare) {
  // Vertices at chosen fractions of a pixel, far enough apart that the squares never meet, at
  // coordinates the projection keeps exact (x / 32 and y / 24 are binary fractions), so that
  // squares with edges through pixel centres test the half-open rule itself
  const std::pair<float, float> v[3] = {{-20.25f, -10.5f}, {5.75f, 12.0f}, {18.5f, -3.0f}};
  Scene s;
  s.beginObject("triangle");
  const std::uint32_t m = s.addMaterial({});
  s.addPolygonVertices(
      {{v[0].first, v[0].second, 0}, {v[1].first, v[1].second, 0}, {v[2].first, v[2].second, 0}},
      m);
  const Camera c = pixelCamera();
  for (const float size : {2.0f, 3.0f, 4.0f, 5.0f, 2.5f, 1.5f}) {
    for (const char* algorithm : {"zbuffer", "zbuffer-textbook"}) {
      RenderOptions o;
      o.algorithm = algorithm;
      o.polygon_mode = PolygonMode::Point;
      o.point_size = size;
      const Frame f = render(s, c, o);
      std::set<std::pair<int, int>> expected, drawn;  // (column, row from the top)
      for (const auto& [x, y] : v) {
        const double wx = x + 32.0, wy = y + 24.0;  // window coordinates, pixel i spans [i, i+1)
        for (int i = 0; i < 64; ++i)
          for (int j = 0; j < 48; ++j) {
            const double cx = i + 0.5, cy = j + 0.5;
            const bool in = wx - size / 2 <= cx && cx < wx + size / 2 && wy - size / 2 <= cy &&
                            cy < wy + size / 2;
            if (in) expected.insert({i, 47 - j});
          }
      }
      for (int row = 0; row < 48; ++row)
        for (int col = 0; col < 64; ++col)
          if (f.ids[static_cast<std::size_t>(row) * 64 + col] != kNoPolygon)
            drawn.insert({col, row});
      EXPECT_EQ(drawn, expected) << algorithm << " size " << size;
      const std::size_t side = static_cast<std::size_t>(std::floor(size));
      EXPECT_GE(drawn.size(), 3 * side * side) << algorithm << " size " << size;
    }
  }
}

// The tiled renderer bins each point's square: the same frame as the textbook loop, bit for bit,
// with squares that cross tile edges.
TEST(PointSize, TiledEqualsTextbookForLargePoints) {
  const Scene s = makeBuiltinScene("spheres:3000");
  const Camera c = frameScene(s, 320, 240);
  for (const float size : {2.0f, 7.0f, 33.0f}) {
    RenderOptions o;
    o.polygon_mode = PolygonMode::Point;
    o.point_size = size;
    o.algorithm = "zbuffer";
    const Frame tiled = render(s, c, o);
    o.algorithm = "zbuffer-textbook";
    const Frame textbook = render(s, c, o);
    EXPECT_EQ(tiled.ids, textbook.ids) << size;
    EXPECT_EQ(tiled.depth, textbook.depth) << size;
    EXPECT_EQ(tiled.overdraw, textbook.overdraw) << size;
  }
}

TEST(PointSize, OutsideOneToSixtyFourIsRefused) {
  const Scene s = makeBuiltinScene("demo");
  const Camera c = frameScene(s, 32, 24);
  for (const float size : {0.5f, 0.0f, 65.0f, NAN}) {
    RenderOptions o;
    o.polygon_mode = PolygonMode::Point;
    o.point_size = size;
    EXPECT_THROW(render(s, c, o), Error) << size;
  }
}

}  // namespace
}  // namespace hsr
