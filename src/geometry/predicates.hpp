#pragma once
// Exact orientation predicates: the sign of a determinant, decided exactly, so that
// collinear and nearly collinear inputs get the true answer, not a rounding accident.
//   - on snapped fixed-point coordinates (int64): exact in __int128;
//   - on doubles: Shewchuk's method (1997), a floating-point filter with a proven error bound
//     and, when the filter cannot decide, exact expansion arithmetic. Exact whenever no
//     intermediate product overflows or underflows (|coordinates| between about 1e-140 and
//     1e140, or 0).

#include <cstdint>

#include <glm/vec2.hpp>

namespace hsr::detail {

// +1 when a, b, c turn counter-clockwise (c left of a->b, y up), -1 clockwise, 0 collinear.
int orient2d(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by, std::int64_t cx,
             std::int64_t cy);
int orient2d(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c);

// The filter alone, for tests: the determinant in double and whether its sign is certain.
struct Orient2dEstimate {
  double det;
  bool certain;
};
Orient2dEstimate orient2dFilter(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c);

}  // namespace hsr::detail
