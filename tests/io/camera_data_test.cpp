// The camera and the depth in scene units, for data users (hsr/camera.hpp Intrinsics,
// hsr/io.hpp depthAs, cameraJson): a point lands where the intrinsics say, and depth.npy's
// linear depth and ray distance are the scene's own lengths.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/core.h>
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
  for (const auto& [w, h, fov] :
       {std::tuple{640, 480, 45.0f}, std::tuple{800, 300, 60.0f}, std::tuple{301, 227, 20.0f}}) {
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
    const FrameBuffer<float> linear = depthAs(f, c, DepthKind::kLinear);
    const FrameBuffer<float> distance = depthAs(f, c, DepthKind::kDistance);
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
        EXPECT_NEAR(linear[k], 5.0, 5e-4)
            << (ortho ? "ortho" : "perspective") << " " << x << "," << y;
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

// Calibrated input: with fx != fy and an off-centre principal point, every vertex lands at
// fx X / Z + cx, fy Y / Z + cy, and a small square drawn around a point covers that pixel.
TEST(CameraData, GivenIntrinsicsPutAPointAtThatPixel) {
  const Scene scene = makeBuiltinScene("spheres:1000");
  Camera c = frameScene(scene, 640, 480);
  c.intrinsics = {520.0, 470.0, 301.25, 207.75};
  c.validate();
  EXPECT_EQ(intrinsicsOf(c).fx, 520.0);
  const glm::dmat4 view(c.view());
  for (std::uint32_t v = 0; v < scene.vertexCount(); v += 89) {
    const glm::dvec4 e = view * glm::dvec4(scene.position(v), 1.0);
    const double x = e.x, y = -e.y, z = -e.z;
    const glm::dvec2 at = pixelOf(c, scene.position(v));
    EXPECT_NEAR(520.0 * x / z + 301.25, at.x, 1e-3) << v;
    EXPECT_NEAR(470.0 * y / z + 207.75, at.y, 1e-3) << v;
  }
  // Drawn: squares 3 pixels wide facing the camera at chosen pixels and depths
  Camera k;
  k.eye = {0, 0, 0}, k.target = {0, 0, -1}, k.near = 0.1f, k.far = 100.0f;
  k.width = 320, k.height = 200;
  k.intrinsics = {250.0, 180.0, 140.0, 90.0};
  for (const auto& [u, v, depth] : {std::tuple{140, 90, 4.0}, std::tuple{17, 23, 9.0},
                                    std::tuple{300, 181, 2.5}, std::tuple{203, 11, 30.0}}) {
    // The OpenCV point behind pixel (u, v) at this depth, in OpenGL's eye space (y up, -z)
    const double X = (u - 140.0) / 250.0 * depth, Y = (v - 90.0) / 180.0 * depth;
    const float hx = static_cast<float>(1.5 * depth / 250.0),
                hy = static_cast<float>(1.5 * depth / 180.0);
    const glm::vec3 p(static_cast<float>(X), static_cast<float>(-Y), static_cast<float>(-depth));
    Scene s;
    s.beginObject("square");
    const std::uint32_t m = s.addMaterial({});
    s.addPolygonVertices({p + glm::vec3(-hx, -hy, 0), p + glm::vec3(hx, -hy, 0),
                          p + glm::vec3(hx, hy, 0), p + glm::vec3(-hx, hy, 0)},
                         m);
    const Frame f = render(s, k);
    int drawn = 0;
    for (int y = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; ++x)
        if (f.ids[static_cast<std::size_t>(y) * k.width + x] != kNoPolygon) {
          ++drawn;
          EXPECT_LE(std::abs(x - u), 1) << u << "," << v;
          EXPECT_LE(std::abs(y - v), 1) << u << "," << v;
        }
    EXPECT_EQ(drawn, 9) << u << "," << v;
    EXPECT_NEAR(depthAs(f, k, DepthKind::kLinear)[static_cast<std::size_t>(v) * k.width + u], depth,
                1e-3 * depth);
  }
  Camera bad = c;
  bad.intrinsics.fx = -1;
  EXPECT_THROW(bad.validate(), Error);
  bad = c;
  bad.ortho = true;
  EXPECT_THROW(bad.validate(), Error);
}

// A pose in either convention gives back the same view; what is not a rigid motion is refused.
TEST(CameraData, PosesRoundTripInBothConventions) {
  Camera c;
  c.eye = {3, -2, 7}, c.target = {0.5f, 1, -1}, c.up = {0.2f, 1, 0.1f};
  for (const PoseConvention conv : {PoseConvention::kOpenCV, PoseConvention::kOpenGL}) {
    const glm::dmat4 pose = poseOf(c, conv);
    Camera d;
    setPose(d, pose, conv);
    const glm::mat4 a = c.view(), b = d.view();
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) EXPECT_NEAR(a[i][j], b[i][j], 1e-5) << i << "," << j;
  }
  // OpenCV's camera looks down its +z with y down: its pose's third column is the view direction
  const glm::dmat4 cv = poseOf(c, PoseConvention::kOpenCV);
  const glm::dvec3 forward = glm::normalize(glm::dvec3(c.target - c.eye));
  EXPECT_NEAR(glm::dot(glm::dvec3(cv[2]), forward), 1.0, 1e-6);
  EXPECT_NEAR(glm::dot(glm::dvec3(poseOf(c, PoseConvention::kOpenGL)[2]), forward), -1.0, 1e-6);
  glm::dmat4 scaled = cv;
  scaled[0] *= 2.0;
  Camera d;
  EXPECT_THROW(setPose(d, scaled, PoseConvention::kOpenCV), Error);
  glm::dmat4 mirrored = cv;
  mirrored[0] = -mirrored[0];
  EXPECT_THROW(setPose(d, mirrored, PoseConvention::kOpenCV), Error);
  glm::dmat4 projective = cv;
  projective[0][3] = 0.5;
  EXPECT_THROW(setPose(d, projective, PoseConvention::kOpenCV), Error);
  EXPECT_THROW(poseConventionNamed("colmap"), Error);
}

TEST(CameraData, PoseTextIsReadRowByRow) {
  const glm::dmat4 m = poseFromText("1 0 0 5\n0 1 0 6\n0 0 1 7\n0 0 0 1\n");
  EXPECT_EQ(m[3][0], 5.0);
  EXPECT_EQ(m[3][2], 7.0);
  const glm::dmat4 j = poseFromText("[[1, 0, 0, 5], [0, 1, 0, 6], [0, 0, 1, 7]]");
  EXPECT_EQ(j, m);
  EXPECT_THROW(poseFromText("1 2 3"), Error);
  EXPECT_THROW(poseFromText("1 0 0 5 0 1 0 6 0 0 1 x 0 0 0 1"), Error);
  EXPECT_THROW(poseFromText(std::string(17 * 2, ' ') + "1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1"), Error);
}

// A camera written as JSON and read back renders the same pixels: perspective, orthographic and
// calibrated, also when read from a manifest that holds it under "camera".
TEST(CameraData, CameraJsonReadBackRendersTheSamePixels) {
  const Scene scene = makeBuiltinScene("spheres:300");
  Camera persp = frameScene(scene, 200, 150);
  persp.fov_deg = 37.5f;
  Camera ortho = persp;
  ortho.ortho = true;
  ortho.ortho_half_height = orthoHalfHeightFor(ortho, scene.bounds());
  Camera calibrated = persp;
  calibrated.intrinsics = {190.0, 170.0, 97.5, 80.25};
  for (const Camera& c : {persp, ortho, calibrated}) {
    const std::string json = cameraJson(c);
    const Camera back = cameraFromJson(json);
    EXPECT_EQ(back.view(), c.view());
    EXPECT_EQ(back.projection(), c.projection());
    EXPECT_EQ(render(scene, back).ids, render(scene, c).ids);
    EXPECT_EQ(cameraFromJson("{\"camera\": " + json + "}").projection(), c.projection());
    const std::vector<Camera> views = camerasFromJson("[" + json + "," + json + "]");
    ASSERT_EQ(views.size(), 2u);
    EXPECT_EQ(views[1].view(), c.view());
  }
  // Only a pose: the eye and the view direction come from it
  nlohmann::json j = nlohmann::json::parse(cameraJson(persp));
  j.erase("eye");
  const Camera posed = cameraFromJson(j.dump());
  EXPECT_LT(glm::length(posed.eye - persp.eye), 1e-4f * glm::length(persp.eye));
  // Errors name the field
  j = nlohmann::json::parse(cameraJson(persp));
  j.erase("near");
  try {
    cameraFromJson(j.dump());
    ADD_FAILURE() << "a camera without near was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("\"near\""), std::string::npos) << e.what();
  }
  // Every missing field in one message, not the first alone
  j.erase("far");
  j.erase("width");
  try {
    cameraFromJson(j.dump());
    ADD_FAILURE() << "a camera without near, far and width was read";
  } catch (const Error& e) {
    for (const char* field : {"\"near\"", "\"far\"", "\"width\""})
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << field << ": " << e.what();
  }
  EXPECT_THROW(cameraFromJson("{"), Error);
  EXPECT_THROW(cameraFromJson("[]"), Error);
  EXPECT_THROW(camerasFromJson("[]"), Error);
  j = nlohmann::json::parse(cameraJson(persp));
  j["width"] = 0;
  EXPECT_THROW(cameraFromJson(j.dump()), Error);
  j = nlohmann::json::parse(cameraJson(persp));
  j["far"] = 1e300;
  EXPECT_THROW(cameraFromJson(j.dump()), Error);
}

// A file camera whose far / near passes 1000 keeps its view but gets near and far around the
// scene, and no more is clipped; a sane one is kept as the file says.
TEST(CameraData, FileCamerasWithWastefulClipPlanesAreRefitted) {
  const Scene scene = makeBuiltinScene("spheres:300");
  const Camera framed = frameScene(scene, 200, 150);
  SceneCamera file;
  file.eye = framed.eye, file.target = framed.target, file.up = framed.up;
  file.near = 0.05f * glm::length(framed.eye - framed.target) / 1600.0f;
  file.far = 1e6f;
  const Camera refit = fromSceneCamera(file, scene.bounds(), 200, 150);
  EXPECT_GT(refit.near, 100.0f * file.near);
  EXPECT_LT(refit.far, 1e-3f * file.far);
  Camera as_file = refit;
  as_file.near = file.near, as_file.far = file.far;
  const Frame a = render(scene, refit), b = render(scene, as_file);
  std::size_t drawn_a = 0, drawn_b = 0;
  for (std::size_t k = 0; k < a.ids.size(); ++k)
    drawn_a += a.ids[k] != kNoPolygon, drawn_b += b.ids[k] != kNoPolygon;
  EXPECT_EQ(drawn_a, drawn_b);
  SceneCamera sane = file;
  sane.near = 1.0f, sane.far = 500.0f;
  const Camera kept = fromSceneCamera(sane, scene.bounds(), 200, 150);
  EXPECT_EQ(kept.near, 1.0f);
  EXPECT_EQ(kept.far, 500.0f);
}

// Per pixel: the object, the material and the normal of the polygon shown.
TEST(CameraData, ObjectsMaterialsAndNormalsPerPixel) {
  Scene s;
  const std::uint32_t red = s.addMaterial({{1, 0, 0}, 1.0f, "red"});
  const std::uint32_t blue = s.addMaterial({{0, 0, 1}, 1.0f, "blue"});
  s.beginObject("left");
  s.addPolygonVertices({{-2, -1, 0}, {0, -1, 0}, {0, 1, 0}, {-2, 1, 0}}, red);
  s.beginObject("right, turned");
  s.addPolygonVertices({{0, -1, 0}, {2, -1, -1}, {2, 1, -1}, {0, 1, 0}}, blue);  // wound away
  Camera c;
  c.eye = {0, 0, 6}, c.target = {0, 0, 0}, c.width = 160, c.height = 80, c.near = 1, c.far = 20;
  const Frame f = render(s, c);
  const std::vector<std::uint32_t> objects = objectsAt(f, s), materials = materialsAt(f, s);
  const std::vector<float> world = normalsAt(f, s, c, NormalSpace::kWorld);
  const std::vector<float> eye = normalsAt(f, s, c, NormalSpace::kEye);
  const std::size_t left = 40 * 160 + 50, right = 40 * 160 + 100, corner = 0;
  EXPECT_EQ(objects[left], 0u);
  EXPECT_EQ(objects[right], 1u);
  EXPECT_EQ(materials[left], red);
  EXPECT_EQ(materials[right], blue);
  EXPECT_EQ(objects[corner], kNoPolygon);
  EXPECT_TRUE(std::isnan(world[3 * corner]));
  EXPECT_FLOAT_EQ(world[3 * left + 2], 1.0f);
  // The turned square faces the eye whatever its winding: (1, 0, 2) / sqrt(5)
  EXPECT_NEAR(world[3 * right], 1.0 / std::sqrt(5.0), 1e-6);
  EXPECT_NEAR(world[3 * right + 2], 2.0 / std::sqrt(5.0), 1e-6);
  // The camera looks down -z unturned: eye space equals world space here
  EXPECT_NEAR(eye[3 * right], world[3 * right], 1e-6);
  c.eye = {6, 0, 0}, c.target = {0, 0, 0};  // from +x: world x is the eye's +z
  const Frame g = render(s, c);
  const std::vector<float> turned = normalsAt(g, s, c, NormalSpace::kEye);
  for (std::size_t k = 0; k < g.ids.size(); ++k) {
    if (g.ids[k] != kNoPolygon) {
      EXPECT_GT(turned[3 * k + 2], 0.0f) << "faces the eye";
    }
  }
  EXPECT_EQ(normalSpaceNamed("eye"), NormalSpace::kEye);
  EXPECT_THROW(normalSpaceNamed("tangent"), Error);
}

// normals.npy faces the eye: at every drawn pixel, the normal n and the point p the pixel shows
// (its window depth unprojected) satisfy n . (eye - p) >= 0 (in eye space, n . (-p) >= 0; under
// an orthographic camera, n . (eye - target) >= 0), in world and eye space, seen from outside the
// solids and from inside one of them (where every face seen is wound away from the eye).
TEST(CameraData, NormalsFaceTheEyeFromOutsideAndFromInside) {
  const Scene s = makeBuiltinScene("solids");
  // The centroid of object 0's vertices: inside that convex solid
  glm::dvec3 inside(0.0);
  const Object& first = s.objects.at(0);
  for (std::uint32_t v = 0; v < first.vertex_count; ++v)
    inside += glm::dvec3(s.position(first.first_vertex + v));
  inside /= double(first.vertex_count);
  struct View {
    const char* name;
    Camera camera;
  };
  std::vector<View> views;
  views.push_back({"outside, perspective", frameScene(s, 160, 120)});
  Camera ortho = frameScene(s, 160, 120);
  ortho.ortho = true;
  ortho.ortho_half_height = orthoHalfHeightFor(ortho, s.bounds());
  views.push_back({"outside, orthographic", ortho});
  Camera in = frameScene(s, 160, 120);
  in.eye = glm::vec3(inside);
  in.target = glm::vec3(inside) + glm::vec3(0.3f, -0.2f, -1.0f);
  in.near = 1e-3f;
  in.fov_deg = 100.0f;
  views.push_back({"inside object 0, perspective", in});
  for (const View& view : views) {
    SCOPED_TRACE(view.name);
    const Camera& c = view.camera;
    const Frame f = render(s, c);
    const glm::dmat4 view_m(c.view()), clip_from_world = glm::dmat4(c.projection()) * view_m;
    const glm::dmat4 world_from_clip = glm::inverse(clip_from_world);
    const glm::dvec3 eye(c.eye), toward_eye = glm::normalize(glm::dvec3(c.eye - c.target));
    for (NormalSpace space : {NormalSpace::kWorld, NormalSpace::kEye}) {
      const std::vector<float> n = normalsAt(f, s, c, space);
      std::size_t drawn = 0, away = 0;
      double worst = 1.0;
      for (int row = 0; row < f.height; ++row)
        for (int x = 0; x < f.width; ++x) {
          const std::size_t k = std::size_t(row) * f.width + x;
          if (f.ids[k] == kNoPolygon) continue;
          ++drawn;
          const double y = f.height - 1 - row;  // GL window y, up
          const glm::dvec4 ndc(2.0 * (x + 0.5) / f.width - 1.0, 2.0 * (y + 0.5) / f.height - 1.0,
                               2.0 * f.depth[k] - 1.0, 1.0);
          glm::dvec4 pw = world_from_clip * ndc;
          const glm::dvec3 p = glm::dvec3(pw) / pw.w;
          glm::dvec3 to_eye = c.ortho ? toward_eye : glm::normalize(eye - p);
          if (space == NormalSpace::kEye) to_eye = glm::dmat3(view_m) * to_eye;  // a direction
          const glm::dvec3 normal(n[3 * k], n[3 * k + 1], n[3 * k + 2]);
          ASSERT_NEAR(glm::length(normal), 1.0, 1e-5) << "pixel " << k;
          const double facing = glm::dot(normal, to_eye);
          worst = std::min(worst, facing);
          // Seen nearly edge-on the unprojected point is only as good as the float depth
          away += facing < -1e-4;
        }
      EXPECT_GT(drawn, 1000u);
      EXPECT_EQ(away, 0u) << "pixels whose normal points away from the eye; worst cosine " << worst;
    }
  }
}

// A Z-up model (CAD, Blender) framed with --up 0,0,1 is seen from its front three-quarter,
// from above, keeping z up; y up frames as it always did.
TEST(CameraData, FramingFollowsTheGivenUpAxis) {
  Bounds b;
  b.extend({-1, -2, -3});
  b.extend({4, 5, 6});
  const Camera y = frameBounds(b, 320, 240);
  const Camera y_given = frameBounds(b, 320, 240, 45.0f, false, {0, 1, 0});
  EXPECT_EQ(y.eye, y_given.eye);
  EXPECT_EQ(y.up, glm::vec3(0, 1, 0));
  EXPECT_GT(y.eye.y, y.target.y);
  const Camera z = frameBounds(b, 320, 240, 45.0f, false, {0, 0, 1});
  EXPECT_EQ(z.up, glm::vec3(0, 0, 1));
  EXPECT_GT(z.eye.z, z.target.z) << "from above";
  EXPECT_LT(z.eye.y, z.target.y) << "from the front (-y), as Blender's front view";
  EXPECT_GT(z.eye.x, z.target.x) << "and from the right, as with y up";
  // All eight corners in view
  for (int k = 0; k < 8; ++k) {
    const glm::vec3 corner((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y,
                           (k & 4) ? b.hi.z : b.lo.z);
    const glm::dvec2 at = pixelOf(z, corner);
    EXPECT_GT(at.x, 0.0);
    EXPECT_LT(at.x, 320.0);
    EXPECT_GT(at.y, 0.0);
    EXPECT_LT(at.y, 240.0);
  }
}

// A list of views written by hand: what is left out is defaulted (the size given, up +y,
// perspective at 45 degrees) and near and far are fitted around the scene, as frameScene fits
// them; a plane given is kept, the other fitted around it.
TEST(CameraData, ViewsLeftIncompleteAreFilledAsStated) {
  const Scene scene = makeBuiltinScene("spheres:300");
  const Camera framed = frameScene(scene, 200, 150);
  const auto at = [](const glm::vec3& v) { return fmt::format("[{}, {}, {}]", v.x, v.y, v.z); };
  const std::string eye = at(framed.eye), target = at(framed.target);
  ViewList list =
      viewsFromJson("[{\"eye\": " + eye + ", \"target\": " + target + "}, {\"eye\": " + eye +
                        ", \"target\": " + target + ", \"near\": 0.5}]",
                    ViewDefaults{200, 150});
  ASSERT_EQ(list.cameras.size(), 2u);
  list.fitDepth(scene.bounds());
  Camera expected = framed;
  expected.up = {0.0f, 1.0f, 0.0f};
  fitNearFar(expected, scene.bounds());
  const Camera& a = list.cameras[0];
  EXPECT_EQ(a.width, 200);
  EXPECT_EQ(a.height, 150);
  EXPECT_EQ(a.fov_deg, 45.0f);
  EXPECT_FALSE(a.ortho);
  EXPECT_EQ(a.near, expected.near);
  EXPECT_EQ(a.far, expected.far);
  EXPECT_EQ(list.cameras[1].near, 0.5f);
  EXPECT_EQ(list.cameras[1].far, expected.far);
  // The strict reader still needs every field
  EXPECT_THROW(camerasFromJson("[{\"eye\": " + eye + ", \"target\": " + target + "}]"), Error);
}

}  // namespace
}  // namespace hsr
