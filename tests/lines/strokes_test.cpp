// Segments into pen strokes (lines/strokes.hpp): duplicates and overlaps drawn once,
// collinear runs joined, chains connected, the first layer winning over the second, no length
// lost; checked on small cases whose answer is known and on seeded random segments against a
// brute-force union of intervals per line.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include <glm/geometric.hpp>

#include "cross/figures.hpp"
#include "lines/strokes.hpp"
#include "test_util.hpp"

namespace hsr::detail {
namespace {

using glm::dvec2;

constexpr double kTol = 1e-6;

double lengthOf(const std::vector<Stroke>& strokes) {
  double l = 0;
  for (const Stroke& s : strokes)
    for (std::size_t i = 1; i < s.points.size(); ++i)
      l += glm::length(s.points[i] - s.points[i - 1]);
  return l;
}

// Every stroke has two points or more, no zero-length piece, and turns somewhere between any
// three consecutive points (collinear runs were joined).
void expectWellFormed(const std::vector<Stroke>& strokes) {
  for (const Stroke& s : strokes) {
    ASSERT_GE(s.points.size(), 2u);
    for (std::size_t i = 1; i < s.points.size(); ++i)
      EXPECT_GT(glm::length(s.points[i] - s.points[i - 1]), kTol);
    for (std::size_t i = 2; i < s.points.size(); ++i) {
      const dvec2 u = s.points[i - 1] - s.points[i - 2], v = s.points[i] - s.points[i - 1];
      const bool straight_on =
          std::abs(u.x * v.y - u.y * v.x) <= 1e-9 * glm::length(u) * glm::length(v) &&
          glm::dot(u, v) > 0;
      EXPECT_FALSE(straight_on) << "a collinear run left in pieces";
    }
  }
}

struct Merged {
  std::vector<Stroke> first, second;
  StrokeStats first_stats, second_stats;
};

Merged merge(const std::vector<StrokeSegment>& first,
             const std::vector<StrokeSegment>& second = {}) {
  Merged m;
  mergeStrokes(first, second, kTol, &m.first, &m.second, &m.first_stats, &m.second_stats);
  expectWellFormed(m.first);
  expectWellFormed(m.second);
  return m;
}

TEST(Strokes, DuplicatesAndReversedCopiesAreDrawnOnce) {
  const Merged m = merge({{{0, 0}, {4, 0}}, {{0, 0}, {4, 0}}, {{4, 0}, {0, 0}}});
  ASSERT_EQ(m.first.size(), 1u);
  EXPECT_NEAR(lengthOf(m.first), 4.0, 1e-12);
}

TEST(Strokes, OverlappingAndTouchingCollinearSegmentsBecomeOne) {
  const Merged m = merge({{{0, 1}, {2, 1}}, {{1, 1}, {3, 1}}, {{3, 1}, {5, 1}}, {{7, 1}, {8, 1}}});
  ASSERT_EQ(m.first.size(), 2u);
  EXPECT_NEAR(lengthOf(m.first), 6.0, 1e-12);
  for (const Stroke& s : m.first) EXPECT_EQ(s.points.size(), 2u);
  EXPECT_EQ(m.first_stats.segments, 4u);
  EXPECT_EQ(m.first_stats.strokes, 2u);
}

TEST(Strokes, TheFirstLayerWinsWhereBothCover) {
  // Hidden [0, 4] with a visible [1, 2] on it: hidden keeps [0, 1] and [2, 4]
  const Merged m = merge({{{1, 0}, {2, 0}}}, {{{0, 0}, {4, 0}}});
  EXPECT_NEAR(lengthOf(m.first), 1.0, 1e-12);
  EXPECT_NEAR(lengthOf(m.second), 3.0, 1e-12);
  EXPECT_EQ(m.second.size(), 2u);
}

TEST(Strokes, ChainsFollowSharedEndsAndLoopsClose) {
  // A square from four segments given in no order, one reversed
  const Merged m = merge({{{1, 0}, {1, 1}}, {{0, 0}, {1, 0}}, {{0, 1}, {1, 1}}, {{0, 1}, {0, 0}}});
  ASSERT_EQ(m.first.size(), 1u);
  EXPECT_EQ(m.first[0].points.size(), 5u);
  EXPECT_EQ(m.first[0].points.front(), m.first[0].points.back());
  EXPECT_NEAR(lengthOf(m.first), 4.0, 1e-12);
  // A polyline stops where kinds change and where three pieces meet
  const Merged t = merge(
      {{{0, 0}, {1, 0}, 0}, {{1, 0}, {2, 1}, 1}, {{1, 0}, {1, -1}, 0}, {{1, -1}, {2, -2}, 0}});
  EXPECT_NEAR(lengthOf(t.first), 1 + std::sqrt(2.0) + 1 + std::sqrt(2.0), 1e-12);
  for (const Stroke& s : t.first) EXPECT_TRUE(s.kind == 0 || s.points.size() == 2u);
}

TEST(Strokes, PiecesOfSeveralKindsKeepTheLowestWhereTheyOverlap) {
  const Merged m = merge({{{0, 0}, {3, 0}, 2}, {{1, 0}, {2, 0}, 0}});
  double by_kind[3] = {0, 0, 0};
  for (const Stroke& s : m.first) by_kind[s.kind] += lengthOf({s});
  EXPECT_NEAR(by_kind[0], 1.0, 1e-12);
  EXPECT_NEAR(by_kind[2], 2.0, 1e-12);
}

// Random segments on a few lines (so they overlap) and a few at random: the strokes' length is
// the union's, measured by merging intervals per line by brute force; every stroke connected.
TEST(Strokes, NoLengthIsLostOrDrawnTwiceOnRandomSegments) {
  testing::Rng rng(11);
  int cases = 0;
  double total_union = 0, total_segments = 0;
  StrokeStats last;
  for (int c = 0; c < 50 * testing::countScale(); ++c, ++cases) {
    std::vector<StrokeSegment> segs;
    // Lines through integer points with small integer directions: exact overlaps
    // (line) -> [s0, s1]
    std::map<std::pair<int, int>, std::vector<std::pair<double, double>>> per_line;
    for (int k = 0; k < 40; ++k) {
      const int line = static_cast<int>(rng.next() % 5);
      const dvec2 o(line * 3.0, line * 2.0);
      const dvec2 d = glm::normalize(dvec2(1 + line, 2 - line));
      double s0 = static_cast<double>(rng.next() % 20), s1 = static_cast<double>(rng.next() % 20);
      if (s0 == s1) continue;
      if (s1 < s0) std::swap(s0, s1);
      segs.push_back({o + d * s0, o + d * s1, 0});
      per_line[{line, 0}].push_back({s0, s1});
      total_segments += s1 - s0;
    }
    double expected = 0;
    for (auto& [line, iv] : per_line) {
      std::sort(iv.begin(), iv.end());
      double a = iv[0].first, b = iv[0].second;
      for (const auto& [u, v] : iv) {
        if (u > b)
          expected += b - a, a = u, b = v;
        else
          b = std::max(b, v);
      }
      expected += b - a;
    }
    const Merged m = merge(segs);
    EXPECT_NEAR(lengthOf(m.first), expected, 1e-9 * expected) << "case " << c;
    EXPECT_NEAR(m.first_stats.length, expected, 1e-9 * expected);
    total_union += expected;
    last = m.first_stats;
  }
  testing::printFigures("strokes: " + std::to_string(cases) +
                        " random cases, the strokes' length equals the "
                        "union of the segments (" +
                        std::to_string(static_cast<long>(total_segments)) + " given, " +
                        std::to_string(static_cast<long>(total_union)) + " drawn)");
}

TEST(Strokes, OrderingShortensPenUpTravelOnAGrid) {
  // A grid of short separate dashes given in a scattered order
  std::vector<StrokeSegment> segs;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) {
      const int x = (i * 7) % 20, y = (j * 13) % 20;
      segs.push_back({{x * 10.0, y * 10.0}, {x * 10.0 + 3, y * 10.0}, 0});
    }
  const Merged m = merge(segs);
  EXPECT_EQ(m.first.size(), 400u);
  EXPECT_NEAR(penUpTravel(m.first), m.first_stats.pen_up, 1e-9);
  // As short as the boustrophedon, row by row and back (7 between dashes, 10 between rows);
  // the order the strokes came in travels more than twice that
  EXPECT_LE(m.first_stats.pen_up, 20 * 19 * 7 + 19 * 10 + 1e-9);
  EXPECT_GT(m.first_stats.pen_up_unordered, 2 * m.first_stats.pen_up);
}

// The ends left after half the strokes are drawn lie on one line far from the pen: the grid
// made again for them is one cell high, and the pen's cell must be found without passing
// int's range (UBSan caught a float-to-int overflow here).
TEST(Strokes, OrderingWhenTheEndsLeftLieOnOneLine) {
  std::vector<StrokeSegment> segs;
  for (int i = 0; i < 6; ++i) segs.push_back({{i * 2.0, -5000.0}, {i * 2.0, -4990.0}, 0});
  for (int i = 0; i < 5; ++i) segs.push_back({{i * 10.0, 0.0}, {i * 10.0 + 3.0, 0.0}, 0});
  const Merged m = merge(segs);
  EXPECT_EQ(m.first.size(), 11u);
  EXPECT_NEAR(m.first_stats.length, 6 * 10.0 + 5 * 3.0, 1e-9);
  EXPECT_TRUE(std::isfinite(m.first_stats.pen_up));
  EXPECT_NEAR(penUpTravel(m.first), m.first_stats.pen_up, 1e-9);
}

}  // namespace
}  // namespace hsr::detail
