// The Open CASCADE peer itself (occt_peer.hpp): its window matches hsr's camera, a cube seen
// from a three-quarter view gives its nine visible and three hidden edges where hsr's camera
// puts them, and a UV sphere in silhouette-only mode a closed outline on the projected circle.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include "agreement/occt_peer.hpp"

namespace hsr {
namespace {

using testing::OcctLines;
using testing::OcctMesh;
using testing::OcctMode;
using testing::OcctSegment;

// hsr's window pixel of `p`: camera.projection() * camera.view(), in double
glm::dvec2 hsrPixel(const Camera& camera, const glm::dvec3& p) {
  const glm::dvec4 clip =
      glm::dmat4(camera.projection()) * glm::dmat4(camera.view()) * glm::dvec4(p, 1.0);
  return {(clip.x / clip.w + 1) / 2 * camera.width - 0.5,
          (1 - clip.y / clip.w) / 2 * camera.height - 0.5};
}

OcctMesh unitCube() {
  OcctMesh mesh;
  for (int i = 0; i < 8; ++i) mesh.vertices.push_back({i & 1, (i >> 1) & 1, (i >> 2) & 1});
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.triangles.push_back({q[0], q[1], q[2]});
    mesh.triangles.push_back({q[0], q[2], q[3]});
  }
  return mesh;
}

OcctMesh uvSphere(int slices, int stacks) {
  OcctMesh mesh;
  mesh.vertices.push_back({0, 1, 0});
  for (int i = 1; i < stacks; ++i) {
    const double phi = std::numbers::pi * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double theta = 2 * std::numbers::pi * j / slices;
      mesh.vertices.push_back(
          {std::sin(phi) * std::cos(theta), std::cos(phi), -std::sin(phi) * std::sin(theta)});
    }
  }
  const auto bottom = static_cast<std::uint32_t>(mesh.vertices.size());
  mesh.vertices.push_back({0, -1, 0});
  auto at = [&](int ring, int j) { return std::uint32_t(1 + ring * slices + (j % slices)); };
  for (int j = 0; j < slices; ++j) {
    mesh.triangles.push_back({0, at(0, j), at(0, j + 1)});
    mesh.triangles.push_back({bottom, at(stacks - 2, j + 1), at(stacks - 2, j)});
    for (int r = 0; r + 1 < stacks - 1; ++r) {
      mesh.triangles.push_back({at(r, j), at(r + 1, j), at(r + 1, j + 1)});
      mesh.triangles.push_back({at(r, j), at(r + 1, j + 1), at(r, j + 1)});
    }
  }
  return mesh;
}

// The cube edge (a, b) whose projection `s` is, either way round; {-1, -1} if none
std::pair<int, int> cubeEdgeOf(const OcctSegment& s, const std::vector<glm::dvec2>& corners) {
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b)
      if (std::popcount(unsigned(a ^ b)) == 1 && glm::length(s.a - corners[a]) < 1e-6 &&
          glm::length(s.b - corners[b]) < 1e-6)
        return {std::min(a, b), std::max(a, b)};
  return {-1, -1};
}

Camera threeQuarterCamera() {
  Camera camera;
  camera.eye = {3.0f, 2.5f, 4.0f};
  camera.target = {0.5f, 0.5f, 0.5f};
  return camera;
}

TEST(OcctPeer, WindowMatchesHsrCamera) {
  Camera perspective = threeQuarterCamera();
  Camera ortho = perspective;
  ortho.ortho = true;
  ortho.ortho_half_height = 1.5f;
  for (const Camera& camera : {perspective, ortho})
    for (const glm::dvec3& p : unitCube().vertices) {
      const glm::dvec2 ours = hsrPixel(camera, p), occt = testing::occtPixelOf(camera, p);
      EXPECT_NEAR(occt.x, ours.x, 1e-6);
      EXPECT_NEAR(occt.y, ours.y, 1e-6);
    }
}

TEST(OcctPeer, CubeHasNineVisibleAndThreeHiddenEdges) {
  const OcctMesh cube = unitCube();
  for (bool ortho : {false, true}) {
    Camera camera = threeQuarterCamera();
    camera.ortho = ortho;
    camera.ortho_half_height = 1.5f;
    std::vector<glm::dvec2> corners;
    for (const glm::dvec3& p : cube.vertices) corners.push_back(hsrPixel(camera, p));
    const OcctLines lines = testing::occtHiddenLines(cube, camera, OcctMode::kFacePerTriangle);
    // Corner 0 (the origin) is the one turned away from the eye: its three edges are hidden,
    // the other nine seen whole; the faces' diagonals (0 degrees) are smooth, left out
    ASSERT_EQ(lines.visible.size(), 9u) << "ortho " << ortho;
    ASSERT_EQ(lines.hidden.size(), 3u) << "ortho " << ortho;
    std::map<std::pair<int, int>, int> seen;
    for (const OcctSegment& s : lines.visible) {
      const auto edge = cubeEdgeOf(s, corners);
      EXPECT_NE(edge.first, -1) << s.a.x << "," << s.a.y << " " << s.b.x << "," << s.b.y;
      EXPECT_NE(edge.first, 0);
      ++seen[edge];
    }
    for (const OcctSegment& s : lines.hidden) {
      const auto edge = cubeEdgeOf(s, corners);
      EXPECT_EQ(edge.first, 0) << s.a.x << "," << s.a.y << " " << s.b.x << "," << s.b.y;
      ++seen[edge];
    }
    EXPECT_EQ(seen.size(), 12u);
  }
}

TEST(OcctPeer, SphereSilhouetteIsAClosedCircle) {
  const OcctMesh sphere = uvSphere(48, 24);
  Camera camera;  // at (0, 0, 5) looking at the origin, 45 degrees, 800 x 600
  const OcctLines lines = testing::occtHiddenLines(sphere, camera, OcctMode::kSingleFace);
  // The silhouette circle of a unit sphere seen from distance 5, in pixels
  const double focal = camera.height / 2.0 / std::tan(camera.fov_deg / 2 * std::numbers::pi / 180);
  const double radius = focal * std::tan(std::asin(1.0 / 5.0));
  const glm::dvec2 centre = hsrPixel(camera, {0, 0, 0});
  ASSERT_GE(lines.visible.size(), 24u);
  EXPECT_TRUE(lines.hidden.empty());
  std::map<std::pair<long long, long long>, int> ends;  // endpoints on a 1e-6 px grid
  double length = 0;
  for (const OcctSegment& s : lines.visible) {
    for (const glm::dvec2& p : {s.a, s.b}) {
      // The mesh's outline is inscribed: within the circle, and within cos(pi / 48) of it
      EXPECT_LE(glm::length(p - centre), radius * 1.001);
      EXPECT_GE(glm::length(p - centre), radius * std::cos(std::numbers::pi / 48) * 0.995);
      ++ends[{std::llround(p.x * 1e6), std::llround(p.y * 1e6)}];
    }
    length += glm::length(s.b - s.a);
  }
  for (const auto& [point, count] : ends) EXPECT_EQ(count % 2, 0) << "an open end";
  EXPECT_NEAR(length, 2 * std::numbers::pi * radius, 0.02 * 2 * std::numbers::pi * radius);
}

}  // namespace
}  // namespace hsr
