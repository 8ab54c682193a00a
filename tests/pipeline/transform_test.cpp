// The transform stage four vertices at a time (SSE2) against the readable one-at-a-time loop:
// the same clip positions, outcodes and window positions, bit for bit, on vertices chosen to
// reach every branch (inside, outside each plane, behind the eye, at the eye, beyond float's
// range, NaN and infinite input, beyond toWindow's 2^22 pixels), for perspective and parallel
// cameras and for a clip band wider than the viewport.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "hsr/camera.hpp"
#include "hsr/scene.hpp"
#include "pipeline/stages.hpp"

namespace hsr::detail {
namespace {

#if defined(__SSE2__) && !defined(HSR_NO_SIMD)

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }

// A scene of n vertices (in one object, so the four-wide loop and its scalar tail both run):
// mostly near the camera's view, some far off, some special values.
Scene vertexScene(std::uint64_t seed, int n, const glm::vec3& eye) {
  SplitMix64 rng(seed);
  Scene s;
  s.beginObject("vertices");
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int i = 0; i < n; ++i) {
    glm::vec3 p(rng.uniform(-1.5f, 1.5f), rng.uniform(-1.5f, 1.5f), rng.uniform(-1.5f, 1.5f));
    switch (rng.next() % 16) {
      case 0:  // far outside every plane
        p *= 1e3f;
        break;
      case 1:  // behind the eye, and on its plane (w = 0)
        p = eye +
            glm::vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), 1.0f + rng.uniform(-0.2f, 0.2f));
        break;
      case 2:
        p = eye;
        break;
      case 3:  // beyond float's range once transformed
        p = glm::vec3(3e38f, -3e38f, 3e38f);
        break;
      case 4:  // not finite
        p[static_cast<int>(rng.next() % 3)] = (rng.next() & 1) ? nan : -inf;
        break;
      case 5:  // just in front of the eye: projected far beyond 2^22 pixels
        p = eye + glm::vec3(rng.uniform(0.5f, 1.0f), rng.uniform(-1, 1), -0.0001f);
        break;
      case 6:  // on pixel centres and half-way between, where rounding ties
        p = glm::vec3(std::round(p.x * 64) / 64, std::round(p.y * 64) / 64, 0.0f);
        break;
      default:
        break;
    }
    s.addVertex(p);
  }
  return s;
}

TEST(TransformStage, FourVerticesAtATimeAreTheScalarLoop) {
  std::uint64_t compared = 0, projected = 0;
  for (std::uint64_t seed = 1; seed <= 24; ++seed) {
    const int n = 1003 + static_cast<int>(seed);  // not a multiple of four: the tail runs too
    // A camera off every axis, so that no entry of the matrix is zero and every sum rounds
    SplitMix64 rng(seed * 977);
    Camera camera;
    camera.eye = {rng.uniform(-0.7f, 0.7f), rng.uniform(-0.7f, 0.7f),
                  4.0f + rng.uniform(-0.5f, 0.5f)};
    camera.target = {rng.uniform(-0.3f, 0.3f), rng.uniform(-0.3f, 0.3f), rng.uniform(-0.3f, 0.3f)};
    camera.up = glm::normalize(glm::vec3(rng.uniform(-0.4f, 0.4f), 1.0f, rng.uniform(-0.4f, 0.4f)));
    const Scene scene = vertexScene(seed, n, camera.eye);
    camera.width = 160 + static_cast<int>(seed) * 7;
    camera.height = 120 + static_cast<int>(seed) * 3;
    camera.ortho = seed % 3 == 0;
    camera.ortho_half_height = 1.7f;
    camera.near = 0.05f * static_cast<float>(seed);
    camera.far = 6.0f + static_cast<float>(seed);
    const glm::mat4 mvp = camera.projection() * camera.view();
    const Viewport vp = viewportOf(camera);
    const ClipSetup cs = seed % 4 == 1 ? ClipSetup{2.0f, 1.5f} : ClipSetup{1.0f, 1.0f};
    std::vector<glm::vec4> clip_a(n), clip_b(n);
    std::vector<VertexOut> out_a(n), out_b(n);
    transformVertexRange(scene, mvp, cs, vp, 0, static_cast<std::uint32_t>(n), clip_a.data(),
                         out_a.data());
    transformVertexRangeSse2(scene, mvp, cs, vp, 0, static_cast<std::uint32_t>(n), clip_b.data(),
                             out_b.data());
    for (int v = 0; v < n; ++v) {
      const std::string what = "seed " + std::to_string(seed) + ", vertex " + std::to_string(v);
      for (int k = 0; k < 4; ++k)
        ASSERT_EQ(bits(clip_a[v][k]), bits(clip_b[v][k])) << what << ", clip coordinate " << k;
      ASSERT_EQ(out_a[v].code, out_b[v].code) << what;
      ++compared;
      if (out_a[v].code & (kMustClip | kNonFinite)) continue;
      ++projected;
      EXPECT_EQ(bits(out_a[v].x), bits(out_b[v].x)) << what;
      EXPECT_EQ(bits(out_a[v].y), bits(out_b[v].y)) << what;
      EXPECT_EQ(bits(out_a[v].z), bits(out_b[v].z)) << what;
      EXPECT_EQ(out_a[v].fx, out_b[v].fx) << what;
      EXPECT_EQ(out_a[v].fy, out_b[v].fy) << what;
    }
  }
  // Both kinds were met in numbers: projected vertices and ones left to clipping or dropped
  EXPECT_GT(projected, compared / 4);
  EXPECT_LT(projected, compared * 9 / 10);
}

#endif  // a build without the SIMD sibling has only the loop the other tests run

}  // namespace
}  // namespace hsr::detail
