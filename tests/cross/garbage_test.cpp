// docs/testing.md row 13: scenes of random bit-pattern floats (NaN, Inf, subnormals, 1e38) and
// random cameras. Nothing may crash or reach undefined behaviour (the sanitizer build checks
// float-cast-overflow too); bad polygons are dropped and counted, and what is drawn is finite.

#include <gtest/gtest.h>

#include <cstdint>
#include <cmath>
#include <cstring>

#include "core/bit_cast.hpp"
#include "hsr/error.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using testing::Rng;

float randomBits(Rng& rng) {
  return detail::bitCast<float>(static_cast<std::uint32_t>(rng.next()));
}

// A float that is random bits 1 time in 4, else an ordinary coordinate.
float mostlySane(Rng& rng, float scale) {
  return (rng.next() & 3) == 0 ? randomBits(rng) : rng.uniform(-scale, scale);
}

class Garbage : public testing::EveryAlgorithm {};

TEST_P(Garbage, RandomBitPatternScenesNeverCrash) {
  // docs/testing.md row 13: 1,000 in CI. In the sanitizer leg's tier (testing::legCases) a
  // twentieth for the object-order algorithms, whose pair work on these soups (every large
  // triangle over every other in a 64 x 64 picture) takes 20-40 s in Release alone, and an eighth
  // for the others (50 and 125 scenes: every branch of the scene builder's refusals and of the
  // random states is still taken, under ASan+UBSan the search is the fuzzers'); Release runs all
  // 1,000 for every one.
  const bool object_order = findAlgorithm(GetParam()).precision == Precision::kObject;
  const int scenes = testing::legCases(1000 * testing::countScale(), object_order ? 20 : 8);
  std::uint64_t dropped = 0, drawn = 0;
  // One frame rendered into again, scene after scene: the scratch an algorithm keeps in it meets
  // every kind of garbage after every other (a fresh frame is every other suite's), and no
  // render maps fresh memory (under the sanitizers, every block over 128 KiB is mapped afresh)
  Frame f;
  for (int n = 0; n < scenes; ++n) {
    SCOPED_TRACE("garbage scene seed " + std::to_string(n));
    Rng rng(static_cast<std::uint64_t>(n) * 7919u + 1u);
    Scene s;
    const int meshes = 1 + static_cast<int>(rng.next() % 20);
    for (int m = 0; m < meshes; ++m) {
      s.beginObject("garbage");
      const std::uint32_t mat = s.addMaterial({{randomBits(rng), 0.5f, 0.5f}, randomBits(rng)});
      const int verts = 3 + static_cast<int>(rng.next() % 64);
      for (int v = 0; v < verts; ++v)
        s.addVertex({mostlySane(rng, 4.0f), mostlySane(rng, 4.0f), mostlySane(rng, 4.0f)});
      const int tris = static_cast<int>(rng.next() % 256);
      for (int t = 0; t < tris; ++t) {
        // 1 in 32 indices out of range: refused by the scene with an error, never stored.
        std::uint32_t idx[3];
        for (std::uint32_t& i : idx)
          i = (rng.next() % 32 == 0) ? static_cast<std::uint32_t>(rng.next())
                                     : static_cast<std::uint32_t>(rng.next() % verts);
        try {
          s.addPolygon({idx[0], idx[1], idx[2]}, mat);
        } catch (const Error&) {
        }
      }
    }
    Camera cam;
    cam.width = 64;
    cam.height = 64;
    cam.eye = {mostlySane(rng, 8.0f), mostlySane(rng, 8.0f), 6.0f + rng.uniform(0.0f, 4.0f)};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.near = 0.05f;
    cam.far = 50.0f;
    cam.ortho = (rng.next() & 1) != 0;
    cam.ortho_half_height = 4.0f;
    RenderOptions o = options();
    o.cull = static_cast<CullMode>(rng.next() % 4);
    o.polygon_mode = static_cast<PolygonMode>(rng.next() % 3);
    o.outline = (rng.next() & 1) != 0;
    // What the algorithm cannot do is refused (tests/visibility/registry_test.cpp); here the
    // draws go on with what it can (the random numbers drawn the same either way).
    if (!findAlgorithm(GetParam()).has(kPolygonModes)) o.polygon_mode = PolygonMode::Fill;
    if (!findAlgorithm(GetParam()).has(kOutline)) o.outline = false;
    try {
      cam.validate();
    } catch (const Error&) {
      EXPECT_THROW(render(s, cam, o), Error);  // a bad camera is refused, never rendered
      continue;
    }
    render(s, cam, o, f);
    dropped += f.stats.degenerate_dropped;
    for (std::size_t k = 0; k < f.ids.size(); ++k) {
      ASSERT_TRUE(std::isfinite(f.depth[k]));
      ASSERT_GE(f.depth[k], 0.0f);
      ASSERT_LE(f.depth[k], 1.0f);
      if (f.ids[k] != kNoPolygon) {
        ASSERT_LT(f.ids[k], s.polygonCount());
        drawn++;
      }
    }
  }
  std::printf(
      "[ figures ] row 13 %s: %d garbage scenes, %llu triangles dropped as degenerate, "
      "%llu pixels drawn, 0 crashes\n",
      GetParam().c_str(), scenes, static_cast<unsigned long long>(dropped),
      static_cast<unsigned long long>(drawn));
  EXPECT_GT(dropped, 0u);
  EXPECT_GT(drawn, 0u);
}

TEST_P(Garbage, NonFiniteCamerasAreRefused) {
  Scene s;
  s.addPolygonVertices({{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}}, s.addMaterial({}));
  const float bad[] = {NAN, INFINITY, -INFINITY};
  for (float b : bad) {
    for (int field = 0; field < 7; ++field) {
      Camera c;
      c.width = c.height = 32;
      switch (field) {
        case 0:
          c.eye.x = b;
          break;
        case 1:
          c.target.y = b;
          break;
        case 2:
          c.up.z = b;
          break;
        case 3:
          c.fov_deg = b;
          break;
        case 4:
          c.near = b;
          break;
        case 5:
          c.far = b;
          break;
        default:
          c.ortho = true;
          c.ortho_half_height = b;
          break;
      }
      EXPECT_THROW(render(s, c, options()), Error) << "field " << field << " = " << b;
    }
  }
}

// Coordinates so large that the transform overflows to infinity: dropped and counted, never
// converted to integers.
TEST_P(Garbage, HugeCoordinatesOverflowingTheTransformAreDropped) {
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  s.addPolygonVertices({{-3e38f, -3e38f, 0}, {3e38f, -3e38f, 0}, {0, 3e38f, 0}}, m);
  s.addPolygonVertices({{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}}, m);
  Camera c;
  c.width = c.height = 32;
  c.eye = {0.5f, 0.25f, 5.0f};
  RenderOptions o = options();
  o.frustum_cull = false;
  const Frame f = render(s, c, o);
  EXPECT_EQ(f.stats.degenerate_dropped, 1u);
  std::size_t second = 0;
  for (PolygonId id : f.ids) second += id == 1;
  EXPECT_GT(second, 0u);
}

HSR_INSTANTIATE_FOR_EVERY_ALGORITHM(Garbage);

}  // namespace
}  // namespace hsr
