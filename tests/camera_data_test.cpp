// The camera and the depth in scene units, for data users (hsr/camera.hpp Intrinsics,
// hsr/io.hpp depthAs, cameraJson): a point lands where the intrinsics say, and depth.npy's
// linear depth and ray distance are the scene's own lengths.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <tuple>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"

namespace hsr {
namespace {

// Where the pipeline puts a world point: clip space, then the window (pixel centres at
// integers, y down).
glm::dvec2 pixelOf(const Camera& c, const glm::vec3& p) {
  const glm::dvec4 clip = glm::dmat4(c.projection()) * glm::dmat4(c.view()) * glm::dvec4(p, 1.0);
  return {(clip.x / clip.w + 1.0) / 2.0 * c.width - 0.5,
          (1.0 - clip.y / clip.w) / 2.0 * c.height - 0.5};
}

TEST(CameraData, APointLandsWhereTheIntrinsicsSay) {
  const Scene scene = makeBuiltinScene("spheres:1000");
  for (const auto& [w, h, fov] : {std::tuple{640, 480, 45.0f}, std::tuple{800, 300, 60.0f},
                                  std::tuple{301, 227, 20.0f}}) {
    Camera c = frameScene(scene, w, h);
    c.fov_deg = fov;
    const Intrinsics k = intrinsicsOf(c);
    EXPECT_DOUBLE_EQ(k.cx, w / 2.0 - 0.5);
    EXPECT_DOUBLE_EQ(k.cy, h / 2.0 - 0.5);
    const glm::dmat4 view(c.view());
    for (std::uint32_t v = 0; v < scene.vertexCount(); v += 97) {
      const glm::vec3 p = scene.position(v);
      const glm::dvec4 e = view * glm::dvec4(p, 1.0);
      // OpenCV's camera frame: x right, y down, z forward
      const double x = e.x, y = -e.y, z = -e.z;
      ASSERT_GT(z, 0.0);
      const glm::dvec2 expected = pixelOf(c, p);
      EXPECT_NEAR(k.fx * x / z + k.cx, expected.x, 1e-3) << w << "x" << h << " vertex " << v;
      EXPECT_NEAR(k.fy * y / z + k.cy, expected.y, 1e-3) << w << "x" << h << " vertex " << v;
    }
  }
  Camera o = frameScene(scene, 200, 100);
  o.ortho = true;
  EXPECT_EQ(intrinsicsOf(o).fx, 0.0);
}

// A square facing the eye at distance 5: linear depth 5 on every drawn pixel, the ray distance
// the length from the eye to where the pixel's ray meets the square, inf elsewhere.
TEST(CameraData, DepthInSceneUnitsIsTheSceneLength) {
  Scene s;
  s.beginObject("square");
  const std::uint32_t m = s.addMaterial({});
  s.addPolygonVertices({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, m);
  for (const bool ortho : {false, true}) {
    Camera c;
    c.eye = {0, 0, 5};
    c.target = {0, 0, 0};
    c.near = 0.5f, c.far = 50.0f, c.width = 160, c.height = 120, c.ortho = ortho;
    c.ortho_half_height = 1.5f;
    const Frame f = render(s, c);
    const std::vector<float> linear = depthAs(f, c, DepthKind::kLinear);
    const std::vector<float> distance = depthAs(f, c, DepthKind::kDistance);
    EXPECT_EQ(depthAs(f, c, DepthKind::kWindow), f.depth);
    const glm::dmat4 p(c.projection());
    int drawn = 0;
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width; ++x) {
        const std::size_t k = static_cast<std::size_t>(y) * c.width + x;
        if (f.ids[k] == kNoPolygon) {
          EXPECT_TRUE(std::isinf(linear[k]) && std::isinf(distance[k]));
          continue;
        }
        ++drawn;
        // Float window z bounds the precision: 2^-24 of [0, 1], times far / near-ish
        EXPECT_NEAR(linear[k], 5.0, 5e-4) << (ortho ? "ortho" : "perspective") << " " << x << "," << y;
        double expected = 5.0;
        if (!ortho) {
          const double u = (2.0 * (x + 0.5) / c.width - 1.0) / p[0][0];
          const double v = (1.0 - 2.0 * (y + 0.5) / c.height) / p[1][1];
          expected = glm::length(glm::dvec3(5.0 * u, 5.0 * v, 5.0));
        }
        EXPECT_NEAR(distance[k], expected, 5e-4) << x << "," << y;
      }
    EXPECT_GT(drawn, 1000);
  }
  EXPECT_EQ(depthKindNamed("distance"), DepthKind::kDistance);
  EXPECT_THROW(depthKindNamed("meters"), Error);
}

TEST(CameraData, CameraJsonHoldsTheMatricesAndIntrinsics) {
  Camera c;
  c.width = 640, c.height = 480;
  const nlohmann::json j = nlohmann::json::parse(cameraJson(c));
  EXPECT_EQ(j.at("projection_kind"), "perspective");
  EXPECT_EQ(j.at("width"), 640);
  const glm::mat4 proj = c.projection();
  for (int r = 0; r < 4; ++r)
    for (int col = 0; col < 4; ++col)
      EXPECT_FLOAT_EQ(j.at("projection").at(r).at(col).get<float>(), proj[col][r]);
  EXPECT_DOUBLE_EQ(j.at("intrinsics").at("fx").get<double>(), intrinsicsOf(c).fx);
  c.ortho = true;
  EXPECT_TRUE(nlohmann::json::parse(cameraJson(c)).at("intrinsics").is_null());
}

}  // namespace
}  // namespace hsr
