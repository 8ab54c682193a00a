// Properties of the fill rule through the whole pipeline (docs/testing.md rows 1 and 2): triangles
// that share edges cover every pixel centre exactly once, with no double hits and no holes.
// Fragments are counted with Frame::overdraw and the depth test off, so every fragment counts.

#include <gtest/gtest.h>

#include <cmath>
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

constexpr double kPi = 3.14159265358979323846;
// Pixels whose centre is closer than this to an outline edge are not judged: snapping vertices
// to 1/256 px moves edges by up to ~0.003 px, and float transforms add a little more.
constexpr double kMargin = 0.01;

RenderOptions countEveryFragment(const std::string& algorithm) {
  RenderOptions o = testing::optionsFor(algorithm);
  // Every fragment writes, so overdraw counts all of them: with the depth test off, or with
  // no depth test at all (a painter).
  if (findAlgorithm(algorithm).has(kDepthFuncs)) o.depth_test = false;
  o.frustum_cull = false;
  o.threads = 2;
  return o;
}

// Window-space (GL, y up) convex polygon test with a margin: +1 inside by more than `margin`
// pixels, -1 outside by more than it, 0 too close to call. Vertices counter-clockwise.
int classify(const std::vector<glm::dvec2>& poly, glm::dvec2 p, double margin) {
  double min_dist = 1e300;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
    const glm::dvec2 e = b - a;
    const double d = (e.x * (p.y - a.y) - e.y * (p.x - a.x)) / std::sqrt(e.x * e.x + e.y * e.y);
    min_dist = std::min(min_dist, d);
  }
  if (min_dist > margin) return 1;
  if (min_dist < -margin) return -1;
  return 0;
}

struct CoverageReport {
  std::uint64_t overlaps = 0;  // pixels written more than once
  std::uint64_t holes = 0;     // pixels surely inside, never written
  std::uint64_t spill = 0;     // pixels surely outside, written
  std::string first;           // the first offending pixel
};

// Checks overdraw against a convex window-space outline (GL coordinates, y up). Without an
// outline, every pixel of the viewport must be written exactly once.
CoverageReport checkCoverage(const Frame& f, const std::vector<glm::dvec2>* outline) {
  CoverageReport r;
  for (int row = 0; row < f.height; ++row) {
    for (int x = 0; x < f.width; ++x) {
      const int gl_y = f.height - 1 - row;
      const std::uint32_t n = f.overdraw[static_cast<std::size_t>(row) * f.width + x];
      const int where = outline ? classify(*outline, {x + 0.5, gl_y + 0.5}, kMargin) : 1;
      const char* what = nullptr;
      if (n > 1) {
        r.overlaps++;
        what = "written twice";
      } else if (n == 0 && where > 0) {
        r.holes++;
        what = "hole";
      } else if (n > 0 && where < 0) {
        r.spill++;
        what = "written outside";
      }
      if (what && r.first.empty()) {
        r.first = std::string(what) + " at x=" + std::to_string(x) +
                  " gl_y=" + std::to_string(gl_y) + " (count " + std::to_string(n) + ")";
      }
    }
  }
  return r;
}

void expectExactCover(const CoverageReport& r, const std::string& label) {
  EXPECT_EQ(r.overlaps, 0u) << label << ": " << r.first;
  EXPECT_EQ(r.holes, 0u) << label << ": " << r.first;
  EXPECT_EQ(r.spill, 0u) << label << ": " << r.first;
}

// ---------------------------------------------------------------------------------------------
// Row 1: a fan around a centre, vertices walking a 500x500 rectangle in random steps in
// [0, 1) px (about 4,000 triangles), on a 1000x1000 target.

Scene fan(const glm::vec2& centre, const std::vector<glm::vec2>& rim) {
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  s.beginObject("fan");
  const std::uint32_t c = s.addVertex({centre, 0.0f});
  for (const glm::vec2& p : rim) s.addVertex({p, 0.0f});
  const std::uint32_t n = static_cast<std::uint32_t>(rim.size());
  for (std::uint32_t k = 0; k < n; ++k) s.addPolygon({c, 1 + k, 1 + (k + 1) % n}, m);
  return s;
}

class RasterProperties : public testing::EveryAlgorithm {};

TEST_P(RasterProperties, FanCoversEachPixelOnce) {
  const int size = 1000;
  const Camera cam = pixelCamera(size, size);
  const int seeds = testing::legCases(10 * testing::countScale(), 2);  // half in the sanitizer leg
  for (int seed = 1; seed <= seeds; ++seed) {
    SCOPED_TRACE("fan seed " + std::to_string(seed));
    Rng rng(static_cast<std::uint64_t>(seed));
    // The rectangle, placed at a random sub-pixel offset; the rim walks its sides
    // counter-clockwise in random steps and always lands on the corners.
    const float x0 = 250.0f + rng.uniform(-100.0f, 100.0f),
                y0 = 250.0f + rng.uniform(-100.0f, 100.0f);
    const glm::vec2 corners[4] = {{x0, y0}, {x0 + 500, y0}, {x0 + 500, y0 + 500}, {x0, y0 + 500}};
    std::vector<glm::vec2> rim;
    for (int side = 0; side < 4; ++side) {
      const glm::vec2 a = corners[side], b = corners[(side + 1) % 4];
      for (float t = 0.0f; t < 500.0f; t += rng.uniform(0.0f, 1.0f))
        rim.push_back(a + (b - a) * (t / 500.0f));
    }
    const glm::vec2 centre(x0 + rng.uniform(1.0f, 499.0f), y0 + rng.uniform(1.0f, 499.0f));
    const Scene s = fan(centre, rim);
    const Frame f = render(s, cam, countEveryFragment(GetParam()));
    std::vector<glm::dvec2> outline;
    for (const glm::vec2& c : corners) outline.push_back({c.x, c.y});
    const CoverageReport r = checkCoverage(f, &outline);
    std::printf("raster fan seed %d: %zu triangles, %llu written twice, %llu holes\n", seed,
                rim.size(), static_cast<unsigned long long>(r.overlaps),
                static_cast<unsigned long long>(r.holes));
    expectExactCover(r, "fan seed " + std::to_string(seed));
  }
}

// Row 1, clipped: the centre anywhere in [-0.5W, 1.5W]^2 (often off screen), the rim on a circle
// that encloses the viewport, so every pixel of the viewport is covered exactly once.
TEST_P(RasterProperties, ClippedFanCoversViewportOnce) {
  const int size = 1000;
  const Camera cam = pixelCamera(size, size);
  const int seeds = testing::legCases(10 * testing::countScale(), 2);  // half in the sanitizer leg
  for (int seed = 1; seed <= seeds; ++seed) {
    SCOPED_TRACE("clipped fan seed " + std::to_string(seed));
    Rng rng(static_cast<std::uint64_t>(1000 + seed));
    const glm::vec2 centre(rng.uniform(-0.5f * size, 1.5f * size),
                           rng.uniform(-0.5f * size, 1.5f * size));
    const double radius = 3.0 * size;  // > the farthest corner from any such centre
    std::vector<glm::vec2> rim;
    const double step = 2.0 * kPi / 4000.0;
    for (double a = rng.uniform(0.0f, 1.0f) * step; a < 2.0 * kPi;
         a += rng.uniform(0.05f, 1.95f) * step) {
      rim.push_back({static_cast<float>(centre.x + radius * std::cos(a)),
                     static_cast<float>(centre.y + radius * std::sin(a))});
    }
    const Scene s = fan(centre, rim);
    const Frame f = render(s, cam, countEveryFragment(GetParam()));
    const CoverageReport r = checkCoverage(f, nullptr);
    std::printf("raster clipped fan seed %d: %zu triangles, %llu written twice, %llu holes\n", seed,
                rim.size(), static_cast<unsigned long long>(r.overlaps),
                static_cast<unsigned long long>(r.holes));
    expectExactCover(r, "clipped fan seed " + std::to_string(seed));
  }
}

// ---------------------------------------------------------------------------------------------
// Row 2: a 4x4 grid of quads (each two triangles, diagonals alternating) rotated over 15 angles
// in [0, pi/2].

// The grid's vertices, rotated by `angle` about `centre`; cells `cell` wide.
Scene quadGrid(glm::vec2 centre, float cell, double angle, float z = 0.0f) {
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  s.beginObject("grid");
  const double c = std::cos(angle), sn = std::sin(angle);
  for (int j = 0; j <= 4; ++j) {
    for (int i = 0; i <= 4; ++i) {
      const double u = (i - 2) * cell, v = (j - 2) * cell;
      s.addVertex({static_cast<float>(centre.x + c * u - sn * v),
                   static_cast<float>(centre.y + sn * u + c * v), z});
    }
  }
  for (std::uint32_t j = 0; j < 4; ++j) {
    for (std::uint32_t i = 0; i < 4; ++i) {
      const std::uint32_t a = j * 5 + i, b = a + 1, d = a + 5, e = a + 6;
      if ((i + j) % 2 == 0) {
        s.addPolygon({a, b, e}, m);
        s.addPolygon({a, e, d}, m);
      } else {
        s.addPolygon({a, b, d}, m);
        s.addPolygon({b, e, d}, m);
      }
    }
  }
  return s;
}

std::vector<glm::dvec2> gridOutline(glm::vec2 centre, float cell, double angle) {
  const double c = std::cos(angle), sn = std::sin(angle), h = 2.0 * cell;
  std::vector<glm::dvec2> out;
  for (auto [u, v] : {std::pair{-h, -h}, {h, -h}, {h, h}, {-h, h}})
    out.push_back({centre.x + c * u - sn * v, centre.y + sn * u + c * v});
  return out;
}

TEST_P(RasterProperties, RotatedQuadGridHasNoOverlapOrHole) {
  const Camera cam = pixelCamera(256, 256);
  for (int seed = 1; seed <= 3 * testing::countScale(); ++seed) {
    Rng rng(static_cast<std::uint64_t>(2000 + seed));
    const glm::vec2 centre(128.0f + rng.uniform(-4.0f, 4.0f), 128.0f + rng.uniform(-4.0f, 4.0f));
    const float cell = rng.uniform(20.0f, 40.0f);
    for (int k = 0; k < 15; ++k) {
      const double angle = 0.5 * kPi * k / 14.0;
      const std::string label =
          "grid seed " + std::to_string(seed) + " angle " + std::to_string(angle);
      SCOPED_TRACE(label);
      const Frame f = render(quadGrid(centre, cell, angle), cam, countEveryFragment(GetParam()));
      const std::vector<glm::dvec2> outline = gridOutline(centre, cell, angle);
      expectExactCover(checkCoverage(f, &outline), label);
    }
  }
}

// Row 2 with perspective: the same grid on a plane tilted away from a perspective camera, so
// the projected w of its vertices spans about [0.1, 4].
TEST_P(RasterProperties, PerspectiveQuadGridHasNoOverlapOrHole) {
  Camera cam;
  cam.width = 256;
  cam.height = 256;
  cam.fov_deg = 90.0f;
  cam.eye = {0.0f, 0.0f, 0.0f};
  cam.target = {0.0f, 0.0f, -1.0f};
  cam.near = 0.05f;
  cam.far = 10.0f;
  const glm::mat4 mvp = cam.projection() * cam.view();
  for (int k = 0; k < 15; ++k) {
    const double angle = 0.5 * kPi * k / 14.0;
    const std::string label = "perspective grid angle " + std::to_string(angle);
    SCOPED_TRACE(label);
    // The grid in the plane z = -(2.05 + 1.95 y / 1) rotated about z: w = -z runs 0.1 .. 4.
    Scene s = quadGrid({0.0f, 0.0f}, 0.45f, angle);
    Scene tilted;
    const std::uint32_t m = tilted.addMaterial({});
    tilted.beginObject("grid");
    for (const glm::vec3& p : s.positions())
      tilted.addVertex({p.x, p.y * 0.5f, -2.05f - 1.95f * p.y / 1.28f});
    for (PolygonId id = 0; id < s.polygonCount(); ++id) {
      const auto poly = s.polygon(id);
      tilted.addPolygon(std::span<const std::uint32_t>(poly.data(), poly.size()), m);
    }
    const Frame f = render(tilted, cam, countEveryFragment(GetParam()));
    // Outline: the projected outer corners (straight edges stay straight under projection).
    const double c = std::cos(angle), sn = std::sin(angle), h = 2.0 * 0.45;
    std::vector<glm::dvec2> outline;
    for (auto [u, v] : {std::pair{-h, -h}, {h, -h}, {h, h}, {-h, h}}) {
      const double x = c * u - sn * v, y = sn * u + c * v;
      const glm::dvec4 q = glm::dmat4(mvp) * glm::dvec4(x, y * 0.5, -2.05 - 1.95 * y / 1.28, 1.0);
      outline.push_back(
          {(q.x / q.w * 0.5 + 0.5) * cam.width, (q.y / q.w * 0.5 + 0.5) * cam.height});
    }
    expectExactCover(checkCoverage(f, &outline), label);
  }
}

// Row 2: one quad far larger than a 64x64 viewport, rotated through many angles: every pixel
// is written exactly once (the shared diagonal crosses the viewport).
TEST_P(RasterProperties, HugeQuadCoversViewportOnce) {
  const Camera cam = pixelCamera(64, 64);
  Rng rng(3001);
  const int angles = 180 * testing::countScale();
  for (int k = 0; k < angles; ++k) {
    const double angle = 0.5 * kPi * k / angles + rng.uniform(0.0f, 1e-3f);
    const glm::vec2 centre(32.0f + rng.uniform(-20.0f, 20.0f), 32.0f + rng.uniform(-20.0f, 20.0f));
    const float half = rng.uniform(200.0f, 20000.0f);
    const std::string label = "huge quad k " + std::to_string(k);
    SCOPED_TRACE(label);
    Scene s;
    const std::uint32_t m = s.addMaterial({});
    s.beginObject("quad");
    const double c = std::cos(angle), sn = std::sin(angle);
    for (auto [u, v] : {std::pair{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}}) {
      s.addVertex({static_cast<float>(centre.x + half * (c * u - sn * v)),
                   static_cast<float>(centre.y + half * (sn * u + c * v)), 0.0f});
    }
    s.addPolygon({0, 1, 2}, m);
    s.addPolygon({0, 2, 3}, m);
    const Frame f = render(s, cam, countEveryFragment(GetParam()));
    expectExactCover(checkCoverage(f, nullptr), label);
  }
}

HSR_INSTANTIATE_FOR_ALGORITHMS_WITH(RasterProperties, kExactSharedCoverage);

}  // namespace
}  // namespace hsr
