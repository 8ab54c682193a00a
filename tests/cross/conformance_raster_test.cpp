// Conformance, docs/testing.md row 3: bit-exact coverage against an independent, deliberately naive
// reference rasterizer. The reference below shares no code with src/: it snaps window
// coordinates itself (as docs/algorithms.md describes: pixel centres at integers, 8 sub-pixel
// bits, round to nearest, y flipped so row 0 is the top), then tests EVERY pixel centre of the
// image against the three edge lines with the fill rule, in 128-bit integers.
//
// Vertices lie on the 1/16-pixel grid, so 28.4 and 24.8 fixed point describe the same points
// (a 1/16 step is exactly 16/256); the pixel camera maps world x,y to window x,y exactly.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using testing::pixelCamera;
using testing::Rng;

constexpr int kSize = 256;  // the image every case is rendered at

// A triangle in GL window coordinates (y up, origin bottom-left), in 1/16-pixel units.
struct GridTri {
  std::int64_t x[3], y[3];
};

std::string describe(const GridTri& t) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "(%g,%g) (%g,%g) (%g,%g) [window px, y up]", t.x[0] / 16.0,
                t.y[0] / 16.0, t.x[1] / 16.0, t.y[1] / 16.0, t.x[2] / 16.0, t.y[2] / 16.0);
  return buf;
}

// ---------------------------------------------------------------------------------------------
// The reference. Naive on purpose: no bounding box, no incremental stepping, no bias trick.

struct RefVertex {
  __int128 x, y;  // 24.8, y down, measured from pixel centres
};

RefVertex refSnap(double x_up, double y_up, int height) {
  // Window y down = height - y up; the pixel centre (i + 0.5, j + 0.5) becomes (i, j).
  const double xd = x_up - 0.5;
  const double yd = (height - y_up) - 0.5;
  return {static_cast<__int128>(std::lrint(xd * 256.0)),
          static_cast<__int128>(std::lrint(yd * 256.0))};
}

// Coverage of one triangle: cov[row * width + col] = 1 where the pixel centre is inside.
// Returns false (and leaves cov untouched) for a triangle of zero area.
bool refCoverage(const GridTri& t, int width, int height, std::vector<std::uint8_t>& cov) {
  RefVertex v[3];
  for (int k = 0; k < 3; ++k) v[k] = refSnap(t.x[k] / 16.0, t.y[k] / 16.0, height);
  const __int128 area2 =
      (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[1].y - v[0].y) * (v[2].x - v[0].x);
  if (area2 == 0) return false;
  // For each edge a->b (third vertex c): an inward normal n (n . (c - a) > 0), and whether the
  // edge owns the pixel centres on it: a horizontal edge with the interior above it in the
  // image (n points to -y in y-down space; in GL's y-up window, the triangle's bottom edge, as
  // llvmpipe decides for a window-system buffer), or a "left" edge (interior to its right: n
  // points to +x).
  struct Edge {
    __int128 ax, ay, nx, ny;
    bool owns_boundary;
  } e[3];
  for (int k = 0; k < 3; ++k) {
    const RefVertex a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
    __int128 nx = -(b.y - a.y), ny = b.x - a.x;
    if (nx * (c.x - a.x) + ny * (c.y - a.y) < 0) {
      nx = -nx;
      ny = -ny;
    }
    const bool horizontal_owner = ny < 0 && nx == 0;
    const bool left = nx > 0;
    e[k] = {a.x, a.y, nx, ny, horizontal_owner || left};
  }
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      const __int128 px = static_cast<__int128>(col) * 256, py = static_cast<__int128>(row) * 256;
      bool inside = true;
      for (const Edge& ed : e) {
        const __int128 s = ed.nx * (px - ed.ax) + ed.ny * (py - ed.ay);
        if (s < 0 || (s == 0 && !ed.owns_boundary)) inside = false;
      }
      if (inside) cov[static_cast<std::size_t>(row) * width + col] = 1;
    }
  }
  return true;
}

// ---------------------------------------------------------------------------------------------
// Rendering through hsr.

// One object per triangle (z = 0, facing the camera either way), no culling, depth test off
// where the algorithm has one to turn off (no two triangles of a batch share a pixel, so for
// the others, LESS-only, the test makes no difference).
void renderTris(const std::vector<GridTri>& tris, const std::string& algorithm, Frame& frame) {
  Scene scene;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const GridTri& t = tris[i];
    scene.addPolygonVertices({glm::vec3(float(t.x[0]) / 16.0f, float(t.y[0]) / 16.0f, 0.0f),
                              glm::vec3(float(t.x[1]) / 16.0f, float(t.y[1]) / 16.0f, 0.0f),
                              glm::vec3(float(t.x[2]) / 16.0f, float(t.y[2]) / 16.0f, 0.0f)},
                             0);
  }
  scene.addMaterial({});
  RenderOptions o = testing::optionsFor(algorithm);
  if (findAlgorithm(algorithm).has(kDepthFuncs)) o.depth_test = false;
  o.cull = CullMode::None;
  o.frustum_cull = false;
  o.shade = false;
  render(scene, pixelCamera(kSize, kSize), o, frame);
}

struct Totals {
  std::uint64_t triangles = 0, ccw = 0, cw = 0, pixels_compared = 0, pixels_covered = 0;
  std::uint64_t differing = 0;
};

// What a test's batches reuse: the reference's images and hsr's frame (rendered into again, so
// that a suite of thousands of renders maps no fresh memory: under the sanitizers every buffer
// over 128 KiB is mapped and its pages faulted in afresh, which was a third of this suite's time).
struct BatchBuffers {
  std::vector<PolygonId> ref;
  std::vector<std::uint8_t> cov;
  Frame frame;
};

// Renders a batch of triangles whose pixel sets are disjoint and compares the whole image
// pixel by pixel with the reference's id image. Returns the number of differing pixels.
std::uint64_t compareBatch(const std::string& algorithm, const std::vector<GridTri>& tris,
                           Totals& tot, const std::string& ctx, int* reports_left,
                           BatchBuffers& buffers) {
  std::vector<PolygonId>& ref = buffers.ref;
  std::vector<std::uint8_t>& cov = buffers.cov;
  ref.assign(static_cast<std::size_t>(kSize) * kSize, kNoPolygon);
  cov.resize(ref.size());
  for (std::size_t i = 0; i < tris.size(); ++i) {
    std::fill(cov.begin(), cov.end(), 0);
    const GridTri& t = tris[i];
    const std::int64_t a =
        (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.y[1] - t.y[0]) * (t.x[2] - t.x[0]);
    (a > 0 ? tot.ccw : tot.cw)++;
    tot.triangles++;
    if (!refCoverage(t, kSize, kSize, cov)) continue;
    for (std::size_t k = 0; k < cov.size(); ++k) {
      if (!cov[k]) continue;
      // The batches are built so no two triangles can reach the same pixel centre.
      EXPECT_EQ(ref[k], kNoPolygon) << ctx << ": batch construction error";
      ref[k] = static_cast<PolygonId>(i);
    }
  }
  renderTris(tris, algorithm, buffers.frame);
  const Frame& f = buffers.frame;
  std::uint64_t diff = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    tot.pixels_compared++;
    if (ref[k] != kNoPolygon) tot.pixels_covered++;
    if (f.ids[k] == ref[k]) continue;
    diff++;
    if (*reports_left > 0) {
      --*reports_left;
      const int row = static_cast<int>(k / kSize), col = static_cast<int>(k % kSize);
      const PolygonId who = ref[k] != kNoPolygon ? ref[k] : f.ids[k];
      ADD_FAILURE() << ctx << ": pixel col " << col << " row " << row << " (GL y "
                    << (kSize - 1 - row) << "): hsr id " << static_cast<long long>(f.ids[k])
                    << ", reference id " << static_cast<long long>(ref[k]) << "; triangle "
                    << (who < tris.size() ? describe(tris[who]) : std::string("?"));
    }
  }
  tot.differing += diff;
  return diff;
}

// ---------------------------------------------------------------------------------------------

// The reference itself, on cases worked out by hand (so that it is not merely self-consistent).
TEST(ConformanceReference, HandWorkedCases) {
  constexpr int W = 8, H = 8;
  std::vector<std::uint8_t> cov(W * H);
  auto count = [&] {
    int n = 0;
    for (std::uint8_t c : cov) n += c;
    return n;
  };
  auto at = [&](int col, int gl_y) {
    return cov[static_cast<std::size_t>(H - 1 - gl_y) * W + col];
  };
  // A 4x4 square of pixel centres: (0.5..3.5) x (0.5..3.5) split along the diagonal. The lower
  // triangle's left edge (x = 0.5) and its bottom edge (y = 0.5 in GL: the interior lies above
  // it) own their centres; its hypotenuse x + y = 4 runs on the right, and does not.
  GridTri lower{{8, 56, 8}, {8, 8, 56}};  // (0.5,0.5) (3.5,0.5) (0.5,3.5)
  std::fill(cov.begin(), cov.end(), 0);
  ASSERT_TRUE(refCoverage(lower, W, H, cov));
  // Centres (x, y) with x >= 0.5, y >= 0.5, x + y < 4:
  // (0.5,0.5) (0.5,1.5) (0.5,2.5) (1.5,0.5) (1.5,1.5) (2.5,0.5).
  EXPECT_EQ(count(), 6);
  EXPECT_EQ(at(0, 0), 1);
  EXPECT_EQ(at(0, 2), 1);
  EXPECT_EQ(at(2, 0), 1);
  GridTri upper{{56, 56, 8}, {8, 56, 56}};  // (3.5,0.5) (3.5,3.5) (0.5,3.5): top edge y = 3.5
  std::fill(cov.begin(), cov.end(), 0);
  ASSERT_TRUE(refCoverage(upper, W, H, cov));
  // Centres with x < 3.5 (right edge: excluded on it), y < 3.5 (top edge, interior below it
  // in GL: excluded), x + y >= 4 (the hypotenuse is a left edge of this one: included):
  // (1.5,2.5) (2.5,1.5) (2.5,2.5).
  EXPECT_EQ(count(), 3);
  // The two halves cover the 16 centres of the square exactly once minus the ones they both
  // exclude: top row y = 3.5 and right column x = 3.5 (7 centres) -> 9 = 6 + 3.
  EXPECT_EQ(at(0, 3), 0);
  EXPECT_EQ(at(2, 1), 1);
  EXPECT_EQ(at(3, 3), 0);
}

// 4 triangles x 9 shifts of (-1/16, 0, +1/16) px in x and y, each in both windings.
class ConformanceRaster : public testing::EveryAlgorithm {};

TEST_P(ConformanceRaster, FixedCasesBitExact) {
  // In 1/16 px, GL y up: (0) a left edge and a bottom edge through rows/columns of pixel
  // centres, (1) a top edge and a right edge through pixel centres (so the fill rule decides
  // on whole rows and columns), (2) a slope-1 sliver whose long edge runs through centres,
  // (3) a big triangle with vertices off the half-pixel lattice.
  const GridTri base[4] = {
      {{10 * 16 + 8, 40 * 16 + 8, 10 * 16 + 8}, {10 * 16 + 8, 10 * 16 + 8, 40 * 16 + 8}},
      {{100 * 16 + 8, 130 * 16 + 8, 130 * 16 + 8}, {60 * 16 + 8, 60 * 16 + 8, 20 * 16 + 8}},
      {{150 * 16 + 8, 200 * 16 + 8, 150 * 16 + 8}, {150 * 16 + 8, 200 * 16 + 8, 152 * 16 + 8}},
      {{3 * 16 + 8, 250 * 16 + 8, 128 * 16 + 3}, {250 * 16 + 8, 5 * 16 + 8, 128 * 16 + 13}},
  };
  Totals tot;
  int reports_left = 20;
  BatchBuffers buffers;
  for (int i = 0; i < 4; ++i) {
    for (int sy = -1; sy <= 1; ++sy) {
      for (int sx = -1; sx <= 1; ++sx) {
        GridTri t = base[i];
        for (int k = 0; k < 3; ++k) {
          t.x[k] += sx;
          t.y[k] += sy;
        }
        GridTri r = t;  // the other winding
        std::swap(r.x[1], r.x[2]);
        std::swap(r.y[1], r.y[2]);
        const std::string ctx = "fixed case " + std::to_string(i) + " shift (" +
                                std::to_string(sx) + "/16, " + std::to_string(sy) + "/16)";
        compareBatch(GetParam(), {t}, tot, ctx, &reports_left, buffers);
        compareBatch(GetParam(), {r}, tot, ctx + " reversed", &reports_left, buffers);
      }
    }
  }
  std::printf(
      "[conformance raster] fixed: %llu triangles (%llu ccw, %llu cw), %llu pixels "
      "compared, %llu covered, %llu differing\n",
      (unsigned long long)tot.triangles, (unsigned long long)tot.ccw, (unsigned long long)tot.cw,
      (unsigned long long)tot.pixels_compared, (unsigned long long)tot.pixels_covered,
      (unsigned long long)tot.differing);
  EXPECT_EQ(tot.triangles, 72u);
  EXPECT_EQ(tot.differing, 0u);
}

// 10,000 random triangles (x intensity), sizes 2^k px for k = 0..8, vertices on the 1/16 grid,
// random winding. Triangles of one size are batched into disjoint square cells of the 256x256
// image (a cell of side C >= 2^k holds one triangle; pixel centres never lie on cell borders,
// so no two triangles can share a pixel).
// In the sanitizer leg's tier (testing::legCases) a quarter of them (the largest size alone
// renders a frame per triangle); Release compares all 10,000.
const int kRandomTriangles = testing::legCases(10000, 4);

TEST_P(ConformanceRaster, RandomTrianglesBitExact) {
  const std::uint64_t seed = 0x5EED0003ull;
  Rng rng(seed);
  const int total = kRandomTriangles * testing::countScale();
  Totals tot;
  int reports_left = 20;
  std::uint64_t degenerate_skipped = 0;
  BatchBuffers buffers;
  for (int k = 0; k <= 8; ++k) {
    const int size = 1 << k;
    const int cell = std::max(size, 16);
    const int per_row = kSize / cell;
    const int per_batch = per_row * per_row;
    const int count = total / 9 + (k < total % 9 ? 1 : 0);
    int made = 0;
    while (made < count) {
      std::vector<GridTri> batch;
      while (static_cast<int>(batch.size()) < per_batch && made < count) {
        const int c = static_cast<int>(batch.size());
        const std::int64_t cx = std::int64_t(c % per_row) * cell * 16;
        const std::int64_t cy = std::int64_t(c / per_row) * cell * 16;
        // Origin so that the size x size box stays in the cell, then vertices in the box.
        const std::int64_t slack = std::int64_t(cell - size) * 16;
        const std::int64_t ox = cx + static_cast<std::int64_t>(rng.next() % (slack + 1));
        const std::int64_t oy = cy + static_cast<std::int64_t>(rng.next() % (slack + 1));
        GridTri t;
        for (int v = 0; v < 3; ++v) {
          t.x[v] = ox + static_cast<std::int64_t>(rng.next() % (size * 16 + 1));
          t.y[v] = oy + static_cast<std::int64_t>(rng.next() % (size * 16 + 1));
        }
        const std::int64_t a =
            (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.y[1] - t.y[0]) * (t.x[2] - t.x[0]);
        if (a == 0) {
          degenerate_skipped++;
          continue;  // zero area: draws nothing (row 14's business); draw another
        }
        batch.push_back(t);
        made++;
      }
      const std::string ctx = "seed " + std::to_string(seed) + ", size 2^" + std::to_string(k);
      compareBatch(GetParam(), batch, tot, ctx, &reports_left, buffers);
    }
  }
  std::printf(
      "[conformance raster] random (seed %llu): %llu triangles (%llu ccw, %llu cw; "
      "%llu zero-area redrawn), %llu pixels compared, %llu covered, %llu differing\n",
      (unsigned long long)seed, (unsigned long long)tot.triangles, (unsigned long long)tot.ccw,
      (unsigned long long)tot.cw, (unsigned long long)degenerate_skipped,
      (unsigned long long)tot.pixels_compared, (unsigned long long)tot.pixels_covered,
      (unsigned long long)tot.differing);
  EXPECT_EQ(tot.triangles, static_cast<std::uint64_t>(total));
  EXPECT_GT(tot.ccw, 0u);
  EXPECT_GT(tot.cw, 0u);
  EXPECT_EQ(tot.differing, 0u) << "seed " << seed;
}

HSR_INSTANTIATE_FOR_ALGORITHMS_WITH(ConformanceRaster, kExactSharedCoverage);

}  // namespace
}  // namespace hsr
