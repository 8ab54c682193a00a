// orient2d, exactly. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust
// Geometric Predicates" (1997): the error bound of the filter and the error-free
// transformations (two-sum, two-product by Dekker's split) are his; no FMA is used, and the
// build never contracts a * b + c into one, so the transformations are exact as proven.

#include "geometry/predicates.hpp"

#include <cmath>
#include <vector>

namespace hsr::detail {
namespace {

constexpr double kEpsilon = 0x1p-53;                                  // half an ulp of 1
constexpr double kCcwErrBoundA = (3.0 + 16.0 * kEpsilon) * kEpsilon;  // Shewchuk's bound
constexpr double kSplitter = 134217729.0;                             // 2^27 + 1

// a + b = x + y exactly, |y| <= ulp(x) / 2.
inline void twoSum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a, av = x - bv;
  y = (a - av) + (b - bv);
}

inline void twoDiff(double a, double b, double& x, double& y) {
  x = a - b;
  const double bv = a - x, av = x + bv;
  y = (a - av) + (bv - b);
}

inline void split(double a, double& hi, double& lo) {
  const double c = kSplitter * a;
  const double big = c - a;
  hi = c - big;
  lo = a - hi;
}

// a * b = x + y exactly (Dekker).
inline void twoProduct(double a, double b, double& x, double& y) {
  x = a * b;
  double ahi, alo, bhi, blo;
  split(a, ahi, alo);
  split(b, bhi, blo);
  const double err1 = x - ahi * bhi;
  const double err2 = err1 - alo * bhi;
  const double err3 = err2 - ahi * blo;
  y = alo * blo - err3;
}

// Adds b to the nonoverlapping expansion e (increasing magnitude), keeping it nonoverlapping
// and dropping zeros (Shewchuk's Grow-Expansion with zero elimination).
void growExpansion(std::vector<double>& e, double b) {
  double q = b;
  std::size_t out = 0;
  for (std::size_t i = 0; i < e.size(); ++i) {
    double sum, err;
    twoSum(q, e[i], sum, err);
    q = sum;
    if (err != 0.0) e[out++] = err;
  }
  e.resize(out);
  if (q != 0.0) e.push_back(q);
}

int sign(double v) { return v > 0.0 ? 1 : (v < 0.0 ? -1 : 0); }

}  // namespace

int orient2d(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by, std::int64_t cx,
             std::int64_t cy) {
  const __int128 det =
      static_cast<__int128>(bx - ax) * (cy - ay) - static_cast<__int128>(by - ay) * (cx - ax);
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

Orient2dEstimate orient2dFilter(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  const double left = (a.x - c.x) * (b.y - c.y);
  const double right = (a.y - c.y) * (b.x - c.x);
  const double det = left - right;
  const double bound = kCcwErrBoundA * (std::abs(left) + std::abs(right));
  return {det, std::abs(det) > bound};
}

int orient2d(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  const Orient2dEstimate f = orient2dFilter(a, b, c);
  if (f.certain) return sign(f.det);
  // Exact: (ax - cx)(by - cy) - (ay - cy)(bx - cx) with each difference as a two-term
  // expansion and each of the 8 partial products as two terms, summed into one expansion.
  double acx[2], bcy[2], acy[2], bcx[2];
  twoDiff(a.x, c.x, acx[0], acx[1]);
  twoDiff(b.y, c.y, bcy[0], bcy[1]);
  twoDiff(a.y, c.y, acy[0], acy[1]);
  twoDiff(b.x, c.x, bcx[0], bcx[1]);
  std::vector<double> e;
  e.reserve(32);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      double x, y;
      twoProduct(acx[i], bcy[j], x, y);
      growExpansion(e, y);
      growExpansion(e, x);
      twoProduct(-acy[i], bcx[j], x, y);
      growExpansion(e, y);
      growExpansion(e, x);
    }
  // The largest component (the last) carries the sign of the exact sum.
  return e.empty() ? 0 : sign(e.back());
}

}  // namespace hsr::detail
