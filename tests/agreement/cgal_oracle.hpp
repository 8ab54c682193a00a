#pragma once
// CGAL's exact Boolean operations (Debian's libcgal-dev: Polygon_set_2 on the exact-constructions
// kernel) as the oracle of hsr's Weiler-Atherton clipping. Its own library, so that CGAL's
// templates are compiled once and, in the sanitizer build, without instrumentation: the oracle
// is CGAL's code, not ours (hsr's clipper, in libhsr, is instrumented). Used by
// tests/geometry/weiler_atherton_test.cpp.

#include <string>
#include <vector>

#include "hsr/clipping.hpp"

namespace hsr::testing {

// The exact area of A op B by CGAL, as a reduced fraction "p/q" (or "p"), as hsr::exactArea
// writes it.
std::string cgalArea(const GridRegion& a, const GridRegion& b, BooleanOp op);

// The exact area of ((R0 op0 R1) op1 R2) ... by CGAL: a chain of operations, each result the
// next one's A (ops.size() == regions.size() - 1).
std::string cgalChainArea(const std::vector<GridRegion>& regions,
                          const std::vector<BooleanOp>& ops);

// "" when every ring of `region` is simple (CGAL's is_simple on the exact vertices), outer
// rings counter-clockwise and holes clockwise; otherwise what is wrong.
std::string cgalRingProblems(const ExactRegion& region);

}  // namespace hsr::testing
