// Weiler-Atherton clipping (docs/testing.md row 12) against CGAL's exact Boolean operations
// (Polygon_set_2 on the exact-constructions kernel): the areas of A∩B, A∪B, A−B and B−A must
// be equal as exact rationals, on seeded random pairs (star-shaped, comb-shaped, with holes,
// 4 to 256 vertices, on integer grids up to the coordinate limit) and on every case of the
// degenerate catalogue (clip_cases.txt) in 16 placements; the area identities hold exactly; every
// result ring is simple (CGAL's is_simple on the exact vertices), outer rings counter-clockwise
// and holes clockwise; and invalid input is refused with a reason.

#include <gtest/gtest.h>

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_set_2.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gmpxx.h>

#include "cross/figures.hpp"
#include "geometry/clip_shapes.hpp"
#include "hsr/clipping.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using CgalPolygon = CGAL::Polygon_2<K>;
using CgalPolygonWithHoles = CGAL::Polygon_with_holes_2<K>;
using CgalSet = CGAL::Polygon_set_2<K>;
using testing::grouped;

CgalPolygon cgalRing(const GridRing& r, CGAL::Orientation want) {
  CgalPolygon p;
  for (const GridPoint& v : r) p.push_back(K::Point_2(static_cast<double>(v.x), static_cast<double>(v.y)));
  if (p.orientation() != want) p.reverse_orientation();
  return p;
}

CgalSet cgalSet(const GridRegion& region) {
  CgalSet set;
  for (const GridPolygon& poly : region) {
    CgalPolygonWithHoles ph(cgalRing(poly.outer, CGAL::COUNTERCLOCKWISE));
    for (const GridRing& h : poly.holes) ph.add_hole(cgalRing(h, CGAL::CLOCKWISE));
    set.join(ph);
  }
  return set;
}

CgalSet cgalOp(const CgalSet& a, const CgalSet& b, BooleanOp op) {
  CgalSet out = op == BooleanOp::BMinusA ? b : a;
  switch (op) {
    case BooleanOp::Intersection: out.intersection(b); break;
    case BooleanOp::Union: out.join(b); break;
    case BooleanOp::AMinusB: out.difference(b); break;
    case BooleanOp::BMinusA: out.difference(a); break;
  }
  return out;
}

mpq_class toMpq(const K::FT& v) {
  std::ostringstream s;
  s << CGAL::exact(v);
  mpq_class q(s.str());
  q.canonicalize();
  return q;
}

mpq_class cgalArea(const CgalSet& set) {
  std::vector<CgalPolygonWithHoles> polys;
  set.polygons_with_holes(std::back_inserter(polys));
  K::FT a = 0;
  for (const CgalPolygonWithHoles& ph : polys) {
    a += ph.outer_boundary().area();
    for (auto h = ph.holes_begin(); h != ph.holes_end(); ++h) a += h->area();  // negative
  }
  return toMpq(a);
}

mpq_class exactAreaOf(const ExactRegion& r) { return mpq_class(exactArea(r)); }
mpq_class exactAreaOf(const GridRegion& r) { return mpq_class(exactArea(r)); }

K::FT exactCoordinate(__int128 v, std::int64_t d) {
  auto big = [](__int128 x) {
    const bool negative = x < 0;
    const unsigned __int128 m = negative ? -static_cast<unsigned __int128>(x) : static_cast<unsigned __int128>(x);
    mpz_class z(static_cast<unsigned long>(static_cast<std::uint64_t>(m >> 64)));
    z <<= 64;
    z += mpz_class(static_cast<unsigned long>(static_cast<std::uint64_t>(m)));
    return negative ? mpz_class(-z) : z;
  };
  mpq_class q(big(v), mpz_class(static_cast<long>(d)));
  q.canonicalize();
  return K::FT(K::FT::ET(q.get_mpq_t()));
}

// Every ring of the result simple, outer rings counter-clockwise, holes clockwise: "" or what
// is wrong.
std::string ringProblems(const ExactRegion& r) {
  auto check = [](const ExactRing& ring, CGAL::Orientation want) -> std::string {
    CgalPolygon p;
    for (const ExactPoint& v : ring) p.push_back(K::Point_2(exactCoordinate(v.x, v.d), exactCoordinate(v.y, v.d)));
    if (p.size() < 3) return "a ring of fewer than 3 vertices";
    if (!p.is_simple()) return "a ring that is not simple";
    if (p.orientation() != want) return want == CGAL::COUNTERCLOCKWISE ? "an outer ring clockwise" : "a hole counter-clockwise";
    return "";
  };
  for (const ExactPolygon& poly : r) {
    if (std::string s = check(poly.outer, CGAL::COUNTERCLOCKWISE); !s.empty()) return s;
    for (const ExactRing& h : poly.holes)
      if (std::string s = check(h, CGAL::CLOCKWISE); !s.empty()) return s;
  }
  return "";
}

struct Checked {
  std::uint64_t operations = 0, mismatches = 0;
};

// A region in clip_cases.txt's notation, to paste a failing pair into the catalogue.
std::string describe(const GridRegion& r) {
  std::string s;
  for (const GridPolygon& p : r) {
    auto ring = [&](const GridRing& g) {
      for (std::size_t i = 0; i < g.size(); ++i) s += (i ? ", " : "") + std::to_string(g[i].x) + " " + std::to_string(g[i].y);
    };
    s += "\n  ";
    ring(p.outer);
    for (const GridRing& h : p.holes) s += " / ", ring(h);
  }
  return s;
}

// All four operations on one pair: areas against CGAL, identities, ring validity.
void checkPair(const GridRegion& a, const GridRegion& b, const std::string& what, Checked* c,
               const std::vector<std::string>* counts = nullptr) {
  const CgalSet ca = cgalSet(a), cb = cgalSet(b);
  mpq_class got[4];
  for (int k = 0; k < 4; ++k) {
    const BooleanOp op = static_cast<BooleanOp>(k);
    const ExactRegion r = booleanOp(a, b, op);
    got[k] = exactAreaOf(r);
    const mpq_class want = cgalArea(cgalOp(ca, cb, op));
    c->operations++;
    if (got[k] != want) {
      if (c->mismatches++ < 5)
        ADD_FAILURE() << what << " " << booleanOpName(op) << ": area " << got[k] << ", CGAL " << want << "\nA:" << describe(a)
                      << "\nB:" << describe(b);
    }
    const std::string problem = ringProblems(r);
    EXPECT_EQ(problem, "") << what << " " << booleanOpName(op) << "\nA:" << describe(a) << "\nB:" << describe(b);
    if (counts != nullptr) {
      std::size_t holes = 0;
      for (const ExactPolygon& p : r) holes += p.holes.size();
      EXPECT_EQ(std::to_string(r.size()) + ":" + std::to_string(holes), (*counts)[k])
          << what << " " << booleanOpName(op) << ": polygons:holes";
    }
  }
  const mpq_class area_a = exactAreaOf(a), area_b = exactAreaOf(b);
  EXPECT_EQ(got[0] + got[2], area_a) << what << ": area(A∩B) + area(A−B) = area(A)";
  EXPECT_EQ(got[0] + got[3], area_b) << what << ": area(A∩B) + area(B−A) = area(B)";
  EXPECT_EQ(got[1], area_a + area_b - got[0]) << what << ": area(A∪B) = area(A) + area(B) − area(A∩B)";
}

TEST(WeilerAtherton, AgreesWithCgalExactlyOnRandomPairs) {
  struct Family {
    const char* name;
    int vertices, pairs;
    double scale;  // grid size: coordinates within about ±scale
  };
  const int k = testing::countScale();
  const Family families[] = {{"star", 4, 600 * k, 1000},   {"star", 16, 400 * k, 1000},
                             {"star", 64, 150 * k, 1000},  {"star", 256, 30 * k, 1000},
                             {"star near the coordinate limit", 16, 100 * k, 2.6e8},
                             {"star on a coarse grid", 16, 200 * k, 12},
                             {"comb", 10, 200 * k, 1000},  {"comb", 66, 60 * k, 1000},
                             {"comb on a coarse grid", 18, 150 * k, 40},
                             {"star with a hole", 16, 200 * k, 1000}, {"star with a hole", 64, 60 * k, 1000}};
  std::string figures = "row 12 weiler-atherton against CGAL (exact areas of A∩B, A∪B, A−B, B−A):";
  Checked total;
  testing::Rng rng(12);
  for (const Family& f : families) {
    Checked c;
    int refused = 0;
    for (int i = 0; i < f.pairs; ++i) {
      GridRegion a, b;
      const double s = f.scale;
      const std::string name(f.name);
      if (name.starts_with("star with a hole")) {
        GridRing hole = testing::starRing(rng, f.vertices, 0, 0, 0.1 * s, 0.45 * s);
        a = {{testing::starRing(rng, f.vertices, 0, 0, 0.5 * s, 0.9 * s), {hole}}};
        b = {{testing::starRing(rng, f.vertices, 0.2 * s, -0.1 * s, 0.2 * s, 0.9 * s), {}}};
      } else if (name.starts_with("star")) {
        a = {{testing::starRing(rng, f.vertices, 0, 0, 0.1 * s, 0.9 * s), {}}};
        b = {{testing::starRing(rng, f.vertices, 0.1 * s, 0.05 * s, 0.1 * s, 0.9 * s), {}}};
      } else {
        const int teeth = (f.vertices - 2) / 4;
        const auto size = static_cast<std::int64_t>(s);
        a = {{testing::combRing(rng, teeth, 0, 0, size, size), {}}};
        GridRing other = testing::combRing(rng, teeth, size / 10, size / 8, size, size);
        for (GridPoint& p : other) std::swap(p.x, p.y);  // teeth sideways, across A's
        b = {{other, {}}};
      }
      if (!invalidRegionReason(a).empty() || !invalidRegionReason(b).empty()) {
        ++refused;  // two vertices rounded onto one grid point, or a hole meeting its ring
        continue;
      }
      checkPair(a, b, name + " " + std::to_string(f.vertices) + " pair " + std::to_string(i), &c);
    }
    EXPECT_LT(refused, f.pairs / 4) << f.name << ": too many invalid pairs to prove anything";
    figures += " " + std::string(f.name) + " " + std::to_string(f.vertices) + ": " + grouped(c.operations) + " ops, " +
               grouped(c.mismatches) + " differ;";
    total.operations += c.operations, total.mismatches += c.mismatches;
  }
  EXPECT_EQ(total.mismatches, 0u);
  EXPECT_GE(total.operations, 4 * 1500u);
  testing::printFigures(figures + " in all " + grouped(total.operations) + " operations, " + grouped(total.mismatches) +
                        " with an area different from CGAL's");
}

// The degenerate catalogue
struct Case {
  std::string name;
  GridRegion a, b;
  std::vector<std::string> counts;  // per operation, "polygons:holes"
};

GridRing parseRing(const std::string& text) {
  GridRing r;
  std::istringstream in(text);
  std::string point;
  while (std::getline(in, point, ',')) {
    std::istringstream p(point);
    GridPoint v;
    if (p >> v.x >> v.y) r.push_back(v);
  }
  return r;
}

std::vector<Case> readCases() {
  std::ifstream in(std::string(HSR_SOURCE_DIR) + "/tests/geometry/clip_cases.txt");
  std::vector<Case> cases;
  std::string line;
  while (std::getline(in, line)) {
    if (line.starts_with("case ")) {
      cases.push_back({line.substr(5), {}, {}, {}});
    } else if (line.starts_with("A ") || line.starts_with("B ")) {
      GridPolygon poly;
      std::istringstream rings(line.substr(2));
      std::string ring;
      bool first = true;
      while (std::getline(rings, ring, '/')) {
        if (first) poly.outer = parseRing(ring);
        else poly.holes.push_back(parseRing(ring));
        first = false;
      }
      (line[0] == 'A' ? cases.back().a : cases.back().b).push_back(poly);
    } else if (line.starts_with("expect ")) {
      std::istringstream e(line.substr(7));
      std::string c;
      while (e >> c) cases.back().counts.push_back(c);
    }
  }
  return cases;
}

GridRegion transformed(GridRegion r, int symmetry) {
  auto move = [&](GridRing& ring) {
    for (GridPoint& v : ring) {
      std::int64_t x = v.x, y = v.y;
      if (symmetry & 1) x = -x;
      if (symmetry & 2) y = -y;
      if (symmetry & 4) std::swap(x, y);
      v = {x + 1000, y - 3000};
    }
  };
  for (GridPolygon& p : r) {
    move(p.outer);
    for (GridRing& h : p.holes) move(h);
  }
  return r;
}

TEST(WeilerAtherton, DegenerateCatalogueMatchesCgalAndTheFile) {
  const std::vector<Case> cases = readCases();
  ASSERT_GE(cases.size(), 30u);
  Checked c;
  for (const Case& k : cases) {
    ASSERT_EQ(k.counts.size(), 4u) << k.name;
    ASSERT_EQ(invalidRegionReason(k.a), "") << k.name;
    ASSERT_EQ(invalidRegionReason(k.b), "") << k.name;
    for (int symmetry = 0; symmetry < 8; ++symmetry) {
      const GridRegion a = transformed(k.a, symmetry), b = transformed(k.b, symmetry);
      const std::string where = k.name + " (symmetry " + std::to_string(symmetry);
      checkPair(a, b, where + ")", &c, &k.counts);
      const std::vector<std::string> swapped{k.counts[0], k.counts[1], k.counts[3], k.counts[2]};
      checkPair(b, a, where + ", A and B swapped)", &c, &swapped);
    }
  }
  EXPECT_EQ(c.mismatches, 0u);
  testing::printFigures("row 12 weiler-atherton degenerate catalogue: " + grouped(cases.size()) + " cases x 16 placements, " +
                        grouped(c.operations) + " operations, " + grouped(c.mismatches) + " with an area different from CGAL's");
}

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
      {{{{{0, 0}, {4, 4}, {4, 0}, {0, 3}}, {}}}, "cross"},                            // a bow tie
      {{{{{0, 0}, {6, 0}, {3, 0}, {3, 3}}, {}}}, "run along"},                        // a spike
      {{{{{0, 0}, {kClipCoordinateLimit + 1, 0}, {0, 5}}, {}}}, "beyond"},
      {{{square, {{{5, 5}, {6, 5}, {6, 6}}}}}, "not inside its outer ring"},
      {{{{{0, 0}, {8, 0}, {8, 8}, {0, 8}}, {{{1, 1}, {1, 7}, {7, 7}, {7, 1}}, {{2, 2}, {2, 3}, {3, 3}}}}}, "overlaps"},  // nested holes
      {{{square, {}}, {{{1, 1}, {3, 1}, {3, 3}}, {}}}, "overlaps"},                   // polygon in polygon
      {{{square, {}}, {{{2, 2}, {6, 2}, {6, 6}}, {}}}, "cross"},
      {{{square, {}}, {{{0, 0}, {4, 0}, {2, -3}}, {}}}, "run along"},                 // a shared edge
      {{{{{0, 0}, {4, 0}, {2, 2}, {4, 4}, {0, 4}, {2, 2}}, {}}}, "touch"},            // a ring through one point twice
  };
  for (const Bad& b : bad) {
    const std::string reason = invalidRegionReason(b.region);
    EXPECT_NE(reason.find(b.says), std::string::npos) << "expected \"" << b.says << "\", got \"" << reason << "\"";
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

}  // namespace
}  // namespace hsr
