// Exact areas of clipped regions (hsr/clipping.hpp's exactArea): each ring's shoelace sum in
// GMP's rationals, so an area is a reduced fraction with nothing rounded. Apart from the
// clipper (weiler_atherton.cpp) because it is what needs GMP: the tests and the CLI use it to
// check the clipper's identities exactly; the clipper itself never does.

#include <cstdint>
#include <string>

#include <gmpxx.h>

#include "hsr/clipping.hpp"

namespace hsr {
namespace {

using i128 = __int128;
using u128 = unsigned __int128;

mpz_class toMpz(i128 v) {
  const bool negative = v < 0;
  const u128 m = negative ? -static_cast<u128>(v) : static_cast<u128>(v);
  mpz_class r(static_cast<unsigned long>(static_cast<std::uint64_t>(m >> 64)));
  r <<= 64;
  r += mpz_class(static_cast<unsigned long>(static_cast<std::uint64_t>(m)));
  return negative ? mpz_class(-r) : r;
}

mpq_class exactTwiceSignedArea(const ExactRing& r) {
  mpq_class sum = 0;
  for (std::size_t i = 0, n = r.size(); i < n; ++i) {
    const ExactPoint &p = r[i], &q = r[(i + 1) % n];
    const mpz_class num = toMpz(p.x) * toMpz(q.y) - toMpz(q.x) * toMpz(p.y);
    const mpz_class den = mpz_class(static_cast<long>(p.d)) * mpz_class(static_cast<long>(q.d));
    mpq_class term(num, den);
    term.canonicalize();
    sum += term;
  }
  return sum;
}

}  // namespace

std::string exactArea(const ExactRegion& region) {
  mpq_class twice = 0;
  for (const ExactPolygon& p : region) {
    twice += abs(exactTwiceSignedArea(p.outer));
    for (const ExactRing& h : p.holes) twice -= abs(exactTwiceSignedArea(h));
  }
  mpq_class area = twice / 2;
  area.canonicalize();
  return area.get_str();
}

std::string exactArea(const GridRegion& region) { return exactArea(exactRegion(region)); }

}  // namespace hsr
