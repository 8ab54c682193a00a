// docs/testing.md row 14: the degenerate geometry catalogue. One named test per case, each stating
// the documented behaviour and running it on every registered algorithm (hsr::algorithms()),
// so that a new algorithm is held to the same rules with no test change.
//
// Coverage is judged against a naive exact reference written here, sharing no code with src/:
// vertices on the 1/256-pixel grid (where the pixel camera maps world x,y to window x,y
// exactly and 24.8 snapping changes nothing), every pixel centre tested against the three
// edges in 128-bit integers with the fill rule. Cases that cannot be exact (clipping
// at 1e6 px and beyond) say which margin they use. Fragments are counted with the depth test
// off, so Frame::overdraw holds every fragment each triangle wrote.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using testing::pixelCamera;
using testing::Rng;

std::vector<const AlgorithmInfo*> lessOnlyAlgorithms();

// "[ figures ]" for the README's Reliability table: Degenerate tests run and passed.
[[maybe_unused]] ::testing::Environment* const kFigures = testing::printFiguresAtEnd([] {
  const testing::SuiteTally t = testing::tallySuite("Degenerate");
  if (t.run == 0) return;
  std::string names;
  const auto applicable = testing::algorithmsWith("Degenerate", kExactSharedCoverage | kDepthFuncs);
  for (const AlgorithmInfo* a : applicable)
    names += (names.empty() ? "" : ", ") + std::string(a->name);
  std::string less_only;
  for (const AlgorithmInfo* a : lessOnlyAlgorithms())
    less_only += (less_only.empty() ? "" : ", ") + std::string(a->name);
  std::printf(
      "[ figures ] row 14 degenerate catalogue: %d cases run, %d passed, each on %zu "
      "algorithm(s) (%s) and, held to the z-buffer's frame with LESS, on %s\n",
      t.run, t.passed, applicable.size(), names.c_str(), less_only.c_str());
});

constexpr int kSize = 256;  // most cases render at kSize x kSize with the pixel camera

// ---------------------------------------------------------------------------------------------
// The exact reference

// A triangle in GL window coordinates (y up, origin bottom-left), in pixels.
using Tri = std::array<glm::dvec2, 3>;

// A point on the 1/256-pixel grid, from integer grid units.
glm::dvec2 grid(std::int64_t x, std::int64_t y) { return {x / 256.0, y / 256.0}; }

// Adds 1 to count[row * width + col] for every pixel centre the triangle covers by the fill
// rule (raster/edge.hpp); returns false for a triangle of zero area (which covers nothing). The
// vertices must lie on the 1/256 grid (checked).
bool addCoverage(const Tri& t, int width, int height, std::vector<int>& count) {
  struct V {
    __int128 x, y;  // 24.8, y down, measured from pixel centres
  } v[3];
  for (int k = 0; k < 3; ++k) {
    const double gx = t[k].x * 256.0, gy = (height - t[k].y) * 256.0;
    EXPECT_TRUE(gx == std::floor(gx) && gy == std::floor(gy)) << "off the grid: test bug";
    v[k] = {static_cast<__int128>(gx) - 128, static_cast<__int128>(gy) - 128};
  }
  const __int128 area2 =
      (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[1].y - v[0].y) * (v[2].x - v[0].x);
  if (area2 == 0) return false;
  struct Edge {
    __int128 ax, ay, nx, ny;
    bool owns;  // a horizontal edge with the inside above it (y down), or a left edge
  } e[3];
  for (int k = 0; k < 3; ++k) {
    const V a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
    __int128 nx = -(b.y - a.y), ny = b.x - a.x;  // a normal; made to point inside
    if (nx * (c.x - a.x) + ny * (c.y - a.y) < 0) nx = -nx, ny = -ny;
    e[k] = {a.x, a.y, nx, ny, (ny < 0 && nx == 0) || nx > 0};
  }
  double lo_x = 1e300, hi_x = -1e300, lo_y = 1e300, hi_y = -1e300;
  for (const glm::dvec2& p : t) {
    lo_x = std::min(lo_x, p.x), hi_x = std::max(hi_x, p.x);
    lo_y = std::min(lo_y, p.y), hi_y = std::max(hi_y, p.y);
  }
  const int c0 = std::max(0, static_cast<int>(std::floor(lo_x)) - 1);
  const int c1 = std::min(width - 1, static_cast<int>(std::ceil(hi_x)) + 1);
  const int r0 = std::max(0, height - 2 - static_cast<int>(std::ceil(hi_y)));
  const int r1 = std::min(height - 1, height - static_cast<int>(std::floor(lo_y)) + 1);
  for (int row = r0; row <= r1; ++row) {
    for (int col = c0; col <= c1; ++col) {
      const __int128 px = __int128(col) * 256, py = __int128(row) * 256;
      bool inside = true;
      for (const Edge& ed : e) {
        const __int128 s = ed.nx * (px - ed.ax) + ed.ny * (py - ed.ay);
        if (s < 0 || (s == 0 && !ed.owns)) inside = false;
      }
      if (inside) count[static_cast<std::size_t>(row) * width + col]++;
    }
  }
  return true;
}

// Margin test on a triangle in GL window coordinates, for cases that are not on the grid:
// +1 when (x, y) is inside by more than `margin` pixels, -1 outside by more, 0 too close to call.
int classify(Tri t, glm::dvec2 p, double margin) {
  const double area = (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[1].y - t[0].y) * (t[2].x - t[0].x);
  if (area < 0) std::swap(t[1], t[2]);
  double d = 1e300;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec2 a = t[k], e = t[(k + 1) % 3] - t[k];
    d = std::min(d, (e.x * (p.y - a.y) - e.y * (p.x - a.x)) / std::hypot(e.x, e.y));
  }
  return d > margin ? 1 : (d < -margin ? -1 : 0);
}

// ---------------------------------------------------------------------------------------------
// Scenes and rendering

// One object of flat triangles at height z, in the given order (polygon id = index).
Scene flatScene(const std::vector<Tri>& tris, float z = 0.0f) {
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  s.beginObject("flat");
  for (const Tri& t : tris)
    s.addPolygonVertices(
        {glm::vec3(float(t[0].x), float(t[0].y), z), glm::vec3(float(t[1].x), float(t[1].y), z),
         glm::vec3(float(t[2].x), float(t[2].y), z)},
        m);
  return s;
}

// Every fragment counts (depth test off), nothing culled, flat colour.
RenderOptions countEveryFragment() {
  RenderOptions o;
  o.depth_test = false;
  o.frustum_cull = false;
  o.cull = CullMode::None;
  o.shade = false;
  return o;
}

// The algorithms with exact shared coverage but the depth test LESS alone (scan-line, Warnock,
// the octree): they cannot count every fragment, so each degenerate scene is drawn by them with
// LESS and must equal the z-buffer's frame drawn so, bit for bit (ids, depths, colours).
std::vector<const AlgorithmInfo*> lessOnlyAlgorithms() {
  std::vector<const AlgorithmInfo*> out;
  for (const AlgorithmInfo* a :
       testing::algorithmsWith("Degenerate, LESS only", kExactSharedCoverage))
    if (!a->has(kDepthFuncs)) out.push_back(a);
  return out;
}

// Runs `check` on the frame of every registered algorithm this catalogue applies to: its
// expectations are exact pixel coverage and counts (drawn with the depth test off). Then the
// LESS-only algorithms draw the same scene with LESS and are held to the z-buffer's frame.
// The frames are rendered into again from case to case (one per thread, the reference's apart):
// the suite's thousands of renders then map no fresh memory, which under the sanitizers (every
// buffer over 128 KiB mapped and faulted in afresh) was half of its time.
template <class Check>
void forEachAlgorithm(const Scene& scene, const Camera& camera, RenderOptions options,
                      Check check) {
  thread_local Frame f, reference;
  for (const AlgorithmInfo* ap :
       testing::algorithmsWith("Degenerate", kExactSharedCoverage | kDepthFuncs)) {
    const AlgorithmInfo& a = *ap;
    SCOPED_TRACE("algorithm " + std::string(a.name));
    options.algorithm = std::string(a.name);
    render(scene, camera, options, f);
    check(std::as_const(f));
  }
  options.depth_test = true;
  options.depth_func = DepthFunc::Less;
  options.depth_mask = true;
  options.algorithm = "zbuffer";
  render(scene, camera, options, reference);
  for (const AlgorithmInfo* ap : lessOnlyAlgorithms()) {
    if (!unsupported(*ap, camera, options).empty()) continue;  // a line mode or outline case
    SCOPED_TRACE("algorithm " + std::string(ap->name) + " (LESS, against the z-buffer)");
    options.algorithm = std::string(ap->name);
    testing::sampleAtCentres(options);
    render(scene, camera, options, f);
    EXPECT_EQ(f.stats.degenerate_dropped, reference.stats.degenerate_dropped);
    std::size_t differ = 0, first = f.ids.size();
    for (std::size_t k = 0; k < f.ids.size(); ++k)
      if (f.ids[k] != reference.ids[k] && differ++ == 0) first = k;
    EXPECT_EQ(differ, 0u) << "pixels whose id differs from the z-buffer's; first at " << first
                          << ": " << (differ ? f.ids[first] : 0) << " against "
                          << (differ ? reference.ids[first] : 0);
    EXPECT_TRUE(f.depth == reference.depth) << "depths differ from the z-buffer's";
    EXPECT_TRUE(f.color == reference.color) << "colours differ from the z-buffer's";
  }
}

// Compares every pixel's fragment count with the reference's; reports the first few misses.
std::uint64_t expectCounts(const Frame& f, const std::vector<int>& want, const std::string& what) {
  std::uint64_t bad = 0;
  for (std::size_t k = 0; k < want.size(); ++k) {
    if (static_cast<int>(f.overdraw[k]) == want[k]) continue;
    if (++bad <= 5)
      ADD_FAILURE() << what << ": pixel col " << k % f.width << " GL y "
                    << (f.height - 1 - static_cast<int>(k / f.width)) << " written "
                    << f.overdraw[k] << " times, the exact reference says " << want[k];
  }
  return bad;
}

// Every depth value finite and in [0, 1] (no NaN reached the buffers); ids in range.
void expectSaneBuffers(const Frame& f, std::size_t polygons) {
  for (std::size_t k = 0; k < f.depth.size(); ++k) {
    ASSERT_TRUE(std::isfinite(f.depth[k]) && f.depth[k] >= 0.0f && f.depth[k] <= 1.0f)
        << "depth " << f.depth[k] << " at " << k;
    ASSERT_TRUE(f.ids[k] == kNoPolygon || f.ids[k] < polygons) << "id " << f.ids[k];
  }
}

std::size_t drawnBy(const Frame& f, PolygonId id) {
  return static_cast<std::size_t>(std::count(f.ids.begin(), f.ids.end(), id));
}

// A random integer in [lo, hi].
std::int64_t randInt(Rng& rng, std::int64_t lo, std::int64_t hi) {
  return lo + static_cast<std::int64_t>(rng.next() % static_cast<std::uint64_t>(hi - lo + 1));
}

// ---------------------------------------------------------------------------------------------
// Zero area

// Documented: a polygon whose vertices are collinear in world space has zero area. It is
// dropped before rasterization and its n - 2 triangles are counted in
// Stats::degenerate_dropped; it draws 0 pixels in every polygon mode and cull mode. A normal
// triangle beside them draws as usual.
TEST(Degenerate, ZeroAreaCollinearTrianglesDrawNothingAndAreCounted) {
  const int seeds = 3 * testing::countScale();
  std::uint64_t polygons = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    SCOPED_TRACE("collinear seed " + std::to_string(seed));
    Rng rng(0xC011'0000u + static_cast<std::uint64_t>(seed));
    Scene s;
    const std::uint32_t m = s.addMaterial({});
    s.addPolygonVertices({{10, 10, 0}, {60, 10, 0}, {10, 60, 0}}, m);  // id 0: the control
    std::uint32_t dropped = 0;
    for (int i = 0; i < 200; ++i) {
      // a + t d for integer t, with a and d on the 1/256 grid: exactly collinear in float
      const glm::vec3 a(randInt(rng, 2048, 63488) / 256.0f, randInt(rng, 2048, 63488) / 256.0f,
                        randInt(rng, -1024, 1024) / 256.0f);
      glm::vec3 d(randInt(rng, -4096, 4096) / 256.0f, randInt(rng, -4096, 4096) / 256.0f,
                  randInt(rng, -256, 256) / 256.0f);
      switch (i % 5) {
        case 0:
          d.y = d.z = 0;
          break;  // along a row
        case 1:
          d.x = d.z = 0;
          break;  // along a column
        case 2:
          d = glm::vec3(1, 1, 0);
          break;  // diagonal through pixel centres
        default:
          break;  // anywhere, also in depth
      }
      const int n = (i % 7 == 0) ? 5 : 3;  // some collinear pentagons
      std::vector<glm::vec3> pts;
      for (int k = 0; k < n; ++k) pts.push_back(a + float(randInt(rng, -3, 3)) * d);
      s.addPolygonVertices(pts, m);
      dropped += n - 2;  // triangles
      ++polygons;
    }
    for (PolygonMode mode : {PolygonMode::Fill, PolygonMode::Line, PolygonMode::Point}) {
      for (CullMode cull : {CullMode::None, CullMode::Back}) {
        RenderOptions o;
        o.polygon_mode = mode;
        o.cull = cull;
        forEachAlgorithm(s, pixelCamera(kSize, kSize), o, [&](const Frame& f) {
          EXPECT_EQ(f.stats.degenerate_dropped, dropped);
          EXPECT_GT(drawnBy(f, 0), 0u);
          EXPECT_EQ(drawnBy(f, 0) + drawnBy(f, kNoPolygon), f.ids.size())
              << "a collinear polygon drew pixels";
        });
      }
    }
  }
  std::printf("degenerate: %llu collinear polygons, all dropped and counted\n",
              static_cast<unsigned long long>(polygons));
}

// Documented: a polygon whose vertices repeat (the same position twice, or the same index)
// so that it spans no area is dropped and counted like a collinear one (its n - 2 triangles),
// drawing 0 pixels. A polygon with a repeated vertex that still spans an area is NOT
// degenerate: it draws exactly the pixels of the area it spans; the zero-width corner at the
// repeated vertex is the one triangle of it counted in degenerate_dropped.
TEST(Degenerate, ZeroAreaRepeatedVertexTrianglesDrawNothingAndAreCounted) {
  Rng rng(0x5EED'0002u);
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  s.beginObject("repeats");
  std::uint32_t zero_area = 0;  // triangles
  std::vector<Tri> spanning;    // the triangles that the non-degenerate polygons span
  for (int i = 0; i < 100 * testing::countScale(); ++i) {
    const auto point = [&] {
      return glm::vec3(randInt(rng, 256, 65280) / 256.0f, randInt(rng, 256, 65280) / 256.0f,
                       randInt(rng, -512, 512) / 256.0f);
    };
    const glm::vec3 a = point(), b = point(), c = point();
    const std::uint32_t ia = s.addVertex(a), ib = s.addVertex(b), ic = s.addVertex(c);
    const std::uint32_t ia2 = s.addVertex(a);  // same position, another index
    switch (i % 8) {
      case 0:
        s.addPolygon({ia, ia2, ib}, m);
        break;  // two corners at one position
      case 1:
        s.addPolygon({ia, ib, ia2}, m);
        break;
      case 2:
        s.addPolygon({ia, ia, ib}, m);
        break;  // the same index twice
      case 3:
        s.addPolygon({ia, ia2, ia}, m);
        break;  // all three at one position
      case 4:
        s.addPolygon({ia, ib, ia2, ib}, m);
        break;  // a quad folded onto a segment
      case 5:
        s.addPolygon({ia, ia2, ib, ib}, m);
        break;
      default: {
        // a quad with one repeated corner that still spans the triangle (a, b, c)
        if (i % 8 == 6)
          s.addPolygon({ia, ib, ib, ic}, m);
        else
          s.addPolygon({ia, ia2, ib, ic}, m);
        spanning.push_back({glm::dvec2(a.x, a.y), glm::dvec2(b.x, b.y), glm::dvec2(c.x, c.y)});
        ++zero_area;  // its zero-width corner
        continue;
      }
    }
    zero_area += (i % 8 == 4 || i % 8 == 5) ? 2 : 1;
  }
  // Fragments of the spanning quads, which may overlap one another: exact reference sums
  std::vector<int> want(static_cast<std::size_t>(kSize) * kSize, 0);
  for (const Tri& t : spanning) addCoverage(t, kSize, kSize, want);
  forEachAlgorithm(s, pixelCamera(kSize, kSize), countEveryFragment(), [&](const Frame& f) {
    EXPECT_EQ(f.stats.degenerate_dropped, zero_area);
    EXPECT_EQ(expectCounts(f, want, "repeated vertices"), 0u);
  });
}

// Documented: a triangle with positive area in world space whose plane contains the view
// direction is seen edge-on: its window-space area is 0 after snapping, so it draws 0 pixels,
// as in OpenGL. It is valid geometry, so it is NOT counted in degenerate_dropped.
TEST(Degenerate, EdgeOnTrianglesDrawNothingAndAreNotCountedAsDegenerate) {
  Rng rng(0xED6E'0003u);
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  for (int i = 0; i < 200; ++i) {
    // Collinear in x,y (exactly, on the grid), spread in z: a vertical plane seen edge-on by
    // the pixel camera, which looks straight down -z
    const glm::vec2 a(randInt(rng, 2048, 63488) / 256.0f, randInt(rng, 2048, 63488) / 256.0f);
    glm::vec2 d(randInt(rng, -2048, 2048) / 256.0f, randInt(rng, -2048, 2048) / 256.0f);
    if (i % 3 == 0) d = glm::vec2(0, 1);
    if (i % 3 == 1) d = glm::vec2(1, 0);
    const float t1 = float(randInt(rng, 1, 3)), t2 = float(randInt(rng, -3, -1));
    // z = 0, 2, 3 at t = 0, t1 > 0, t2 < 0: never linear in t, so never collinear in 3D
    s.addPolygonVertices(
        {glm::vec3(a, 0.0f), glm::vec3(a + t1 * d, 2.0f), glm::vec3(a + t2 * d, 3.0f)}, m);
  }
  for (FacingTest facing : {FacingTest::WindowArea, FacingTest::EyePlane}) {
    RenderOptions o;
    o.facing_test = facing;
    forEachAlgorithm(s, pixelCamera(kSize, kSize), o, [&](const Frame& f) {
      EXPECT_EQ(f.stats.degenerate_dropped, 0u);
      EXPECT_EQ(drawnBy(f, kNoPolygon), f.ids.size()) << "an edge-on triangle drew pixels";
    });
  }
}

// ---------------------------------------------------------------------------------------------
// Needles and sub-pixel triangles

// Extended Euclid: x, y with a x + b y = gcd(a, b) (returned).
std::int64_t extendedGcd(std::int64_t a, std::int64_t b, std::int64_t* x, std::int64_t* y) {
  if (b == 0) {
    *x = a >= 0 ? 1 : -1;
    *y = 0;
    return std::llabs(a);
  }
  std::int64_t x1, y1;
  const std::int64_t g = extendedGcd(b, a % b, &x1, &y1);
  *x = y1;
  *y = x1 - (a / b) * y1;
  return g;
}

// Documented: a needle (aspect ratio, longest side over height, of 1e5 to 1e8 here) draws
// exactly the pixel centres inside it by the fill rule: no more, no fewer, never a
// crash. Random needles on the grid (most cover few centres), plus needles whose long edge
// runs exactly through a row, a column or a diagonal of pixel centres, so the fill rule
// decides every centre on it.
TEST(Degenerate, NeedleTrianglesDrawExactlyTheCentresInside) {
  const int scenes = 4 * testing::countScale();
  std::uint64_t needles = 0, covered = 0, at_least_1e6 = 0;
  double min_aspect = 1e300, max_aspect = 0;
  for (int n = 0; n < scenes; ++n) {
    SCOPED_TRACE("needle scene seed " + std::to_string(n));
    Rng rng(0x0EED'1E00u + static_cast<std::uint64_t>(n));
    std::vector<Tri> tris;
    for (int i = 0; i < 60; ++i) {
      const double len = 40.0 + rng.uniform(0.0f, 180.0f);  // pixels
      const double angle = rng.uniform(0.0f, 6.2831853f);
      // Direction (p, q) in grid units, coprime so the lattice comes as close to the line as
      // it can; the apex's cross product with it is exactly m, giving aspect len^2 * 65536 / m
      std::int64_t p = std::llround(len * 256.0 * std::cos(angle));
      const std::int64_t q = std::llround(len * 256.0 * std::sin(angle));
      std::int64_t x, y;
      while (extendedGcd(p, q, &x, &y) != 1) ++p;
      const double aspect_target = std::pow(10.0, rng.uniform(5.0f, 8.0f));
      const std::int64_t m =
          std::max<std::int64_t>(1, std::llround(double(p * p + q * q) / aspect_target));
      // p*x + q*y = 1, so the offset (r, s) = m (-y, x) has p*s - q*r = m; slide it along the
      // needle to somewhere in its middle
      std::int64_t r = -m * y, s = m * x;
      const double along = double(r * p + s * q) / double(p * p + q * q);
      const std::int64_t k = std::llround(along - rng.uniform(0.2f, 0.8f));
      r -= k * p;
      s -= k * q;
      // Place it inside the viewport: A such that A, A + (p, q) and A + (r, s) fit
      const std::int64_t lo_x = -std::min<std::int64_t>({0, p, r}),
                         hi_x = kSize * 256 - std::max<std::int64_t>({0, p, r});
      const std::int64_t lo_y = -std::min<std::int64_t>({0, q, s}),
                         hi_y = kSize * 256 - std::max<std::int64_t>({0, q, s});
      if (lo_x >= hi_x || lo_y >= hi_y) continue;
      const std::int64_t ax = randInt(rng, lo_x, hi_x), ay = randInt(rng, lo_y, hi_y);
      Tri t{grid(ax, ay), grid(ax + p, ay + q), grid(ax + r, ay + s)};
      if (rng.next() & 1) std::swap(t[1], t[2]);  // either winding
      const double aspect = double(p * p + q * q) / double(m);
      min_aspect = std::min(min_aspect, aspect);
      max_aspect = std::max(max_aspect, aspect);
      at_least_1e6 += aspect >= 1e6;
      tris.push_back(t);
    }
    // Long edges exactly through pixel centres: a row, a column, a diagonal; the apex one
    // grid step off the line, on either side
    for (int i = 0; i < 24; ++i) {
      const std::int64_t cx = randInt(rng, 8, 120) * 256 + 128,
                         cy = randInt(rng, 8, 120) * 256 + 128;
      const std::int64_t len = randInt(rng, 40, 120) * 256;
      const std::int64_t side = (i & 1) ? 1 : -1;
      const std::int64_t mid = randInt(rng, 1, len / 256 - 1) * 256 + randInt(rng, 0, 255);
      Tri t;
      switch (i % 3) {
        case 0:
          t = {grid(cx, cy), grid(cx + len, cy), grid(cx + mid, cy + side)};
          break;
        case 1:
          t = {grid(cx, cy), grid(cx, cy + len), grid(cx + side, cy + mid)};
          break;
        default:
          t = {grid(cx, cy), grid(cx + len, cy + len), grid(cx + mid + side, cy + mid)};
          break;
      }
      if (i % 4 >= 2) std::swap(t[1], t[2]);
      tris.push_back(t);
    }
    std::vector<int> want(static_cast<std::size_t>(kSize) * kSize, 0);
    for (const Tri& t : tris) EXPECT_TRUE(addCoverage(t, kSize, kSize, want));
    needles += tris.size();
    covered += static_cast<std::uint64_t>(std::accumulate(want.begin(), want.end(), 0));
    forEachAlgorithm(flatScene(tris), pixelCamera(kSize, kSize), countEveryFragment(),
                     [&](const Frame& f) {
                       expectSaneBuffers(f, tris.size());
                       EXPECT_EQ(expectCounts(f, want, "needles"), 0u);
                     });
  }
  std::printf(
      "degenerate: %llu needles (aspect %.2g..%.2g, %llu at 1e6 or more), %llu pixel "
      "centres covered, all exactly as the reference\n",
      static_cast<unsigned long long>(needles), min_aspect, max_aspect,
      static_cast<unsigned long long>(at_least_1e6), static_cast<unsigned long long>(covered));
}

// Documented: a needle a million pixels long and one pixel wide (aspect 1e6), crossing the
// viewport, is clipped in homogeneous coordinates and drawn at every pixel centre inside it
// and at none outside. Clipping in float moves the clipped vertices off the exact edge by up
// to about 4e-8 of the far coordinates (measured: 0.04 px at +-5e5 px), so centres within
// 0.05 px of an edge are not judged; the axis-aligned family has none, so it is exact.
TEST(Degenerate, MillionPixelNeedlesAreClippedExactly) {
  const int count = 40 * testing::countScale();
  Rng rng(0x1E6'0005u);
  std::uint64_t judged = 0, ambiguous = 0, inside = 0;
  for (int i = 0; i < count; ++i) {
    std::uint64_t unjudged = 0;
    Tri t;
    const bool axis = i % 2 == 0;
    if (axis) {
      // Horizontal: y from y0 to y0 + 1 over 1e6 px; the slanted edge moves 2.6e-4 px across
      // the viewport, far from any pixel centre
      const double y0 = randInt(rng, 8, 240) + 0.75;
      t = {glm::dvec2(-5e5, y0), glm::dvec2(5e5, y0), glm::dvec2(5e5, y0 + 1.0)};
      if (i % 4 == 0) t = {glm::dvec2(-5e5, y0 + 1.0), glm::dvec2(-5e5, y0), glm::dvec2(5e5, y0)};
    } else {
      // Any direction through a random point of the viewport, 1 px wide
      const double a = rng.uniform(0.0f, 3.14159265f);
      const glm::dvec2 c(rng.uniform(32.0f, 224.0f), rng.uniform(32.0f, 224.0f));
      const glm::dvec2 d(std::cos(a), std::sin(a)), nrm(-d.y, d.x);
      t = {c - 5e5 * d, c + 5e5 * d, c + 5e5 * d + nrm};
    }
    for (glm::dvec2& p : t) p = glm::dvec2(glm::vec2(p));  // what the scene holds: floats
    const Scene s = flatScene({t});
    forEachAlgorithm(s, pixelCamera(kSize, kSize), countEveryFragment(), [&](const Frame& f) {
      expectSaneBuffers(f, 1);
      std::uint64_t wrong = 0;
      for (int row = 0; row < kSize; ++row) {
        for (int col = 0; col < kSize; ++col) {
          const int c = classify(t, {col + 0.5, kSize - 1 - row + 0.5}, 0.05);
          const std::uint32_t n = f.overdraw[static_cast<std::size_t>(row) * kSize + col];
          if (c == 0) {
            ++ambiguous;
            ++unjudged;
            EXPECT_LE(n, 1u);
            continue;
          }
          ++judged;
          inside += c > 0;
          if (n != (c > 0 ? 1u : 0u) && ++wrong <= 3)
            ADD_FAILURE() << "needle " << i << ": pixel col " << col << " GL y " << kSize - 1 - row
                          << " written " << n << " times, " << (c > 0 ? "inside" : "outside");
        }
      }
      EXPECT_EQ(wrong, 0u) << "needle " << i;
      EXPECT_EQ(f.stats.clipped, 1u);
    });
    if (axis) {
      EXPECT_EQ(unjudged, 0u) << "the axis-aligned family is exact";
    }
  }
  std::printf(
      "degenerate: %d million-pixel needles, %llu pixel centres judged (%llu inside), "
      "%llu within 0.05 px of an edge\n",
      count, static_cast<unsigned long long>(judged), static_cast<unsigned long long>(inside),
      static_cast<unsigned long long>(ambiguous));
}

// Documented: a triangle smaller than a pixel (bounding box under 1 px each way) contains at
// most one pixel centre, and draws it exactly when the centre-sampling rule says (inside, or
// on a top or left edge): 0 or 1 pixel, never more. Cases include a vertex on the centre and
// an edge through it.
TEST(Degenerate, SubPixelTrianglesDrawZeroOrOnePixelByTheCentreRule) {
  const int scenes = 3 * testing::countScale();
  std::uint64_t total = 0, drew = 0;
  for (int n = 0; n < scenes; ++n) {
    SCOPED_TRACE("sub-pixel seed " + std::to_string(n));
    Rng rng(0x5B'0006u + static_cast<std::uint64_t>(n));
    std::vector<Tri> tris;
    for (int cy = 1; cy + 2 < kSize; cy += 3) {
      for (int cx = 1; cx + 2 < kSize; cx += 3) {
        // Vertices within a box of 255/256 px around the centre of pixel (cx, cy)
        const std::int64_t bx = (cx * 256 + 128) - randInt(rng, 0, 255);
        const std::int64_t by = (cy * 256 + 128) - randInt(rng, 0, 255);
        std::int64_t v[3][2];
        for (auto& p : v) p[0] = bx + randInt(rng, 0, 255), p[1] = by + randInt(rng, 0, 255);
        const int kind = static_cast<int>(rng.next() % 4);
        if (kind == 1) v[0][0] = cx * 256 + 128, v[0][1] = cy * 256 + 128;  // a vertex on it
        if (kind == 2) v[0][1] = v[1][1] = cy * 256 + 128;                  // horizontal edge
        if (kind == 3) v[0][0] = v[1][0] = cx * 256 + 128;                  // vertical edge
        std::int64_t lo[2] = {v[0][0], v[0][1]}, hi[2] = {v[0][0], v[0][1]};
        for (auto& p : v)
          for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
        if (hi[0] - lo[0] > 255 || hi[1] - lo[1] > 255) continue;  // stays sub-pixel
        tris.push_back({grid(v[0][0], v[0][1]), grid(v[1][0], v[1][1]), grid(v[2][0], v[2][1])});
      }
    }
    std::vector<int> want(static_cast<std::size_t>(kSize) * kSize, 0);
    for (const Tri& t : tris) addCoverage(t, kSize, kSize, want);
    for (int w : want) ASSERT_LE(w, 1) << "test construction: cells overlap";
    total += tris.size();
    drew += static_cast<std::uint64_t>(std::accumulate(want.begin(), want.end(), 0));
    forEachAlgorithm(flatScene(tris), pixelCamera(kSize, kSize), countEveryFragment(),
                     [&](const Frame& f) {
                       EXPECT_EQ(expectCounts(f, want, "sub-pixel"), 0u);
                       // One triangle per 3x3 cell: no cell may hold more than one fragment
                       for (std::size_t id = 0; id < tris.size(); ++id)
                         ASSERT_LE(drawnBy(f, PolygonId(id)), 1u);
                     });
  }
  std::printf("degenerate: %llu sub-pixel triangles, %llu drew their one pixel, the rest none\n",
              static_cast<unsigned long long>(total), static_cast<unsigned long long>(drew));
}

// Documented: a fan of sub-pixel triangles around a point, its rim walking a small
// rectangle in steps of 1/256 to 1/4 px, covers every pixel centre inside the rectangle
// exactly once (the fill rule is exact on shared edges, however small the triangles) and
// none outside.
TEST(Degenerate, SubPixelFanCoversEachCentreExactlyOnce) {
  const int scenes = 3 * testing::countScale();
  std::uint64_t triangles = 0, centres = 0;
  for (int n = 0; n < scenes; ++n) {
    SCOPED_TRACE("sub-pixel fan seed " + std::to_string(n));
    Rng rng(0xFA0'0007u + static_cast<std::uint64_t>(n));
    std::vector<Tri> tris;
    std::vector<int> inside_rect(static_cast<std::size_t>(kSize) * kSize, 0);
    for (int fy = 0; fy < 10; ++fy) {
      for (int fx = 0; fx < 10; ++fx) {
        // Rectangle of 1.5 to 3 px a side at a random grid offset in a 20 px cell
        const std::int64_t x0 = (fx * 24 + 8) * 256 + randInt(rng, 0, 255);
        const std::int64_t y0 = (fy * 24 + 8) * 256 + randInt(rng, 0, 255);
        const std::int64_t w = randInt(rng, 384, 768), h = randInt(rng, 384, 768);
        const std::int64_t corner[4][2] = {{x0, y0}, {x0 + w, y0}, {x0 + w, y0 + h}, {x0, y0 + h}};
        std::vector<std::array<std::int64_t, 2>> rim;
        for (int side = 0; side < 4; ++side) {
          const std::int64_t* a = corner[side];
          const std::int64_t* b = corner[(side + 1) % 4];
          const std::int64_t steps = std::max(std::llabs(b[0] - a[0]), std::llabs(b[1] - a[1]));
          for (std::int64_t t = 0; t < steps; t += randInt(rng, 1, 64))
            rim.push_back({a[0] + (b[0] - a[0]) * t / steps, a[1] + (b[1] - a[1]) * t / steps});
        }
        const std::int64_t cx = x0 + randInt(rng, 1, w - 1), cy = y0 + randInt(rng, 1, h - 1);
        for (std::size_t k = 0; k < rim.size(); ++k) {
          const auto& a = rim[k];
          const auto& b = rim[(k + 1) % rim.size()];
          tris.push_back({grid(cx, cy), grid(a[0], a[1]), grid(b[0], b[1])});
        }
        addCoverage({grid(x0, y0), grid(x0 + w, y0), grid(x0 + w, y0 + h)}, kSize, kSize,
                    inside_rect);
        addCoverage({grid(x0, y0), grid(x0 + w, y0 + h), grid(x0, y0 + h)}, kSize, kSize,
                    inside_rect);
      }
    }
    std::vector<int> want(static_cast<std::size_t>(kSize) * kSize, 0);
    for (const Tri& t : tris) addCoverage(t, kSize, kSize, want);
    // The fill rule, checked on the reference itself: the fan covers what the rectangle does
    EXPECT_EQ(want, inside_rect) << "reference: the fan and its rectangle differ";
    triangles += tris.size();
    centres += static_cast<std::uint64_t>(std::accumulate(want.begin(), want.end(), 0));
    forEachAlgorithm(
        flatScene(tris), pixelCamera(kSize, kSize), countEveryFragment(),
        [&](const Frame& f) { EXPECT_EQ(expectCounts(f, inside_rect, "sub-pixel fan"), 0u); });
  }
  std::printf("degenerate: %llu sub-pixel fan triangles, %llu centres each written exactly once\n",
              static_cast<unsigned long long>(triangles), static_cast<unsigned long long>(centres));
}

// ---------------------------------------------------------------------------------------------
// Huge and tiny coordinates

// Documented: coordinates of 1e6 to 1e30 never crash anything or put NaN or Inf into the
// buffers, in orthographic and perspective views and every polygon mode; coordinates whose
// transform overflows float (3e38) are dropped and counted in degenerate_dropped.
TEST(Degenerate, HugeCoordinatesNeverCrashOrWriteNaN) {
  Rng rng(0xB16'0008u);
  std::uint64_t renders = 0, frames = 0;
  for (float mag : {1e6f, 1e8f, 1e10f, 1e15f, 1e20f, 1e25f, 1e30f, 3e38f}) {
    Scene s;
    const std::uint32_t m = s.addMaterial({});
    for (int i = 0; i < 30; ++i) {
      // Each draw in its own statement: a function's arguments are evaluated in an order the
      // compiler chooses (GCC last first, Clang first first), and the scene must not depend on
      // it (the web build is Clang's). The order is GCC's: the scenes this suite always drew.
      const auto huge = [&] {
        const float sx = (rng.next() & 1) ? mag : -mag;
        switch (rng.next() % 4) {
          case 0: {
            const float z = rng.uniform(-2.0f, 2.0f), y = rng.uniform(0.0f, 64.0f);
            return glm::vec3(sx, y, z);
          }
          case 1: {
            const float z = rng.uniform(-2.0f, 2.0f), x = rng.uniform(0.0f, 64.0f);
            return glm::vec3(x, sx, z);
          }
          case 2: {
            const float y = rng.uniform(0.0f, 64.0f), x = rng.uniform(0.0f, 64.0f);
            return glm::vec3(x, y, sx);
          }
          default: {
            const float sy = (rng.next() & 1) ? mag : -mag;
            return glm::vec3(sx, sy, sx);
          }
        }
      };
      const float near_y = rng.uniform(0.0f, 64.0f), near_x = rng.uniform(0.0f, 64.0f);
      const glm::vec3 near_pt(near_x, near_y, 0.0f);
      s.addPolygonVertices({near_pt, huge(), (i % 3 == 0) ? huge() : near_pt + glm::vec3(9, 1, 0)},
                           m);
    }
    Camera persp;
    persp.width = persp.height = 64;
    persp.eye = {32, 32, 80};
    persp.target = {32, 32, 0};
    persp.far = 1000.0f;
    for (const Camera& cam : {pixelCamera(64, 64), persp}) {
      // In perspective, 3e38 overflows the transform; the pixel camera's scale (2/64) keeps
      // it finite there, so it is clipped instead
      for (PolygonMode mode : {PolygonMode::Fill, PolygonMode::Line, PolygonMode::Point}) {
        RenderOptions o;
        o.polygon_mode = mode;
        o.frustum_cull = (renders & 1) != 0;
        o.outline = mode == PolygonMode::Fill;
        SCOPED_TRACE("magnitude " + std::to_string(mag) +
                     (cam.ortho ? ", pixel camera" : ", perspective") + ", frustum cull " +
                     std::to_string(o.frustum_cull));
        forEachAlgorithm(s, cam, o, [&](const Frame& f) {
          ++frames;
          expectSaneBuffers(f, s.polygonCount());
          if (mag > 1e38f && !cam.ortho) {
            EXPECT_GT(f.stats.degenerate_dropped, 0u) << "transform overflow";
          }
        });
        ++renders;
      }
    }
  }
  // The overflow case alone: exactly the overflowing triangle is dropped and counted
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  s.addPolygonVertices({{-3e38f, -3e38f, 0}, {3e38f, -3e38f, 0}, {0, 3e38f, 0}}, m);
  s.addPolygonVertices({{10, 10, 0}, {50, 10, 0}, {10, 50, 0}}, m);
  Camera cam;
  cam.width = cam.height = 64;
  cam.eye = {30, 30, 60};
  cam.target = {30, 30, 0};
  RenderOptions o;
  o.frustum_cull = false;
  forEachAlgorithm(s, cam, o, [&](const Frame& f) {
    EXPECT_EQ(f.stats.degenerate_dropped, 1u);
    EXPECT_EQ(drawnBy(f, 0), 0u);
    EXPECT_GT(drawnBy(f, 1), 0u);
  });
  std::printf("degenerate: %llu renders of triangles reaching 1e6..3e38, buffers always finite\n",
              static_cast<unsigned long long>(frames));
}

// Documented (docs/testing.md row 14: "counted drop or correct clip"): a triangle with vertices at
// 1e6 to 1e30 is either dropped and counted (degenerate_dropped or clipped_away, drawing
// nothing), or clipped correctly: every pixel centre more than 0.01 px inside the exact
// triangle is drawn, none more than 0.01 px outside, at the triangle's own depth. The shapes
// include edges whose two ends both lie far outside, on opposite sides of the viewport; their
// coordinates are chosen so that an exact clip is representable (axis-aligned edges).
TEST(Degenerate, HugeCoordinatesClipCorrectly) {
  constexpr int W = 64;
  std::uint64_t cases = 0, judged = 0, wrong_total = 0, dropped = 0;
  for (double mag : {1e6, 1e7, 1e8, 1e10, 1e15, 1e20, 1e25, 1e30}) {
    const float M = static_cast<float>(mag);
    // Edges pass through the viewport at y = 20.25, x = 40.75 etc.; in GL window coordinates
    const std::vector<Tri> shapes = {
        {glm::dvec2(-M, 20.25), glm::dvec2(M, 20.25), glm::dvec2(0, M)},  // far ends both sides
        {glm::dvec2(40.75, -M), glm::dvec2(40.75, M), glm::dvec2(-M, 0)},
        {glm::dvec2(-M, -M), glm::dvec2(M, -M), glm::dvec2(0, M)},             // covers everything
        {glm::dvec2(10.5, 12.25), glm::dvec2(M, 12.25), glm::dvec2(10.5, M)},  // one vertex in view
        {glm::dvec2(30.25, 30.25), glm::dvec2(-M, 40.5), glm::dvec2(-M, -M)},
        {glm::dvec2(M, M), glm::dvec2(M + M, M), glm::dvec2(M, M + M)},  // all outside
    };
    for (std::size_t k = 0; k < shapes.size(); ++k) {
      const Tri& t = shapes[k];
      const float z = 1.5f;
      const Scene s = flatScene({t}, z);
      RenderOptions o;
      o.frustum_cull = false;
      const float depth = (9.0f - z) / 19.0f;  // the pixel camera's window depth of z
      forEachAlgorithm(s, pixelCamera(W, W), o, [&](const Frame& f) {
        if (f.stats.degenerate_dropped + f.stats.clipped_away > 0 && drawnBy(f, 0) == 0) {
          ++dropped;  // a counted drop
          return;
        }
        std::uint64_t wrong = 0;
        for (int row = 0; row < W; ++row) {
          for (int col = 0; col < W; ++col) {
            const std::size_t idx = static_cast<std::size_t>(row) * W + col;
            const int c = classify(t, {col + 0.5, W - 1 - row + 0.5}, 0.01);
            if (c == 0) continue;
            ++judged;
            const bool drawn = f.ids[idx] == 0;
            if (drawn) {
              EXPECT_NEAR(f.depth[idx], depth, 1e-6);
            }
            if (drawn != (c > 0) && ++wrong <= 2)
              ADD_FAILURE() << "magnitude " << mag << " shape " << k << ": pixel col " << col
                            << " GL y " << W - 1 - row
                            << (drawn ? " drawn, outside" : " not drawn, inside");
          }
        }
        EXPECT_EQ(wrong, 0u) << "magnitude " << mag << " shape " << k << ": " << wrong
                             << " pixels wrong (clipped " << f.stats.clipped << ", away "
                             << f.stats.clipped_away << ", dropped " << f.stats.degenerate_dropped
                             << ")";
        wrong_total += wrong;
      });
      ++cases;
    }
  }
  std::printf(
      "degenerate: %llu huge-coordinate triangles, %llu counted drops, %llu pixel centres "
      "judged, %llu wrong\n",
      static_cast<unsigned long long>(cases), static_cast<unsigned long long>(dropped),
      static_cast<unsigned long long>(judged), static_cast<unsigned long long>(wrong_total));
}

// Documented: subnormal coordinates (below FLT_MIN, e.g. 1e-40) are ordinary, tiny numbers.
// A triangle made only of them has a positive exact area, so it is not counted as degenerate;
// it snaps to one point and draws 0 pixels. In a normal triangle they change nothing: ids,
// depth and fragment counts are bit-identical to the same triangle with the subnormals
// replaced by 0. No NaN, no crash.
TEST(Degenerate, SubnormalCoordinatesAreValidTinyGeometry) {
  const float sub[] = {1e-40f, -2.5e-42f, 1.4e-45f, 5e-39f, -1.1754942e-38f};
  for (float v : sub) ASSERT_EQ(std::fpclassify(v), FP_SUBNORMAL) << v;
  Rng rng(0x50B'0009u);
  Scene tiny, with, without;
  const std::uint32_t m0 = tiny.addMaterial({}), m1 = with.addMaterial({}),
                      m2 = without.addMaterial({});
  for (int i = 0; i < 50; ++i) {
    const auto pick = [&] { return sub[rng.next() % std::size(sub)]; };
    tiny.addPolygonVertices(
        {{pick(), pick(), pick()}, {2 * 1e-40f, pick(), 0}, {pick(), 3e-40f, pick()}}, m0);
    // A visible triangle; some coordinates get a subnormal added where they are 0, others are
    // replaced by a subnormal offset of a grid value (which rounds back to the grid value)
    const glm::vec3 a(randInt(rng, 1, 200), randInt(rng, 1, 200), 0);
    const glm::vec3 b = a + glm::vec3(randInt(rng, 5, 50), randInt(rng, 0, 20), 0);
    const glm::vec3 c = a + glm::vec3(randInt(rng, 0, 20), randInt(rng, 5, 50), 0);
    without.addPolygonVertices({a, b, c}, m2);
    with.addPolygonVertices({a + glm::vec3(0, 0, pick()), b + glm::vec3(pick(), pick(), pick()),
                             c + glm::vec3(0, 0, pick())},
                            m1);
  }
  // A triangle of a subnormal corner and two ordinary ones, exactly at the origin's pixel
  with.addPolygonVertices({{1e-40f, 1e-40f, 1e-40f}, {12, 0, 0}, {0, 12, 0}}, m1);
  without.addPolygonVertices({{0, 0, 0}, {12, 0, 0}, {0, 12, 0}}, m2);
  const Camera cam = pixelCamera(kSize, kSize);
  forEachAlgorithm(tiny, cam, {}, [&](const Frame& f) {
    expectSaneBuffers(f, tiny.polygonCount());
    EXPECT_EQ(f.stats.degenerate_dropped, 0u);
    EXPECT_EQ(drawnBy(f, kNoPolygon), f.ids.size());
  });
  for (const AlgorithmInfo* ap :
       testing::algorithmsWith("Degenerate", kExactSharedCoverage | kDepthFuncs)) {
    const AlgorithmInfo& a = *ap;
    SCOPED_TRACE("algorithm " + std::string(a.name));
    for (bool depth_test : {true, false}) {
      RenderOptions o;
      o.algorithm = std::string(a.name);
      o.depth_test = depth_test;
      const Frame fa = render(with, cam, o), fb = render(without, cam, o);
      expectSaneBuffers(fa, with.polygonCount());
      EXPECT_EQ(fa.ids, fb.ids);
      EXPECT_EQ(fa.overdraw, fb.overdraw);
      EXPECT_EQ(fa.depth, fb.depth);  // bit-identical: window depth of z = 1e-40 is that of 0
      EXPECT_EQ(fa.stats.degenerate_dropped, 0u);
      EXPECT_GT(fa.ids.size() - drawnBy(fa, kNoPolygon), 1000u);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// T-junctions, non-manifold edges, flipped faces, duplicates

// A T-junction: triangle ABC on one side of edge AB; on the other side two triangles AMD and
// MBD share a vertex M on AB. Returns the three triangles (GL window coordinates).
std::vector<Tri> tJunction(glm::dvec2 a, glm::dvec2 b, glm::dvec2 m, glm::dvec2 c, glm::dvec2 d) {
  return {{a, b, c}, {a, m, d}, {m, b, d}};
}

// Documented: a T-junction vertex M that lies exactly on the edge AB in snapped (24.8)
// coordinates leaves no crack and no double write: AM and MB lie on AB, so the fill rule
// gives each pixel centre on the line to exactly one side. (The library does not weld
// T-junctions; exactness comes from the snapping and the fill rule.)
TEST(Degenerate, TJunctionVertexOnTheEdgeLeavesNoCrack) {
  const int cases = 150 * testing::countScale();
  Rng rng(0x7'0010u);
  std::uint64_t on_line = 0;
  for (int i = 0; i < cases; ++i) {
    // A and B on the grid with B - A = q * (u, v), M = A + j (u, v): exactly on AB
    const std::int64_t q = randInt(rng, 2, 12);
    std::int64_t u = randInt(rng, -1500, 1500), v = randInt(rng, -1500, 1500);
    if (i % 3 == 0)
      v = 0;  // along a row: pixel centres on the line when a.y is one
    else if (i % 3 == 1)
      u = 0;  // along a column
    if (u == 0 && v == 0) u = 256;
    std::int64_t ax = 128 * 256 - q * u / 2, ay = 128 * 256 - q * v / 2;
    if (i % 3 == 0) ay = (ay / 256) * 256 + 128;  // the row through pixel centres
    if (i % 3 == 1) ax = (ax / 256) * 256 + 128;  // the column through pixel centres
    const std::int64_t j = randInt(rng, 1, q - 1);
    const glm::dvec2 a = grid(ax, ay), b = grid(ax + q * u, ay + q * v),
                     m = grid(ax + j * u, ay + j * v);
    const glm::dvec2 dir = b - a, nrm = glm::normalize(glm::dvec2(-dir.y, dir.x));
    const double h = rng.uniform(4.0f, 60.0f);
    const glm::dvec2 mid = (a + b) * 0.5;
    const glm::dvec2 c =
        grid(std::llround((mid.x + h * nrm.x) * 256), std::llround((mid.y + h * nrm.y) * 256));
    const glm::dvec2 d =
        grid(std::llround((mid.x - h * nrm.x) * 256), std::llround((mid.y - h * nrm.y) * 256));
    const std::vector<Tri> tris = tJunction(a, b, m, c, d);
    std::vector<int> want(static_cast<std::size_t>(kSize) * kSize, 0);
    for (const Tri& t : tris) addCoverage(t, kSize, kSize, want);
    // Centres on the line AB (strictly between A and B): each covered exactly once
    for (int row = 0; row < kSize; ++row) {
      for (int col = 0; col < kSize; ++col) {
        const glm::dvec2 p(col + 0.5, kSize - 1 - row + 0.5);
        const double cr = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
        const double along = glm::dot(p - a, b - a) / glm::dot(b - a, b - a);
        if (cr == 0.0 && along > 0.0 && along < 1.0) {
          ++on_line;
          EXPECT_EQ(want[static_cast<std::size_t>(row) * kSize + col], 1)
              << "reference, case " << i;
        }
      }
    }
    for (int w : want) ASSERT_LE(w, 1) << "case " << i << ": the reference double-covers";
    forEachAlgorithm(flatScene(tris), pixelCamera(kSize, kSize), countEveryFragment(),
                     [&](const Frame& f) {
                       EXPECT_EQ(expectCounts(f, want, "T-junction " + std::to_string(i)), 0u);
                     });
  }
  std::printf(
      "degenerate: %d T-junctions with M on the edge, %llu pixel centres on the shared "
      "line, each written once\n",
      cases, static_cast<unsigned long long>(on_line));
}

// Documented (honestly): when the T-vertex M is NOT on AB after snapping, here one 1/256 px
// grid step off it, the sliver triangle A-M-B between AB and the path A-M-B is a real crack
// or overlap, and the fill rule cannot hide it. M away from ABC opens a gap: centres in it
// are written by neither side (a crack); M toward ABC makes an overlap: centres in it are
// written by both (a double write). For centres exactly on AB, as here, the fill rule
// decides: a crack only where ABC does not own AB, a double write only where it does. Every
// defect is a pixel centre inside or on the sliver; all other centres are written exactly
// once, and the drawing is exactly the reference in every case.
TEST(Degenerate, TJunctionVertexOffTheEdgeCracksOnlyInsideTheSliver) {
  const int cases = 120 * testing::countScale();
  Rng rng(0x7'0011u);
  std::uint64_t cracks = 0, doubles = 0, crack_cases = 0, double_cases = 0;
  for (int i = 0; i < cases; ++i) {
    // AB along a row of pixel centres (so centres lie on it), M one grid step above or below
    const std::int64_t row_y = randInt(rng, 40, 215) * 256 + 128;
    const std::int64_t ax = randInt(rng, 20, 60) * 256 + randInt(rng, 0, 255);
    const std::int64_t bx = randInt(rng, 160, 230) * 256 + randInt(rng, 0, 255);
    const std::int64_t mx = randInt(rng, ax / 256 + 10, bx / 256 - 10) * 256 + randInt(rng, 0, 255);
    const std::int64_t off = (i & 1) ? 1 : -1;
    const std::int64_t up = (i & 2) ? 1 : -1;  // which side ABC is on
    const glm::dvec2 a = grid(ax, row_y), b = grid(bx, row_y), m = grid(mx, row_y + off);
    const glm::dvec2 c = grid(randInt(rng, 80, 170) * 256, row_y + up * randInt(rng, 8, 30) * 256);
    const glm::dvec2 d = grid(randInt(rng, 80, 170) * 256, row_y - up * randInt(rng, 8, 30) * 256);
    const std::vector<Tri> tris = tJunction(a, b, m, c, d);
    std::vector<int> want(static_cast<std::size_t>(kSize) * kSize, 0);
    for (const Tri& t : tris) addCoverage(t, kSize, kSize, want);
    // Without the T-vertex the union would be ABC + ABD; the sliver is A, M, B
    std::vector<int> sliver(want.size(), 0), outline(want.size(), 0);
    addCoverage({a, m, b}, kSize, kSize, sliver);
    addCoverage({a, d, b}, kSize, kSize, outline);
    addCoverage({a, b, c}, kSize, kSize, outline);
    std::uint64_t case_cracks = 0, case_doubles = 0;
    for (int row = 0; row < kSize; ++row) {
      for (int col = 0; col < kSize; ++col) {
        const std::size_t k = static_cast<std::size_t>(row) * kSize + col;
        const glm::dvec2 p(col + 0.5, kSize - 1 - row + 0.5);
        const int expected = outline[k] > 0 ? 1 : 0;
        if (want[k] == expected) continue;
        // A defect: it must be inside or on the sliver (within its bounding segment's span)
        const bool in_sliver =
            sliver[k] > 0 || (std::abs(p.y - a.y) < 1e-9 && p.x > a.x && p.x < b.x);
        EXPECT_TRUE(in_sliver) << "case " << i << ": defect outside the sliver at col " << col
                               << " GL y " << kSize - 1 - row;
        (want[k] < expected ? case_cracks : case_doubles)++;
      }
    }
    // Which defect, by the side M is on (off: M above AB; up: ABC above AB)
    if (case_cracks > 0) {
      EXPECT_NE(off, up) << "case " << i << ": a crack with M toward ABC";
    }
    if (case_doubles > 0) {
      EXPECT_EQ(off, up) << "case " << i << ": a double write with M away from ABC";
    }
    cracks += case_cracks;
    doubles += case_doubles;
    crack_cases += case_cracks > 0;
    double_cases += case_doubles > 0;
    forEachAlgorithm(flatScene(tris), pixelCamera(kSize, kSize), countEveryFragment(),
                     [&](const Frame& f) {
                       EXPECT_EQ(expectCounts(f, want, "T-junction " + std::to_string(i)), 0u);
                     });
  }
  // The configurations are built so that both defects occur: the test shows them, not hides
  EXPECT_GT(crack_cases, 0u);
  EXPECT_GT(double_cases, 0u);
  std::printf(
      "degenerate: %d T-junctions with M one grid step off the edge: %llu cases crack "
      "(%llu centres), %llu double-write (%llu centres), all inside the sliver\n",
      cases, static_cast<unsigned long long>(crack_cases), static_cast<unsigned long long>(cracks),
      static_cast<unsigned long long>(double_cases), static_cast<unsigned long long>(doubles));
}

// Documented: 3 or more faces on one edge (a non-manifold "book") are each drawn on their
// own: every pixel centre is written once by each face that covers it and by no other (no
// face writes a pixel twice), and with the depth test the pixel shows one of those faces,
// a nearest one.
TEST(Degenerate, NonManifoldEdgeEachFaceWritesItsPixelsOnce) {
  const int cases = 40 * testing::countScale();
  Rng rng(0xB00C'0012u);
  for (int i = 0; i < cases; ++i) {
    SCOPED_TRACE("book " + std::to_string(i));
    const int pages = 3 + static_cast<int>(rng.next() % 4);
    // The shared edge (spine) from A to B, pages fanning out to either side at various depths
    const glm::dvec2 a =
        grid(randInt(rng, 60, 100) * 256 + randInt(rng, 0, 255), randInt(rng, 30, 60) * 256);
    const glm::dvec2 b =
        grid(randInt(rng, 150, 200) * 256 + randInt(rng, 0, 255), randInt(rng, 190, 230) * 256);
    Scene s;
    const std::uint32_t m = s.addMaterial({});
    s.beginObject("book");
    const std::uint32_t ia = s.addVertex({float(a.x), float(a.y), 0.0f});
    const std::uint32_t ib = s.addVertex({float(b.x), float(b.y), 0.0f});
    std::vector<Tri> tris;
    std::vector<float> page_z;
    for (int p = 0; p < pages; ++p) {
      const glm::dvec2 c = grid(randInt(rng, 8, 248) * 256 + randInt(rng, 0, 255),
                                randInt(rng, 8, 248) * 256 + randInt(rng, 0, 255));
      const float z = float(randInt(rng, -1024, 1024)) / 256.0f;
      const std::uint32_t ic = s.addVertex({float(c.x), float(c.y), z});
      if (p % 2)
        s.addPolygon({ia, ib, ic}, m);
      else
        s.addPolygon({ib, ia, ic}, m);  // mixed winding, as real non-manifold meshes have
      tris.push_back({a, b, c});
      page_z.push_back(z);
    }
    // Per face and per pixel: the exact coverage
    std::vector<std::vector<int>> cover(
        tris.size(), std::vector<int>(static_cast<std::size_t>(kSize) * kSize, 0));
    std::vector<int> want(static_cast<std::size_t>(kSize) * kSize, 0);
    for (std::size_t p = 0; p < tris.size(); ++p) {
      addCoverage(tris[p], kSize, kSize, cover[p]);
      for (std::size_t k = 0; k < want.size(); ++k) want[k] += cover[p][k];
    }
    forEachAlgorithm(s, pixelCamera(kSize, kSize), countEveryFragment(), [&](const Frame& f) {
      EXPECT_EQ(expectCounts(f, want, "book, depth test off"), 0u);
    });
    RenderOptions o;
    o.frustum_cull = false;
    forEachAlgorithm(s, pixelCamera(kSize, kSize), o, [&](const Frame& f) {
      std::uint64_t bad = 0;
      for (std::size_t k = 0; k < want.size(); ++k) {
        if (want[k] == 0) {
          if (f.ids[k] != kNoPolygon && ++bad <= 3)
            ADD_FAILURE() << "pixel " << k << " drawn, no face covers it";
          continue;
        }
        const PolygonId id = f.ids[k];
        if (id >= tris.size() || cover[id][k] == 0) {
          if (++bad <= 3)
            ADD_FAILURE() << "pixel " << k << " shows " << id << ", which does not cover it";
          continue;
        }
        // Nearest: no covering face is nearer by more than float rounding of the depth plane.
        // World z at the centre, by the plane through A, B (z = 0) and C (z = page_z)
        const int col = static_cast<int>(k % kSize), row = static_cast<int>(k / kSize);
        const glm::dvec2 pc(col + 0.5, kSize - 1 - row + 0.5);
        const auto zAt = [&](std::size_t p) {
          const glm::dvec2 e1 = b - a, e2 = tris[p][2] - a, r = pc - a;
          const double det = e1.x * e2.y - e1.y * e2.x;
          const double t = (e1.x * r.y - e1.y * r.x) / det;  // weight of C
          return t * page_z[p];
        };
        for (std::size_t p = 0; p < tris.size(); ++p)
          if (cover[p][k] && zAt(p) > zAt(id) + 1e-3 && ++bad <= 3)
            ADD_FAILURE() << "pixel " << k << " shows face " << id << " behind face " << p;
      }
      EXPECT_EQ(bad, 0u);
    });
  }
}

// Documented: culling follows each face's own winding in window space (counter-clockwise is
// front under FrontFace::Ccw, as glFrontFace); a flipped face in a mesh is culled exactly
// when the cull mode says, for every cull mode and front-face rule, with either facing test,
// and counted in culled_backface. Nothing repairs the winding.
TEST(Degenerate, FlippedFacesAreCulledExactlyWhenTheCullRuleSays) {
  Rng rng(0xF11'0013u);
  // A 12 x 12 grid of quads (2 triangles each) with random winding, as a mesh with flips
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  s.beginObject("flipped mesh");
  constexpr int N = 12;
  for (int y = 0; y <= N; ++y)
    for (int x = 0; x <= N; ++x) s.addVertex({8.0f + 20.0f * x, 8.0f + 20.0f * y, 0.0f});
  std::vector<bool> ccw;
  for (int y = 0; y < N; ++y) {
    for (int x = 0; x < N; ++x) {
      const std::uint32_t v00 = y * (N + 1) + x, v10 = v00 + 1, v01 = v00 + N + 1, v11 = v01 + 1;
      for (const auto& t : {std::array<std::uint32_t, 3>{v00, v10, v11},
                            std::array<std::uint32_t, 3>{v00, v11, v01}}) {
        const bool flip = (rng.next() % 3) == 0;
        if (flip)
          s.addPolygon({t[0], t[2], t[1]}, m);
        else
          s.addPolygon({t[0], t[1], t[2]}, m);
        ccw.push_back(!flip);  // counter-clockwise in GL window space (y up) unless flipped
      }
    }
  }
  std::uint64_t checks = 0;
  for (CullMode cull : {CullMode::None, CullMode::Back, CullMode::Front, CullMode::FrontAndBack}) {
    for (FrontFace ff : {FrontFace::Ccw, FrontFace::Cw}) {
      for (FacingTest facing : {FacingTest::WindowArea, FacingTest::EyePlane}) {
        RenderOptions o;
        o.cull = cull;
        o.front_face = ff;
        o.facing_test = facing;
        std::uint64_t culled_want = 0;
        std::vector<bool> drawn_want(ccw.size());
        for (std::size_t id = 0; id < ccw.size(); ++id) {
          const bool front = ccw[id] == (ff == FrontFace::Ccw);
          const bool culled = cull == CullMode::FrontAndBack ||
                              (cull == CullMode::Back && !front) ||
                              (cull == CullMode::Front && front);
          drawn_want[id] = !culled;
          culled_want += culled;
        }
        forEachAlgorithm(s, pixelCamera(kSize, kSize), o, [&](const Frame& f) {
          EXPECT_EQ(f.stats.culled_backface, culled_want);
          for (std::size_t id = 0; id < ccw.size(); ++id) {
            const std::size_t n = drawnBy(f, PolygonId(id));
            // Each triangle covers 180 to 210 pixel centres of its 20 x 20 px quad half
            EXPECT_EQ(n > 0, drawn_want[id])
                << "triangle " << id << (ccw[id] ? " ccw" : " cw") << ", cull " << int(cull)
                << ", front " << (ff == FrontFace::Ccw ? "ccw" : "cw");
            if (drawn_want[id]) {
              EXPECT_GE(n, 180u);
            }
            ++checks;
          }
        });
      }
    }
  }
  std::printf("degenerate: %llu flipped-face cull decisions checked\n",
              static_cast<unsigned long long>(checks));
}

// Documented tie rule: identical triangles (the same vertices in the same order) submitted
// several times have bit-identical depth, so with LESS the first submitted keeps every pixel,
// and with LEQUAL the last submitted does; this holds for shared or separate vertices, on
// sloped planes too.
TEST(Degenerate, DuplicateTrianglesFirstSubmittedWinsWithLess) {
  const int cases = 60 * testing::countScale();
  Rng rng(0xD0B'0014u);
  for (int i = 0; i < cases; ++i) {
    SCOPED_TRACE("duplicates " + std::to_string(i));
    Scene s;
    const std::uint32_t m = s.addMaterial({});
    const auto point = [&] {
      return glm::vec3(rng.uniform(4.0f, 252.0f), rng.uniform(4.0f, 252.0f),
                       rng.uniform(-6.0f, 6.0f));
    };
    const glm::vec3 p[3] = {point(), point(), point()};
    const int copies = 2 + static_cast<int>(rng.next() % 4);
    s.beginObject("dups");
    const std::uint32_t shared[3] = {s.addVertex(p[0]), s.addVertex(p[1]), s.addVertex(p[2])};
    for (int c = 0; c < copies; ++c) {
      if (c % 2 == 0) {
        s.addPolygon({shared[0], shared[1], shared[2]}, m);
      } else {
        s.addPolygon({s.addVertex(p[0]), s.addVertex(p[1]), s.addVertex(p[2])}, m);
      }
    }
    for (DepthFunc func : {DepthFunc::Less, DepthFunc::LEqual}) {
      RenderOptions o;
      o.depth_func = func;
      const PolygonId winner = func == DepthFunc::Less ? 0 : PolygonId(copies - 1);
      forEachAlgorithm(s, pixelCamera(kSize, kSize), o, [&](const Frame& f) {
        const std::size_t drawn = f.ids.size() - drawnBy(f, kNoPolygon);
        EXPECT_EQ(drawnBy(f, winner), drawn) << (func == DepthFunc::Less ? "LESS" : "LEQUAL");
      });
    }
  }
}

// Documented tie rule, any vertex order: the same triangle submitted again with its vertex
// list rotated (b, c, a) or reversed is the same surface, so with LESS the first submitted
// keeps every pixel (docs/testing.md row 6: the tie rule, never a mix of the rule and noise).
TEST(Degenerate, DuplicateTrianglesInAnyVertexOrderFirstSubmittedWins) {
  const int cases = 60 * testing::countScale();
  Rng rng(0xD0B'0015u);
  std::uint64_t noisy_cases = 0, noisy_pixels = 0, pixels = 0;
  for (int i = 0; i < cases; ++i) {
    Scene s;
    const std::uint32_t m = s.addMaterial({});
    const auto point = [&] {
      return glm::vec3(rng.uniform(4.0f, 252.0f), rng.uniform(4.0f, 252.0f),
                       rng.uniform(-6.0f, 6.0f));
    };
    const glm::vec3 a = point(), b = point(), c = point();
    s.addPolygonVertices({a, b, c}, m);
    s.addPolygonVertices({b, c, a}, m);
    s.addPolygonVertices({c, a, b}, m);
    s.addPolygonVertices({a, c, b}, m);
    s.addPolygonVertices({c, b, a}, m);
    forEachAlgorithm(s, pixelCamera(kSize, kSize), {}, [&](const Frame& f) {
      const std::size_t drawn = f.ids.size() - drawnBy(f, kNoPolygon);
      const std::size_t first = drawnBy(f, 0);
      pixels += drawn;
      noisy_pixels += drawn - first;
      noisy_cases += drawn != first;
      EXPECT_EQ(first, drawn) << "case " << i << ": " << drawn - first << " of " << drawn
                              << " pixels show a later duplicate";
    });
  }
  std::printf(
      "degenerate: %d rotated/reversed duplicate sets, %llu with tie noise (%llu of %llu "
      "pixels)\n",
      cases, static_cast<unsigned long long>(noisy_cases),
      static_cast<unsigned long long>(noisy_pixels), static_cast<unsigned long long>(pixels));
}

}  // namespace
}  // namespace hsr
