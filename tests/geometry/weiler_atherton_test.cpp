// Weiler-Atherton clipping (docs/testing.md row 12), the checks that need no oracle: invalid
// regions refused with a reason, empty operands, crossings as exact rationals, and an exact
// vertex rounded once to the nearest double. The comparisons with CGAL's exact Boolean
// operations (random pairs, the degenerate catalogue, chains, fuzz findings) are in
// tests/agreement/cgal_clip_test.cpp, with the other peers.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gmpxx.h>

#include "core/random.hpp"
#include "hsr/clipping.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

TEST(WeilerAtherton, InvalidRegionsAreRefusedWithAReason) {
  struct Bad {
    GridRegion region;
    const char* says;
  };
  const GridRing square{{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  const Bad bad[] = {
      {{{{{0, 0}, {4, 0}}, {}}}, "fewer than 3 vertices"},
      {{{{{0, 0}, {4, 0}, {4, 0}, {0, 4}}, {}}}, "repeated"},
      {{{{{0, 0}, {4, 0}, {8, 0}}, {}}}, "area 0"},
      {{{{{0, 0}, {4, 4}, {4, 0}, {0, 3}}, {}}}, "cross"},      // a bow tie
      {{{{{0, 0}, {6, 0}, {3, 0}, {3, 3}}, {}}}, "run along"},  // a spike
      {{{{{0, 0}, {kClipCoordinateLimit + 1, 0}, {0, 5}}, {}}}, "beyond"},
      {{{square, {{{5, 5}, {6, 5}, {6, 6}}}}}, "not inside its outer ring"},
      {{{{{0, 0}, {8, 0}, {8, 8}, {0, 8}},
         {{{1, 1}, {1, 7}, {7, 7}, {7, 1}}, {{2, 2}, {2, 3}, {3, 3}}}}},
       "overlaps"},                                                  // nested holes
      {{{square, {}}, {{{1, 1}, {3, 1}, {3, 3}}, {}}}, "overlaps"},  // polygon in polygon
      {{{square, {}}, {{{2, 2}, {6, 2}, {6, 6}}, {}}}, "cross"},
      {{{square, {}}, {{{0, 0}, {4, 0}, {2, -3}}, {}}}, "run along"},  // a shared edge
      {{{{{0, 0}, {4, 0}, {2, 2}, {4, 4}, {0, 4}, {2, 2}}, {}}},
       "touch"},  // a ring through one point twice
      // fuzz_clip's first finding: two polygons touching at two vertices, one arc of the L
      // inside the quad and the rest outside (a sample point of each ring said "apart")
      {{{{{0, 0}, {4, 0}, {4, 2}, {2, 2}, {2, 4}, {0, 4}}, {}},
        {{{2, 2}, {4, 4}, {5, 2}, {4, 0}}, {}}},
       "overlaps"},
  };
  for (const Bad& b : bad) {
    const std::string reason = invalidRegionReason(b.region);
    EXPECT_NE(reason.find(b.says), std::string::npos)
        << "expected \"" << b.says << "\", got \"" << reason << "\"";
  }
  // Touching at points is allowed: a hole touching its ring, polygons touching at a corner
  EXPECT_EQ(invalidRegionReason({{square, {{{0, 2}, {2, 3}, {2, 1}}}}}), "");
  EXPECT_EQ(invalidRegionReason({{square, {}}, {{{4, 4}, {8, 4}, {8, 8}}, {}}}), "");
}

TEST(WeilerAtherton, EmptyRegionsGiveTheOtherOrNothing) {
  const GridRegion a{{{{0, 0}, {4, 0}, {4, 4}, {0, 4}}, {}}}, none;
  EXPECT_TRUE(booleanOp(a, none, BooleanOp::Intersection).empty());
  EXPECT_EQ(exactArea(booleanOp(a, none, BooleanOp::Union)), "16");
  EXPECT_EQ(exactArea(booleanOp(a, none, BooleanOp::AMinusB)), "16");
  EXPECT_TRUE(booleanOp(a, none, BooleanOp::BMinusA).empty());
  EXPECT_TRUE(booleanOp(none, none, BooleanOp::Union).empty());
}

TEST(WeilerAtherton, CrossingsAreExactRationals) {
  // Edges crossing at (7/3, 2/3)... : a square and a triangle whose crossings are not on the grid
  const GridRegion a{{{{0, 0}, {3, 0}, {3, 3}, {0, 3}}, {}}}, b{{{{1, 1}, {4, 1}, {4, 5}}, {}}};
  const ExactRegion r = booleanOp(a, b, BooleanOp::Intersection);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(exactArea(r), "5/2");  // also CGAL's
  bool rational = false;
  for (const ExactPoint& p : r[0].outer) rational = rational || p.d != 1;
  EXPECT_TRUE(rational);
}

// An exact vertex's coordinate is rounded once, to the nearest double (ties to even), the same
// on every platform: checked against GMP's exact rationals on quotients as large as a crossing's
// (|n| < 2^89, d < 2^60), small ones, exact ones and ties.
TEST(WeilerAtherton, ExactCoordinatesRoundToTheNearestDouble) {
  auto mpzOf = [](__int128 v) {
    const bool negative = v < 0;
    const unsigned __int128 m =
        negative ? -static_cast<unsigned __int128>(v) : static_cast<unsigned __int128>(v);
    mpz_class r(static_cast<unsigned long>(static_cast<std::uint64_t>(m >> 64)));
    r <<= 64;
    r += mpz_class(static_cast<unsigned long>(static_cast<std::uint64_t>(m)));
    return negative ? mpz_class(-r) : r;
  };
  auto nearest = [&](__int128 n, std::int64_t d) {
    const double got = detail::nearestQuotient(n, d);
    const mpq_class want(mpzOf(n), mpz_class(static_cast<long>(d)));
    const mpq_class err = abs(mpq_class(got) - want);
    for (const double other : {std::nextafter(got, INFINITY), std::nextafter(got, -INFINITY)}) {
      const mpq_class other_err = abs(mpq_class(other) - want);
      if (other_err < err) return false;
      if (other_err == err &&
          (static_cast<std::uint64_t>(std::abs(std::ldexp(got, -std::ilogb(got) + 52))) & 1))
        return false;  // a tie not given to the even one
    }
    return true;
  };
  detail::SplitMix64 rng(7);
  int wrong = 0, checked = 0;
  for (int i = 0; i < 20000; ++i) {
    const int n_bits = 1 + static_cast<int>(rng.next() % 89),
              d_bits = 1 + static_cast<int>(rng.next() % 60);
    const __int128 mag =
        ((static_cast<__int128>(rng.next()) << 64) | rng.next()) & ((__int128{1} << n_bits) - 1);
    const __int128 n = (rng.next() & 1) ? -mag : mag;
    const auto d = static_cast<std::int64_t>(
        std::max<std::uint64_t>(1, rng.next() & ((std::uint64_t{1} << d_bits) - 1)));
    wrong += nearest(n, d) ? 0 : 1;
    ++checked;
  }
  // Exact and tied quotients: (2^53 + 1) / 2 lies halfway between two doubles, as do its kin
  for (const auto& [n, d] : std::vector<std::pair<__int128, std::int64_t>>{
           {(__int128{1} << 54) + 2, 2},
           {(__int128{1} << 54) + 6, 2},
           {(__int128{1} << 55) + 3, 2},
           {(__int128{1} << 88) + (__int128{1} << 35), 1},
           {(__int128{1} << 88) + (__int128{3} << 35), 1},
           {-((__int128{1} << 60) + 1), 3},
           {1, 3},
           {-7, 1},
           {0, 5}}) {
    wrong += nearest(n, d) ? 0 : 1;
    ++checked;
  }
  EXPECT_EQ(wrong, 0) << "of " << checked << " quotients";
  EXPECT_EQ(detail::nearestQuotient((__int128{1} << 53) + 1, 1), 0x1p53);        // a tie: to even
  EXPECT_EQ(detail::nearestQuotient((__int128{1} << 53) + 3, 1), 0x1p53 + 4.0);  // a tie: to even
  EXPECT_EQ(detail::nearestQuotient(1, 3), 1.0 / 3.0);
}

}  // namespace
}  // namespace hsr
