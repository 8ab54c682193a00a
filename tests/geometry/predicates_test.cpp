// Exact orientation predicates (docs/testing.md row 10, orient2d): on grids of ULP perturbations of
// nearly collinear points, where plain double evaluation gets the sign wrong, orient2d must
// agree 100% with an exact integer evaluation of the same doubles.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "cross/figures.hpp"
#include "geometry/predicates.hpp"

namespace hsr {
namespace {

using detail::orient2d;

// The exact sign of orient2d on doubles that are all multiples of 2^-shift with magnitude
// below 2^(62 - shift): scaled to integers, the determinant fits in __int128.
int exactOrient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, int shift) {
  auto q = [&](double v) { return static_cast<__int128>(std::ldexp(v, shift)); };
  const __int128 det =
      (q(b.x) - q(a.x)) * (q(c.y) - q(a.y)) - (q(b.y) - q(a.y)) * (q(c.x) - q(a.x));
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

int naiveOrient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  const double det = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

// Kettner, Mehlhorn, Pion, Schirra, Yap, "Classroom examples of robustness problems in
// geometric computations" (2008): the point p is moved over a 256 x 256 grid of ULP steps
// near the line through q and r.
TEST(Predicates, Orient2dIsExactOnUlpGridsOfNearlyCollinearPoints) {
  struct Config {
    glm::dvec2 p, q, r;
  };
  const Config configs[] = {
      {{0.5, 0.5}, {12.0, 12.0}, {24.0, 24.0}},
      {{0.50000000000002531, 0.5000000000000171},
       {17.300000000000001, 17.300000000000001},
       {24.00000000000005, 24.0000000000000053}},
      {{0.5, 0.5}, {8.8000000000000007, 8.8000000000000007}, {12.1, 12.1}},
  };
  std::uint64_t calls = 0, naive_wrong = 0, zero = 0;
  for (const Config& c : configs) {
    for (int i = 0; i < 256; ++i)
      for (int j = 0; j < 256; ++j) {
        glm::dvec2 p = c.p;
        for (int k = 0; k < i; ++k) p.x = std::nextafter(p.x, 1.0);
        for (int k = 0; k < j; ++k) p.y = std::nextafter(p.y, 1.0);
        // Every coordinate here is a multiple of 2^-53 and below 32.
        const int exact = exactOrient(p, c.q, c.r, 53);
        ASSERT_EQ(orient2d(p, c.q, c.r), exact)
            << "config p=(" << c.p.x << "," << c.p.y << ") + (" << i << "," << j << ") ulp";
        // The same triple in the other orders: the sign follows the permutation.
        ASSERT_EQ(orient2d(c.q, c.r, p), exact);
        ASSERT_EQ(orient2d(c.r, p, c.q), exact);
        ASSERT_EQ(orient2d(c.q, p, c.r), -exact);
        naive_wrong += naiveOrient(p, c.q, c.r) != exact;
        zero += exact == 0;
        calls += 4;
      }
  }
  testing::printFigures(
      "row 10 orient2d: 3 configurations x 256 x 256 ULP offsets, " + testing::grouped(calls) +
      " calls, 100% equal to the exact sign (" + testing::grouped(zero / 1) +
      " exactly collinear); plain double "
      "evaluation got " +
      testing::grouped(naive_wrong) + " of " + testing::grouped(calls / 4) + " wrong");
  EXPECT_GT(naive_wrong, 0u) << "the grids should defeat plain double evaluation";
}

// CGAL's documented example: (0, 0.3), (1, 0.6), (2, 0.9) are collinear as real numbers, but
// 0.3, 0.6 and 0.9 are not doubles; orient2d decides on the doubles the points actually are.
TEST(Predicates, CgalExampleIsDecidedOnTheDoublesNotTheDecimals) {
  const glm::dvec2 a(0.0, 0.3), b(1.0, 0.6), c(2.0, 0.9);
  const int exact = exactOrient(a, b, c, 54);  // 0.3 is a multiple of 2^-54
  EXPECT_NE(exact, 0) << "the doubles nearest 0.3, 0.6, 0.9 are not collinear";
  EXPECT_EQ(orient2d(a, b, c), exact);
  EXPECT_EQ(orient2d(c, b, a), -exact);
  std::printf("CGAL (0,0.3),(1,0.6),(2,0.9): orient2d = %d (the doubles turn %s)\n", exact,
              exact > 0 ? "counter-clockwise" : "clockwise");
}

TEST(Predicates, Orient2dOnFixedPointIsExactAtTheExtremes) {
  // Snapped 24.8 coordinates reach 2^30: products reach 2^62, differences 2^63.
  const std::int64_t big = std::int64_t(1) << 30;
  EXPECT_EQ(orient2d(-big, -big, big, -big, big, big), 1);
  EXPECT_EQ(orient2d(-big, -big, big, big, big, -big), -1);
  EXPECT_EQ(orient2d(-big, -big, 0, 0, big, big), 0);
  EXPECT_EQ(orient2d(-big, -big, 0, 0, big, big - 1), -1);
  EXPECT_EQ(orient2d(0, 0, 0, 0, 5, 7), 0);  // repeated point
}

TEST(Predicates, Orient2dHandlesRepeatedAndZeroPoints) {
  const glm::dvec2 o(0.0), p(1e-300, 1e-300), q(3.0, -2.0);
  EXPECT_EQ(orient2d(o, o, q), 0);
  EXPECT_EQ(orient2d(q, q, q), 0);
  EXPECT_EQ(orient2d(glm::dvec2(0, 0), glm::dvec2(1, 0), glm::dvec2(0, 1)), 1);
  EXPECT_EQ(orient2d(glm::dvec2(0, 0), glm::dvec2(0, 1), glm::dvec2(1, 0)), -1);
  (void)p;
}

}  // namespace
}  // namespace hsr
