// The narrow-triangle walk four columns at a time (raster/narrow_sse41.hpp) against the scalar
// walk, its definition: random triangles under 8 columns wide drawn in order into two frames,
// one per path, with every depth func and mask, clip boxes from the whole viewport down to a
// column, and depth planes that leave [0, 1]. The frames (colour, depth bits, ids, overdraw)
// and the fragment counts must be the same. Triangles whose edge values could leave 32 bits
// fall back to the scalar walk, and draw the same there. The span paths (raster/span.hpp:
// SSE4.1 and AVX2) against the scalar span, likewise.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <random>
#include <vector>

#include "core/random.hpp"
#include "raster/narrow_sse41.hpp"
#include "raster/span.hpp"
#include "raster/triangle.hpp"

// Built where the walk is (x86 with SSE4.1, not HSR_NO_SIMD): elsewhere there is nothing to pin.
#if defined(__SSE4_1__) && !defined(HSR_NO_SIMD)
namespace hsr::detail {
namespace {

struct Buffers {
  int width, height;
  std::vector<std::uint32_t> rgba, overdraw;
  std::vector<float> depth;
  std::vector<PolygonId> ids;
  Buffers(int w, int h, std::mt19937_64& rng)
      : width(w), height(h), rgba(w * h), overdraw(w * h), depth(w * h), ids(w * h) {
    // Stored depths of every kind the tests meet: cleared, random, 0 and 1 exactly.
    std::uniform_real_distribution<float> z(0.0f, 1.0f);
    for (std::size_t k = 0; k < depth.size(); ++k) {
      const unsigned kind = rng() % 8;
      depth[k] = kind == 0 ? 1.0f : kind == 1 ? 0.0f : z(rng);
      ids[k] = kNoPolygon;
      rgba[k] = static_cast<std::uint32_t>(rng());
      overdraw[k] = static_cast<std::uint32_t>(rng() % 4);
    }
  }
  FrameView view() {
    Frame dummy;  // FrameView is made from a Frame; point it at these buffers instead
    FrameView v(dummy);
    v.width = width;
    v.height = height;
    v.rgba = rgba.data();
    v.depth = depth.data();
    v.ids = ids.data();
    v.overdraw = overdraw.data();
    return v;
  }
  bool operator==(const Buffers& o) const {
    for (std::size_t k = 0; k < depth.size(); ++k)
      if (std::bit_cast<std::uint32_t>(depth[k]) != std::bit_cast<std::uint32_t>(o.depth[k]))
        return false;
    return rgba == o.rgba && ids == o.ids && overdraw == o.overdraw;
  }
};

// A random triangle at most `size` pixels across around a point of the viewport (or just
// outside it), with a depth plane that may leave [0, 1] inside it.
bool randomTriangle(std::mt19937_64& rng, int w, int h, int size, std::uint32_t id,
                    ScreenTriangle* t) {
  std::uniform_int_distribution<std::int64_t> cx(-4 * 256, (w + 4) * 256),
      cy(-4 * 256, (h + 4) * 256), d(-size * 128, size * 128);
  const std::int64_t x = cx(rng), y = cy(rng);
  std::int64_t fx[3], fy[3];
  for (int k = 0; k < 3; ++k) {
    fx[k] = x + d(rng);
    fy[k] = y + d(rng);
  }
  std::uniform_real_distribution<double> slope(-0.02, 0.02), z0(-0.3, 1.3);
  const DepthPlane plane{slope(rng), slope(rng), z0(rng) - 0.01 * (x / 256.0 + y / 256.0)};
  if (makeScreenTriangle(fx, fy, windowOrientation(fx, fy), w, h, plane, t) != TriangleFate::kMade)
    return false;
  t->id = id;
  t->rgba = (rng() % 6 == 0) ? 0x80102030u + id : 0xFF000000u | id;  // some transparent
  return true;
}

template <DepthFunc F>
void drawBoth(const std::vector<ScreenTriangle>& tris, const PixelBox& clip, bool mask,
              Buffers& scalar, Buffers& simd, FragmentCounts& cs, FragmentCounts& cv) {
  const RasterPath scalar_path{&fillSpanScalar<F>, false};
  const RasterPath simd_path{sse41SpanFunction(F), true};
  const FrameView a = scalar.view(), b = simd.view();
  for (const ScreenTriangle& t : tris) {
    rasterTriangle<F>(t, clip, a, mask, scalar_path, cs);
    rasterTriangle<F>(t, clip, b, mask, simd_path, cv);
  }
}

TEST(NarrowWalk, FourColumnsAtATimeIsTheScalarWalk) {
  ASSERT_TRUE(spanPathAvailable(SpanPath::kSse41));  // built with SSE4.1, so present
  std::mt19937_64 rng(46);
  constexpr int kW = 150, kH = 90;
  const PixelBox clips[] = {
      {0, 0, kW - 1, kH - 1}, {64, 0, 127, 63}, {128, 64, kW - 1, kH - 1},  {10, 5, 12, 40},
      {20, 20, 20, 80},       {5, 3, 8, 9},     {kW - 4, 0, kW - 1, kH - 1}};
  std::uint64_t tested = 0, renders = 0;
  for (int round = 0; round < 64; ++round) {
    std::vector<ScreenTriangle> tris;
    const int size = 1 + round % 9;
    for (std::uint32_t i = 0; tris.size() < 400; ++i) {
      ScreenTriangle t;
      if (randomTriangle(rng, kW, kH, size, i, &t) && t.x1 - t.x0 < kNarrowTriangleColumns)
        tris.push_back(t);
    }
    const bool mask = round % 3 != 0;
    const PixelBox& clip = clips[round % std::size(clips)];
    const auto f = static_cast<DepthFunc>(round % 8);
    Buffers scalar(kW, kH, rng);
    Buffers simd = scalar;
    FragmentCounts cs, cv;
    withDepthFunc(f, [&]<DepthFunc F>() { drawBoth<F>(tris, clip, mask, scalar, simd, cs, cv); });
    EXPECT_TRUE(scalar == simd) << "round " << round << ", depth func " << int(f);
    EXPECT_EQ(cs.tested, cv.tested) << "round " << round;
    EXPECT_EQ(cs.written, cv.written) << "round " << round;
    tested += cs.tested;
    renders++;
  }
  EXPECT_GT(tested, 10000u);  // the rounds met fragments, not only empty boxes
  EXPECT_EQ(renders, 64u);
}

TEST(NarrowWalk, EdgeValuesBeyond32BitsFallBackToTheScalarWalk) {
  ASSERT_TRUE(spanPathAvailable(SpanPath::kSse41));  // built with SSE4.1, so present
  // A sliver 6 columns wide and 8000 rows tall: its edges' steps per column are about 2^29.
  constexpr int kW = 16, kH = 8192;
  std::mt19937_64 rng(1);
  auto made = [&](const std::int64_t(&fx)[3], const std::int64_t(&fy)[3], double z, PolygonId id,
                  std::uint32_t rgba) {
    ScreenTriangle t{};
    EXPECT_EQ(
        makeScreenTriangle(fx, fy, windowOrientation(fx, fy), kW, kH, DepthPlane{0, 0, z}, &t),
        TriangleFate::kMade);
    t.id = id;
    t.rgba = rgba;
    return t;
  };
  const ScreenTriangle tall =
      made({2 * 256 + 10, 8 * 256 - 3, 5 * 256}, {5, 8000 * 256, 300}, 0.5, 1, 0xFFFFFFFFu);
  // A small one, for contrast: the four-column walk takes it.
  const ScreenTriangle small =
      made({2 * 256, 6 * 256, 4 * 256}, {2 * 256, 2 * 256, 6 * 256}, 0.25, 2, 0xFF00FF00u);
  const PixelBox clip{0, 0, kW - 1, kH - 1};
  Buffers scalar(kW, kH, rng);
  Buffers simd = scalar;
  FragmentCounts cs, cv;
  for (const ScreenTriangle* t : {&tall, &small}) {
    Buffers probe = simd;
    FragmentCounts unused;
    const bool took = rasterNarrowSse41<DepthFunc::Less>(*t, clip, t->x0, t->x1, t->y0, t->y1,
                                                         probe.view(), true, unused);
    EXPECT_EQ(took, t == &small) << "triangle " << t->id;
  }
  drawBoth<DepthFunc::Less>({tall, small}, clip, true, scalar, simd, cs, cv);
  EXPECT_TRUE(scalar == simd);
  EXPECT_EQ(cs.tested, cv.tested);
  EXPECT_GT(cs.tested, 10000u);  // the sliver drew its rows
}

// Every span path writes the scalar span's bits: random spans of 1 to 80 pixels (so every
// tail length of the four- and eight-column steps) anywhere in a row, depth planes that leave
// [0, 1], every depth func, the mask on and off, some triangles transparent, each span drawn by
// every path the processor runs into frames of its own. The frames and the counts must agree.
TEST(SpanPaths, EveryPathWritesTheScalarSpansBits) {
  std::mt19937_64 rng(4646);
  constexpr int kW = 97, kH = 40;
  std::vector<SpanPath> paths;
  for (const SpanPath p : {SpanPath::kSse41, SpanPath::kAvx2})
    if (spanPathAvailable(p)) paths.push_back(p);  // SpanPaths.TheBuildHasThePathsItSays
  ASSERT_FALSE(paths.empty());                     // SSE4.1 at least, in this build
  std::uint64_t written = 0, spans = 0;
  for (int round = 0; round < 96; ++round) {
    const auto f = static_cast<DepthFunc>(round % 8);
    const bool mask = round % 3 != 0;
    Buffers scalar(kW, kH, rng);
    std::vector<Buffers> simd(paths.size(), scalar);
    FragmentCounts cs;
    std::vector<FragmentCounts> cv(paths.size());
    std::uniform_real_distribution<double> slope(-0.01, 0.01), z0(-0.3, 1.3);
    for (std::uint32_t i = 0; i < 300; ++i) {
      ScreenTriangle t{};
      t.depth = DepthPlane{slope(rng), slope(rng), z0(rng)};
      t.id = i;
      t.rgba = (rng() % 6 == 0) ? 0x80102030u + i : 0xFF000000u | i;
      const int len = 1 + static_cast<int>(rng() % 80);
      const int x0 = static_cast<int>(rng() % static_cast<unsigned>(kW - std::min(len, kW) + 1));
      const int x1 = std::min(kW - 1, x0 + len - 1);
      const int y = static_cast<int>(rng() % kH);
      withDepthFunc(f, [&]<DepthFunc F>() {
        fillSpanScalar<F>(t, scalar.view(), y, x0, x1, mask, cs);
        for (std::size_t p = 0; p < paths.size(); ++p) {
          const SpanFn fn =
              paths[p] == SpanPath::kAvx2 ? avx2SpanFunction(F) : sse41SpanFunction(F);
          fn(t, simd[p].view(), y, x0, x1, mask, cv[p]);
        }
      });
      spans++;
    }
    for (std::size_t p = 0; p < paths.size(); ++p) {
      EXPECT_TRUE(scalar == simd[p]) << "round " << round << ", path " << int(paths[p]);
      EXPECT_EQ(cs.tested, cv[p].tested) << "round " << round << ", path " << int(paths[p]);
      EXPECT_EQ(cs.written, cv[p].written) << "round " << round << ", path " << int(paths[p]);
    }
    written += cs.written;
  }
  EXPECT_EQ(spans, 96u * 300u);
  EXPECT_GT(written, 100000u);  // the depth tests passed often, not only failed
}

// A triangle under 16 pixels each way gets its edge values straight from its vertices in 32
// bits: they are setupTriangle's, value and steps, at any pixel near it, wherever it lies
// (vertices up to 2^30 sub-pixel units, as ScreenTriangle allows); one 16 pixels across or more
// is refused.
TEST(NarrowWalk, SmallTriangleEdgesAreSetupTrianglesIn32Bits) {
  SplitMix64 rng(46);
  int compared = 0, refused = 0;
  for (int round = 0; round < 20000; ++round) {
    const std::int32_t reach = (round % 4 == 0) ? (1 << 29) : (1 << 21);
    const std::int32_t cx = static_cast<std::int32_t>(rng.next() % (2u * reach)) - reach;
    const std::int32_t cy = static_cast<std::int32_t>(rng.next() % (2u * reach)) - reach;
    const int spread = round % 8 == 7 ? 6000 : 2100;  // the last kind often spans 16 pixels or more
    ScreenTriangle t{};
    for (int k = 0; k < 3; ++k) {
      t.x[k] = cx + static_cast<std::int32_t>(rng.next() % spread);
      t.y[k] = cy + static_cast<std::int32_t>(rng.next() % spread);
    }
    // A pixel within a few of the triangle's corner, as the walk's windows are
    const int x = static_cast<int>((cx >> kSubpixelBits) - 3 + static_cast<int>(rng.next() % 12));
    const int y = static_cast<int>((cy >> kSubpixelBits) + static_cast<int>(rng.next() % 10));
    NarrowEdges e;
    const std::int32_t span_x =
        std::max({t.x[0], t.x[1], t.x[2]}) - std::min({t.x[0], t.x[1], t.x[2]});
    const std::int32_t span_y =
        std::max({t.y[0], t.y[1], t.y[2]}) - std::min({t.y[0], t.y[1], t.y[2]});
    const bool small = span_x < 16 * kSubpixelOne && span_y < 16 * kSubpixelOne;
    ASSERT_EQ(smallTriangleEdges(t, x, y, &e), small) << "round " << round;
    if (!small) {
      ++refused;
      continue;
    }
    const TriangleSetup s = setupTriangle(t, y);
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(e.value[k], s.edge[k].row + s.edge[k].step_x * x)
          << "round " << round << " edge " << k;
      ASSERT_EQ(e.step_x[k], s.edge[k].step_x) << "round " << round;
      ASSERT_EQ(e.step_y[k], s.edge[k].step_y) << "round " << round;
    }
    ++compared;
  }
  EXPECT_GT(compared, 15000);
  EXPECT_GT(refused, 500);
}

}  // namespace
}  // namespace hsr::detail
#endif
