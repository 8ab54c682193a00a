#include "agreement/cgal_oracle.hpp"

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_set_2.h>

#include <sstream>
#include <vector>

#include <gmpxx.h>

namespace hsr::testing {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using CgalPolygon = CGAL::Polygon_2<K>;
using CgalPolygonWithHoles = CGAL::Polygon_with_holes_2<K>;
using CgalSet = CGAL::Polygon_set_2<K>;

CgalPolygon cgalRing(const GridRing& r, CGAL::Orientation want) {
  CgalPolygon p;
  for (const GridPoint& v : r)
    p.push_back(K::Point_2(static_cast<double>(v.x), static_cast<double>(v.y)));
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

K::FT exactCoordinate(__int128 v, std::int64_t d) {
  const bool negative = v < 0;
  const unsigned __int128 m =
      negative ? -static_cast<unsigned __int128>(v) : static_cast<unsigned __int128>(v);
  mpz_class z(static_cast<unsigned long>(static_cast<std::uint64_t>(m >> 64)));
  z <<= 64;
  z += mpz_class(static_cast<unsigned long>(static_cast<std::uint64_t>(m)));
  mpq_class q(negative ? mpz_class(-z) : z, mpz_class(static_cast<long>(d)));
  q.canonicalize();
  return K::FT(K::FT::ET(q.get_mpq_t()));
}

void apply(CgalSet& a, const CgalSet& b, BooleanOp op) {
  switch (op) {
    case BooleanOp::Intersection:
      a.intersection(b);
      break;
    case BooleanOp::Union:
      a.join(b);
      break;
    case BooleanOp::AMinusB:
      a.difference(b);
      break;
    case BooleanOp::BMinusA: {
      CgalSet r = b;
      r.difference(a);
      a = r;
      break;
    }
  }
}

std::string areaOf(const CgalSet& set) {
  std::vector<CgalPolygonWithHoles> polys;
  set.polygons_with_holes(std::back_inserter(polys));
  K::FT area = 0;
  for (const CgalPolygonWithHoles& ph : polys) {
    area += ph.outer_boundary().area();
    for (auto h = ph.holes_begin(); h != ph.holes_end(); ++h) area += h->area();  // negative
  }
  std::ostringstream s;
  s << CGAL::exact(area);
  mpq_class q(s.str());
  q.canonicalize();
  return q.get_str();
}

}  // namespace

std::string cgalArea(const GridRegion& a, const GridRegion& b, BooleanOp op) {
  CgalSet out = cgalSet(a);
  apply(out, cgalSet(b), op);
  return areaOf(out);
}

std::string cgalChainArea(const std::vector<GridRegion>& regions,
                          const std::vector<BooleanOp>& ops) {
  CgalSet out = cgalSet(regions.at(0));
  for (std::size_t i = 0; i < ops.size(); ++i) apply(out, cgalSet(regions.at(i + 1)), ops[i]);
  return areaOf(out);
}

std::string cgalRingProblems(const ExactRegion& region) {
  auto check = [](const ExactRing& ring, CGAL::Orientation want) -> std::string {
    CgalPolygon p;
    for (const ExactPoint& v : ring)
      p.push_back(K::Point_2(exactCoordinate(v.x, v.d), exactCoordinate(v.y, v.d)));
    if (p.size() < 3) return "a ring of fewer than 3 vertices";
    if (!p.is_simple()) return "a ring that is not simple";
    if (p.orientation() != want)
      return want == CGAL::COUNTERCLOCKWISE ? "an outer ring clockwise"
                                            : "a hole counter-clockwise";
    return "";
  };
  for (const ExactPolygon& poly : region) {
    if (std::string s = check(poly.outer, CGAL::COUNTERCLOCKWISE); !s.empty()) return s;
    for (const ExactRing& h : poly.holes)
      if (std::string s = check(h, CGAL::CLOCKWISE); !s.empty()) return s;
  }
  return "";
}

}  // namespace hsr::testing
