// The fast path's triangles are finished four at a time (ShadeBatch): their depth planes and
// Lambert cosines lane-wise. Pinned twice: the SSE2 lanes, and the AVX2 lanes where the
// processor has AVX2, against the scalar lanes (windowPlane and lambertOf themselves) bit for bit,
// on lanes chosen to reach every branch (edge-on, too steep, duplicate and far-off vertices, huge
// and tiny normals); and the whole pipeline's screen triangles with the batch against the general
// path (which finishes each triangle on its own), byte for byte and in the same order, on scenes
// where clipped triangles of the general path fall between batched ones, with several materials,
// one named by no polygon's material, shading on and off, and every cull mode.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "core/random.hpp"
#include "hsr/render.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/stages.hpp"
#include "test_util.hpp"

namespace hsr::detail {
namespace {

std::uint64_t bits(double d) { return std::bit_cast<std::uint64_t>(d); }

// One lane's window vertices (floats widened to double, as ShadeBatch stores them) and normal.
void randomLane(SplitMix64& rng, ShadeLanes& l, int i) {
  const int kind = static_cast<int>(rng.next() % 8);
  auto coord = [&] {
    switch (kind) {
      case 0:  // far-off vertices (up to toWindow's 2^22 pixels)
        return rng.uniform(-4.0e6f, 4.0e6f);
      case 1:  // a few pixels wide
        return 100.0f + rng.uniform(-2.0f, 2.0f);
      default:
        return rng.uniform(-50.0f, 2000.0f);
    }
  };
  float x[3], y[3], z[3];
  for (int k = 0; k < 3; ++k) {
    x[k] = coord();
    y[k] = coord();
    z[k] = rng.uniform();
  }
  if (kind == 2) {  // edge-on: collinear in the window (C = 0 exactly)
    x[2] = x[1];
    y[2] = y[1];
    x[0] = x[1];
  }
  if (kind == 3) {  // too steep: almost no window area, a large change of depth
    x[1] = x[0] + 0x1p-10f;
    y[1] = y[0];
    x[2] = x[0];
    y[2] = y[0] + 0x1p-10f;
    z[1] = 1.0f;
    z[2] = 0.0f;
  }
  if (kind == 4) {  // duplicate vertex
    x[1] = x[0];
    y[1] = y[0];
    z[1] = z[0];
  }
  // The topmost vertex first, as ShadeBatch::add stores them.
  struct Xy {
    float x, y;
  };
  const Xy v[3] = {{x[0], y[0]}, {x[1], y[1]}, {x[2], y[2]}};
  const Xy* pv[3] = {&v[0], &v[1], &v[2]};
  const int a = topmostVertex(pv), b = (a + 1) % 3, c = (a + 2) % 3;
  l.ax[i] = x[a], l.ay[i] = y[a], l.az[i] = z[a];
  l.bx[i] = x[b], l.by[i] = y[b], l.bz[i] = z[b];
  l.cx[i] = x[c], l.cy[i] = y[c], l.cz[i] = z[c];
  const double scale = kind == 5 ? 1e150 : (kind == 6 ? 1e-150 : 1.0);
  l.nx[i] = scale * (rng.uniform() - 0.5);
  l.ny[i] = scale * (rng.uniform() - 0.5);
  l.nz[i] = scale * (rng.uniform() - 0.5);
  l.len2[i] = l.nx[i] * l.nx[i] + l.ny[i] * l.ny[i] + l.nz[i] * l.nz[i];
  if (!(l.len2[i] > 0.0) || !std::isfinite(l.len2[i])) l.len2[i] = 1.0;  // as usableNormal
}

#if defined(__SSE2__) && !defined(HSR_NO_SIMD)
TEST(ShadeBatch, SimdLanesAreTheScalarLanes) {
  SplitMix64 rng(2026);
  const glm::dvec3 lights[] = {glm::normalize(glm::dvec3(0.3, -0.2, -1.0)),
                               glm::dvec3(0.0, 0.0, 1.0)};
  int ok = 0, failed = 0;
  for (int round = 0; round < 20000; ++round) {
    ShadeLanes in;
    for (int i = 0; i < ShadeLanes::kLanes; ++i) randomLane(rng, in, i);
    const glm::dvec3& light = lights[round % 2];
    ShadedLanes scalar, sse2, avx2;
    shadeLanesScalar(in, light, scalar);
    shadeLanesSse2(in, light, sse2);
    if (shadeLanesAvx2Available()) {
      shadeLanesAvx2(in, light, avx2);
      for (int i = 0; i < ShadeLanes::kLanes; ++i) {
        ASSERT_EQ(sse2.ok[i], avx2.ok[i]) << "round " << round << " lane " << i;
        ASSERT_EQ(bits(sse2.cosine[i]), bits(avx2.cosine[i])) << "round " << round;
        if (!sse2.ok[i]) continue;
        ASSERT_EQ(bits(sse2.dzdx[i]), bits(avx2.dzdx[i])) << "round " << round << " lane " << i;
        ASSERT_EQ(bits(sse2.dzdy[i]), bits(avx2.dzdy[i])) << "round " << round << " lane " << i;
        ASSERT_EQ(bits(sse2.z0[i]), bits(avx2.z0[i])) << "round " << round << " lane " << i;
      }
    }
    for (int i = 0; i < ShadeLanes::kLanes; ++i) {
      ASSERT_EQ(scalar.ok[i], sse2.ok[i]) << "round " << round << " lane " << i;
      ASSERT_EQ(bits(scalar.cosine[i]), bits(sse2.cosine[i])) << "round " << round;
      if (!scalar.ok[i]) {
        failed++;
        continue;
      }
      ok++;
      ASSERT_EQ(bits(scalar.dzdx[i]), bits(sse2.dzdx[i])) << "round " << round << " lane " << i;
      ASSERT_EQ(bits(scalar.dzdy[i]), bits(sse2.dzdy[i])) << "round " << round << " lane " << i;
      ASSERT_EQ(bits(scalar.z0[i]), bits(sse2.z0[i])) << "round " << round << " lane " << i;
    }
  }
  // Both outcomes were reached, many times.
  EXPECT_GT(ok, 50000);
  EXPECT_GT(failed, 5000);
}
#endif

// Triangles in front of the camera, and (every seventh) large ones through the near plane that
// the general path clips, in one object; materials 0..2, and 7, which the scene does not have.
Scene mixedScene(std::uint64_t seed, int n) {
  SplitMix64 rng(seed);
  Scene s;
  s.beginObject("mixed");
  std::uint32_t materials[3];
  for (int m = 0; m < 3; ++m) {
    Material mat;
    mat.color = {rng.uniform(), rng.uniform(), rng.uniform()};
    materials[m] = s.addMaterial(mat);
  }
  for (int i = 0; i < n; ++i) {
    const bool crossing = i % 7 == 3;
    const glm::vec3 c(rng.uniform(-3, 3), rng.uniform(-3, 3),
                      crossing ? rng.uniform(-1, 1) : rng.uniform(-8, -2));
    const float size = crossing ? 6.0f : (i % 3 == 0 ? 0.05f : 0.6f);
    glm::vec3 v[3];
    for (glm::vec3& p : v)
      p = c + size * glm::vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    if (i % 11 == 5) v[2] = v[0] + 0.5f * (v[1] - v[0]);  // zero area: degenerate
    const std::uint32_t m = i % 13 == 0 ? 7u : materials[i % 3];
    s.addPolygonVertices({v[0], v[1], v[2]}, m);
  }
  return s;
}

TEST(ShadeBatch, BatchedTrianglesAreTheGeneralPathsInOrder) {
  const Camera cam = testing::cameraAtOrigin(320, 240);
  const Scene s = mixedScene(9, 20000);
  std::uint64_t batched = 0, clipped = 0;
  for (const CullMode cull : {CullMode::None, CullMode::Back, CullMode::Front}) {
    for (const bool shade : {true, false}) {
      RenderOptions o;
      o.cull = cull;
      o.shade = shade;
      const PreparedScene fast = prepare(s, cam, o, {});
      // Asking for the window polygons too takes every polygon down the general path.
      const PreparedScene general = prepare(s, cam, o, {.window_polygons = true});
      ASSERT_EQ(fast.triangles.size(), general.triangles.size());
      for (std::size_t i = 0; i < fast.triangles.size(); ++i)
        ASSERT_EQ(std::memcmp(&fast.triangles[i], &general.triangles[i], sizeof(ScreenTriangle)), 0)
            << "triangle " << i << ", cull " << static_cast<int>(cull) << ", shade " << shade;
      EXPECT_EQ(fast.stats.triangles_rasterized, general.stats.triangles_rasterized);
      EXPECT_EQ(fast.stats.culled_backface, general.stats.culled_backface);
      EXPECT_EQ(fast.stats.degenerate_dropped, general.stats.degenerate_dropped);
      batched += fast.triangles.size();
      clipped += fast.stats.clipped;
    }
  }
  // The scene reached both paths, interleaved.
  EXPECT_GT(batched, 20000u);
  EXPECT_GT(clipped, 2000u);
}

}  // namespace
}  // namespace hsr::detail
