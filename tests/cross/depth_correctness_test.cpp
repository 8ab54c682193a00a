// Depth correctness, docs/testing.md row 5 (dEQP fragment_ops.depth style), for every algorithm:
//   - a gradient quad whose window depth runs from 0 to 1 (NDC -1 to 1) across the viewport
//     crosses a flat quad at NDC z = 0: the visible surface switches at the analytic column
//     (within 1 px) on every row, in either drawing order, for several gradient directions;
//   - the 8 depth functions, with several clear depths and the depth mask on and off, give
//     at every pixel what the GL rule computed from the two analytic depths says (pixels
//     within 1 px of a line where two different depths meet are skipped); exact ties come
//     from drawing a quad twice and from clearing to the flat quad's own depth;
//   - random interpenetrating triangle pairs under perspective: no pixel where the reference
//     z-buffer is unambiguous shows the far surface (or anything else).
// Orthographic cases use the pixel camera (world x, y = window x, y; window depth
// (9 - z) / 19 for world z), so every analytic depth is exact.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <utility>
#include <string>
#include <vector>

#include "cross/figures.hpp"
#include "cross/random_scenes.hpp"
#include "cross/reference_zbuffer.hpp"
#include "hsr/error.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

constexpr int kSize = 256;
constexpr double kPi = 3.14159265358979323846;
// Largest |stored depth - analytic depth| accepted: float32 depth interpolated along a span.
constexpr double kDepthTolerance = 2e-5;

// World z under the pixel camera for a window depth (eye at z = 10, near 1, far 20, ortho).
float worldZ(double window_depth) { return static_cast<float>(9.0 - 19.0 * window_depth); }

// The gradient: window depth (p . dir - lo) / (hi - lo) over the viewport, 0 at one corner
// and 1 at the opposite one.
struct Gradient {
  double cx, sy, lo, hi;  // dir = (cos, sin); lo/hi = min/max of p . dir over the corners
  explicit Gradient(double degrees) {
    cx = std::cos(degrees * kPi / 180.0);
    sy = std::sin(degrees * kPi / 180.0);
    if (std::abs(cx) < 1e-15) cx = 0.0;
    if (std::abs(sy) < 1e-15) sy = 0.0;
    lo = hi = 0.0;
    for (double x : {0.0, double(kSize)})
      for (double y : {0.0, double(kSize)}) {
        lo = std::min(lo, x * cx + y * sy);
        hi = std::max(hi, x * cx + y * sy);
      }
  }
  double depth(double x, double y) const { return (x * cx + y * sy - lo) / (hi - lo); }
  // The x on row centre y where the depth equals z (the gradient must not run along y).
  double columnOf(double z, double y) const { return (z * (hi - lo) + lo - y * sy) / cx; }
};

// Viewport-sized quads in drawing order: the gradient (true) or the flat one at window depth
// 0.5, NDC z = 0 (false). Drawing one twice gives two polygons with bit-identical depths.
Scene gradientScene(const Gradient& g, std::initializer_list<bool> gradients) {
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  const float w = kSize, h = kSize;
  for (bool gradient : gradients) {
    if (gradient) {
      s.addPolygonVertices({{0, 0, worldZ(g.depth(0, 0))},
                            {w, 0, worldZ(g.depth(w, 0))},
                            {w, h, worldZ(g.depth(w, h))},
                            {0, h, worldZ(g.depth(0, h))}},
                           m);
    } else {
      s.addPolygonVertices({{0, 0, -0.5f}, {w, 0, -0.5f}, {w, h, -0.5f}, {0, h, -0.5f}}, m);
    }
  }
  return s;
}

bool glDepthPasses(DepthFunc f, double z, double stored) {
  switch (f) {
    case DepthFunc::Never:
      return false;
    case DepthFunc::Less:
      return z < stored;
    case DepthFunc::Equal:
      return z == stored;
    case DepthFunc::LEqual:
      return z <= stored;
    case DepthFunc::Greater:
      return z > stored;
    case DepthFunc::NotEqual:
      return z != stored;
    case DepthFunc::GEqual:
      return z >= stored;
    case DepthFunc::Always:
      return true;
  }
  return false;
}

const char* depthFuncName(DepthFunc f) {
  static const char* names[] = {"never",   "less",     "equal",  "lequal",
                                "greater", "notequal", "gequal", "always"};
  return names[static_cast<int>(f)];
}

TEST(DepthCorrectness, GradientQuadCrossesFlatQuadAtTheAnalyticColumn) {
  const Camera camera = testing::pixelCamera(kSize, kSize);
  const double angles[] = {0.0, 10.0, 25.0, 40.0, 180.0, 205.0, 320.0};
  for (const AlgorithmInfo* ap : testing::algorithmsWith("DepthCorrectness.GradientQuad", 0)) {
    const AlgorithmInfo& algo = *ap;
    SCOPED_TRACE("algorithm " + std::string(algo.name));
    std::uint64_t rows = 0, checked = 0, wrong = 0;
    double max_offset = 0.0, max_dz = 0.0;
    for (double angle : angles) {
      const Gradient g(angle);
      for (bool gradient_first : {true, false}) {
        SCOPED_TRACE("gradient at " + std::to_string(angle) + " degrees, drawn " +
                     (gradient_first ? "first" : "second"));
        const PolygonId gid = gradient_first ? 0 : 1, fid = 1 - gid;
        RenderOptions o;
        o.algorithm = std::string(algo.name);
        const Frame f = render(gradientScene(g, {gradient_first, !gradient_first}), camera, o);
        ASSERT_EQ(f.ids.size(), std::size_t(kSize) * kSize);
        int reported = 0;
        for (int y = 0; y < kSize; ++y) {
          rows++;
          const double cy = y + 0.5;
          const double column = g.columnOf(0.5, cy);  // where the gradient meets NDC z = 0
          for (int x = 0; x < kSize; ++x) {
            const double cx = x + 0.5;
            const std::size_t k = static_cast<std::size_t>(kSize - 1 - y) * kSize + x;
            const double zg = g.depth(cx, cy);
            const PolygonId expected = zg < 0.5 ? gid : fid;
            const PolygonId got = f.ids[k];
            if (got != expected) max_offset = std::max(max_offset, std::abs(cx - column));
            if (got == gid) max_dz = std::max(max_dz, std::abs(f.depth[k] - zg));
            if (got == fid) max_dz = std::max(max_dz, std::abs(f.depth[k] - 0.5));
            if (std::abs(cx - column) <= 1.0) continue;  // the line's own pixels
            checked++;
            if (got == expected) continue;
            wrong++;
            if (reported++ < 5 && wrong <= 40)
              ADD_FAILURE() << "pixel (" << x << ", " << y << ") [y up]: expected polygon "
                            << expected << " (gradient z " << zg
                            << " vs 0.5; line at x = " << column << "), got " << got;
          }
        }
      }
    }
    EXPECT_EQ(wrong, 0u);
    EXPECT_LE(max_offset, 1.0) << "the visible surface switches away from the analytic column";
    EXPECT_LE(max_dz, kDepthTolerance);
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "row 5 %s (gradient vs flat quad): %zu directions x 2 orders, %s rows, %s pixels "
                  "checked, %s wrong; switch within %.4f px of the analytic column; max |dz| %.2e",
                  std::string(algo.name).c_str(), std::size(angles), testing::grouped(rows).c_str(),
                  testing::grouped(checked).c_str(), testing::grouped(wrong).c_str(), max_offset,
                  max_dz);
    testing::printFigures(buf);
  }
}

TEST(DepthCorrectness, EveryDepthFuncFollowsTheGlRule) {
  const Camera camera = testing::pixelCamera(kSize, kSize);
  const DepthFunc funcs[] = {DepthFunc::Never,  DepthFunc::Less,    DepthFunc::Equal,
                             DepthFunc::LEqual, DepthFunc::Greater, DepthFunc::NotEqual,
                             DepthFunc::GEqual, DepthFunc::Always};
  const double angles[] = {0.0, 25.0, 205.0};
  for (const AlgorithmInfo* ap :
       testing::algorithmsWith("DepthCorrectness.EveryDepthFunc", kDepthFuncs | kDepthMask)) {
    const AlgorithmInfo& algo = *ap;
    SCOPED_TRACE("algorithm " + std::string(algo.name));
    // The depth the flat quad writes: a constant within a rounding of 0.5. Clearing to exactly
    // that value (as dEQP draws a surface twice) is what makes EQUAL, LEQUAL and GEQUAL pass.
    RenderOptions flat_options;
    flat_options.algorithm = std::string(algo.name);
    const Frame flat_alone = render(gradientScene(Gradient(0.0), {false}), camera, flat_options);
    const float z_flat = flat_alone.depth[0];
    ASSERT_NEAR(z_flat, 0.5, 1e-6);
    for (float z : flat_alone.depth)
      ASSERT_EQ(z, z_flat) << "the flat quad's depth is not constant";
    const double clears[] = {1.0, 0.0, 0.75, z_flat};
    std::uint64_t renders = 0, checked = 0, wrong = 0, drawn = 0;
    std::vector<std::string> unsupported;
    double max_dz = 0.0;
    for (DepthFunc func : funcs) {
      SCOPED_TRACE(std::string("depth func ") + depthFuncName(func));
      bool supported = true;
      for (double angle : angles) {
        const Gradient g(angle);
        // Gradient then flat, flat then gradient, and each drawn twice (exactly equal depths,
        // where EQUAL, LEQUAL, GEQUAL and NOTEQUAL differ from their strict neighbours).
        const std::pair<bool, bool> pairs[] = {
            {true, false}, {false, true}, {true, true}, {false, false}};
        for (const auto& [first_gradient, second_gradient] : pairs) {
          const Scene scene = gradientScene(g, {first_gradient, second_gradient});
          const char* names[] = {"flat", "gradient"};
          for (double clear : clears) {
            for (bool mask : {true, false}) {
              SCOPED_TRACE("gradient at " + std::to_string(angle) +
                           " degrees; drawn: " + names[first_gradient] + ", then " +
                           names[second_gradient] + "; clear depth " + std::to_string(clear) +
                           ", depth mask " + (mask ? "on" : "off"));
              RenderOptions o;
              o.algorithm = std::string(algo.name);
              o.depth_func = func;
              o.clear_depth = static_cast<float>(clear);
              o.depth_mask = mask;
              Frame f;
              try {
                f = render(scene, camera, o);
              } catch (const Error& e) {
                // An algorithm may refuse a depth function it does not implement (never ignore
                // it silently); LESS, the default, every algorithm must do.
                ASSERT_NE(func, DepthFunc::Less) << e.what();
                supported = false;
                break;
              }
              renders++;
              int reported = 0;
              for (int y = 0; y < kSize; ++y) {
                const double cy = y + 0.5;
                // Pixels within 1 px (along the row) of a line where two different depths meet.
                const double meet = first_gradient != second_gradient ? g.columnOf(0.5, cy) : -1e9;
                const double at_clear =
                    first_gradient || second_gradient ? g.columnOf(clear, cy) : -1e9;
                for (int x = 0; x < kSize; ++x) {
                  const double cx = x + 0.5;
                  if (std::abs(cx - meet) <= 1.0 || std::abs(cx - at_clear) <= 1.0) continue;
                  // The GL rule: each fragment in drawing order against the stored depth.
                  const double zq[2] = {first_gradient ? g.depth(cx, cy) : z_flat,
                                        second_gradient ? g.depth(cx, cy) : z_flat};
                  double stored = clear;
                  PolygonId expected = kNoPolygon;
                  for (PolygonId q = 0; q < 2; ++q) {
                    if (!glDepthPasses(func, zq[q], stored)) continue;
                    expected = q;
                    if (mask) stored = zq[q];
                  }
                  const double expected_z = stored;
                  const std::size_t k = static_cast<std::size_t>(kSize - 1 - y) * kSize + x;
                  checked++;
                  drawn += expected != kNoPolygon;
                  const bool id_ok = f.ids[k] == expected;
                  const double dz = std::abs(f.depth[k] - expected_z);
                  if (id_ok) max_dz = std::max(max_dz, dz);
                  if (id_ok && dz <= kDepthTolerance) continue;
                  wrong++;
                  if (reported++ < 3 && wrong <= 40)
                    ADD_FAILURE() << "pixel (" << x << ", " << y << ") [y up]: expected polygon "
                                  << static_cast<int>(expected) << " at depth " << expected_z
                                  << " (fragment depths " << zq[0] << ", " << zq[1] << "), got "
                                  << static_cast<int>(f.ids[k]) << " at depth " << f.depth[k];
                }
              }
            }
            if (!supported) break;
          }
          if (!supported) break;
        }
        if (!supported) break;
      }
      if (!supported) unsupported.push_back(depthFuncName(func));
    }
    // The z-buffer is the reference implementation of the GL state: it does all eight.
    if (algo.name == "zbuffer") {
      EXPECT_TRUE(unsupported.empty());
    }
    EXPECT_EQ(wrong, 0u);
    EXPECT_GT(drawn, checked / 4) << "the cases draw too little to prove anything";
    std::string refused;
    for (const std::string& n : unsupported) refused += (refused.empty() ? "" : ", ") + n;
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "row 5 %s (depth funcs): %zu of 8 supported%s%s%s, %s renders (4 clear depths x "
                  "mask on/off x 4 draw pairs x %zu directions), %s pixels checked (%s drawn), %s "
                  "wrong; max |dz| %.2e",
                  std::string(algo.name).c_str(), 8 - unsupported.size(),
                  refused.empty() ? "" : " (refused: ", refused.c_str(), refused.empty() ? "" : ")",
                  testing::grouped(renders).c_str(), std::size(angles),
                  testing::grouped(checked).c_str(), testing::grouped(drawn).c_str(),
                  testing::grouped(wrong).c_str(), max_dz);
    testing::printFigures(buf);
  }
}

// Two triangles through one point in different planes, both facing the camera within about
// 35 degrees, drawn in a random order.
Scene interpenetratingPair(std::uint64_t seed) {
  using namespace testing::detail_scenes;
  testing::Rng rng(seed * 0xA24BAED4963EE407ull + 0x9FB21C651E98DF25ull);
  const glm::vec3 eye = testing::agreementCamera(seed).eye;
  Scene s;
  s.addMaterial({{1, 0, 0}, 1});
  s.addMaterial({{0, 0, 1}, 1});
  const glm::vec3 c = randomInCube(rng, 0.8f);
  const float r = rng.uniform(0.3f, 0.9f);
  for (std::uint32_t k = 0; k < 2; ++k) {
    glm::vec3 u, v;
    planeBasis(facing(rng, c, eye), &u, &v);
    const std::array<glm::vec3, 3> t = triangleAround(rng, c, u, v, r);
    s.addPolygonVertices({t[0], t[1], t[2]}, k);
  }
  return s;
}

// One test per algorithm (InterpenetratingPairs.NeverShowTheFarSurface/ALGORITHM), so that CTest
// runs them side by side; each computes the reference of every pair itself.
class InterpenetratingPairs : public testing::EveryAlgorithm {};

TEST_P(InterpenetratingPairs, NeverShowTheFarSurface) {
  // A quarter of them in the sanitizer leg's tier (testing::legCases)
  const int pairs = testing::legCases(1000 * testing::countScale(), 4);
  const AlgorithmInfo& algo = findAlgorithm(GetParam());
  std::uint64_t far_shown = 0, mismatches = 0;
  std::uint64_t both = 0, both_unambiguous = 0, pairs_with_both = 0;
  std::vector<std::uint8_t> covered_by_both(std::size_t(kSize) * kSize);
  Frame f;  // rendered into again for every pair: no fresh memory per render (the sanitizers')
  for (int i = 0; i < pairs; ++i) {
    const std::uint64_t seed = 50000 + static_cast<std::uint64_t>(i);
    SCOPED_TRACE("interpenetratingPair(" + std::to_string(seed) + ")");
    const Scene scene = interpenetratingPair(seed);
    const Camera camera = testing::agreementCamera(seed);
    const testing::ReferenceFrame ref = testing::referenceZBuffer(scene, camera);
    ASSERT_TRUE(ref.valid) << ref.problem;
    // The two triangles as the reference projects them: who covers each centre.
    testing::RefPolygon tri[2];
    std::string problem;
    for (PolygonId q = 0; q < 2; ++q) {
      ASSERT_TRUE(
          testing::projectPolygon(scene, q, testing::RefProjection(camera), &tri[q], &problem));
    }
    bool any_both = false;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const std::size_t k = ref.index(x, y);
        const double cx = x + 0.5, cy = y + 0.5;
        covered_by_both[k] = !tri[0].degenerate && !tri[1].degenerate && tri[0].contains(cx, cy) &&
                             tri[1].contains(cx, cy);
        both += covered_by_both[k];
        any_both = any_both || covered_by_both[k];
        both_unambiguous += covered_by_both[k] && !ref.ambiguous[k];
      }
    pairs_with_both += any_both;
    RenderOptions o;
    o.algorithm = std::string(algo.name);
    o.threads = 1 + static_cast<int>(seed % 2);
    render(scene, camera, o, f);
    ASSERT_EQ(f.ids.size(), ref.ids.size());
    int reported = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const std::size_t k = ref.index(x, y);
        if (ref.ambiguous[k] || f.ids[k] == ref.ids[k]) continue;
        mismatches++;
        far_shown += covered_by_both[k] && f.ids[k] == 1 - ref.ids[k];
        if (reported++ < 3 && mismatches <= 40) {
          const double cx = x + 0.5, cy = y + 0.5;
          ADD_FAILURE() << "unambiguous pixel (" << x << ", " << y << ") [y up]: expected "
                        << static_cast<int>(ref.ids[k]) << " (ref z0 " << tri[0].depthAt(cx, cy)
                        << ", z1 " << tri[1].depthAt(cx, cy) << "), got "
                        << static_cast<int>(f.ids[k]) << " at depth " << f.depth[k];
        }
      }
  }
  EXPECT_GT(both_unambiguous, both / 2) << "too few decidable overlap pixels to prove anything";
  EXPECT_EQ(mismatches, 0u);
  EXPECT_EQ(far_shown, 0u);
  testing::printFigures(
      "row 5 " + std::string(algo.name) + " (interpenetrating pairs): " + testing::grouped(pairs) +
      " pairs (" + testing::grouped(pairs_with_both) + " overlapping on screen), " +
      testing::grouped(both) + " pixels covered by both, " + testing::grouped(both_unambiguous) +
      " of them unambiguous, " + testing::grouped(far_shown) + " show the far surface; " +
      testing::grouped(mismatches) + " unambiguous mismatches in all");
}

HSR_INSTANTIATE_FOR_EVERY_ALGORITHM(InterpenetratingPairs);

}  // namespace
}  // namespace hsr
