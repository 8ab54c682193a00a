// Polygon planes, classification and splitting; 2D half-plane clipping.

#include <gtest/gtest.h>

#include <cstdint>
#include <cmath>

#include "core/bit_cast.hpp"
#include "geometry/clip.hpp"
#include "geometry/polygon.hpp"
#include "hsr/scene.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using detail::Plane;
using detail::PlaneSide;

Plane planeOf(const std::vector<glm::dvec3>& v) {
  return detail::canonicalPlane(v.size(), [&](std::size_t i) { return v[i]; });
}

double area(const std::vector<glm::dvec3>& v) {
  return 0.5 * glm::length(detail::newellNormal(v.size(), [&](std::size_t i) { return v[i]; }));
}

bool sameBits(double a, double b) {
  return detail::bitCast<std::uint64_t>(a) == detail::bitCast<std::uint64_t>(b);
}

// The same polygon listed from any vertex, in either direction, gives the same bits: what
// makes identical polygons tie exactly in the depth test.
TEST(PolygonPlane, CanonicalPlaneIsTheSameBitsForEveryRotationAndReversal) {
  testing::Rng rng(0x91A7E);
  for (int c = 0; c < 500; ++c) {
    std::vector<glm::dvec3> v;
    const glm::dvec3 n =
        glm::normalize(glm::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1) + 2));
    const glm::dvec3 u = glm::normalize(glm::cross(n, glm::dvec3(1, 0, 0))), w = glm::cross(n, u);
    const int count = 3 + static_cast<int>(rng.next() % 6);
    for (int k = 0; k < count; ++k) {
      const double a = 6.2831853 * k / count;
      v.push_back(glm::dvec3(
          glm::vec3(glm::dvec3(3, 1, -2) + std::cos(a) * u * 2.0 + std::sin(a) * w * 2.0)));
    }
    const Plane ref = planeOf(v);
    for (int r = 0; r < count; ++r) {
      for (bool reverse : {false, true}) {
        std::vector<glm::dvec3> x(v.begin() + r, v.end());
        x.insert(x.end(), v.begin(), v.begin() + r);
        if (reverse) std::reverse(x.begin(), x.end());
        const Plane p = planeOf(x);
        ASSERT_TRUE(sameBits(p.normal.x, ref.normal.x) && sameBits(p.normal.y, ref.normal.y) &&
                    sameBits(p.normal.z, ref.normal.z) && sameBits(p.d, ref.d))
            << "case " << c << " rotation " << r << (reverse ? " reversed" : "");
      }
    }
  }
}

struct Piece {
  std::vector<glm::dvec3> vertices;
  PolygonId id = 0;
  std::uint32_t rgba = 0;
};

TEST(PolygonSplit, PiecesKeepTheIdSumToTheAreaAndLieOnTheirSides) {
  testing::Rng rng(0x5B117);
  constexpr double kEps = 1e-9;
  int spanning = 0;
  for (int c = 0; c < 2000; ++c) {
    Piece p;
    p.id = static_cast<PolygonId>(c);
    p.rgba = 0xFF00FF00u;
    const int n = 3 + static_cast<int>(rng.next() % 8);
    for (int k = 0; k < n; ++k) {  // a convex polygon in the plane z = x / 3
      const double a = 6.2831853 * k / n;
      const double x = 2 * std::cos(a), y = 2 * std::sin(a);
      p.vertices.emplace_back(x, y, x / 3);
    }
    Plane cut;
    cut.normal = glm::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    if (glm::length(cut.normal) < 0.1) continue;
    cut.d = rng.uniform(-1.5f, 1.5f);
    const PlaneSide side = detail::classifyAgainstPlane(p.vertices, cut, kEps);
    Piece front, behind;
    detail::splitPolygon(p, cut, kEps, &front, &behind);
    EXPECT_EQ(front.id, p.id);
    EXPECT_EQ(behind.id, p.id);
    EXPECT_EQ(behind.rgba, p.rgba);
    EXPECT_NEAR(area(front.vertices) + area(behind.vertices), area(p.vertices),
                1e-9 * area(p.vertices));
    for (const glm::dvec3& v : front.vertices) EXPECT_GE(cut.distance(v), -kEps);
    for (const glm::dvec3& v : behind.vertices) EXPECT_LE(cut.distance(v), kEps);
    if (side == PlaneSide::kFront) {
      EXPECT_TRUE(behind.vertices.empty());
    }
    if (side == PlaneSide::kBehind) {
      EXPECT_TRUE(front.vertices.empty());
    }
    spanning += side == PlaneSide::kSpanning;
  }
  EXPECT_GT(spanning, 500);
}

TEST(PolygonSplit, SharedEdgeGetsOneCrossingPointFromEitherSide) {
  // Two triangles sharing the edge a-b, listed in opposite directions: the split point on
  // that edge must be the same bits, or the split mesh would crack.
  const glm::dvec3 a(0.1, 0.2, 0.3), b(1.7, -0.9, 2.3), c(0.5, 1.5, -1.0), d(1.9, 1.1, 0.7);
  Plane cut;
  cut.normal = glm::dvec3(0.3, 0.7, -0.2);
  cut.d = 0.2;  // a in front, b behind: the plane crosses the shared edge
  std::vector<glm::dvec3> f1, b1, f2, b2;
  detail::splitVertices(std::vector<glm::dvec3>{a, b, c}, cut, 1e-12, &f1, &b1);
  detail::splitVertices(std::vector<glm::dvec3>{b, a, d}, cut, 1e-12, &f2, &b2);
  int shared = 0;
  for (const glm::dvec3& p : f1)
    for (const glm::dvec3& q : f2) shared += p == q && p != a && p != b;
  EXPECT_EQ(shared, 1);
}

TEST(Clip2d, HalfPlaneClipsAreaExactlyOnAGrid) {
  std::vector<glm::dvec2> square = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  detail::clipToHalfPlane(square, 1, 0, -1);  // x >= 1
  double a = 0;
  for (std::size_t i = 0; i < square.size(); ++i)
    a += square[i].x * square[(i + 1) % square.size()].y -
         square[(i + 1) % square.size()].x * square[i].y;
  EXPECT_EQ(a / 2, 12.0);
  detail::clipToHalfPlane(square, -1, -1, 3);  // x + y <= 3
  a = 0;
  for (std::size_t i = 0; i < square.size(); ++i)
    a += square[i].x * square[(i + 1) % square.size()].y -
         square[(i + 1) % square.size()].x * square[i].y;
  EXPECT_EQ(a / 2, 2.0);
  detail::clipToHalfPlane(square, 1, 0, -10);  // x >= 10: nothing left
  EXPECT_TRUE(square.empty());
}

}  // namespace
}  // namespace hsr
