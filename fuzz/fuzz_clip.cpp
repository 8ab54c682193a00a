// libFuzzer target: bytes -> two regions -> Weiler-Atherton clipping (hsr/clipping.hpp).
// Byte 0 picks the grid: coordinates of one byte each (-128..127) times 1, 1,000 or 2^20 (so
// both dense degenerate cases and coordinates near the limit are reached). Then rings, each a
// header byte (bits 0-1: A's outer ring, A's hole, B's outer ring, B's hole; bits 2-7: 3 to 66
// vertices) and its points; a hole goes under its region's last outer ring. At most 512
// vertices in all. A region invalidRegionReason() refuses must come with a reason; for valid
// ones all four operations run and the area identities must hold exactly:
// area(A∩B) + area(A−B) = area(A), area(A∩B) + area(B−A) = area(B),
// area(A∪B) = area(A) + area(B) − area(A∩B); and A∪B, clipped again, gives (A∪B)∩A = A and
// (A∪B)−A = B−A. Anything else (a crash, a sanitizer report, a
// hang, an identity broken) is a finding.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include <gmpxx.h>

#include "hsr/clipping.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::int64_t scales[4] = {1, 1000, std::int64_t{1} << 20, 7};
  const std::int64_t scale = scales[data[0] & 3];
  hsr::GridRegion region[2];
  std::size_t at = 1, vertices = 0;
  while (at < size && vertices < 512) {
    const int header = data[at++], role = header & 3, count = 3 + (header >> 2);
    hsr::GridRing ring;
    for (int i = 0; i < count && at + 1 < size; ++i, at += 2)
      ring.push_back({static_cast<std::int8_t>(data[at]) * scale,
                      static_cast<std::int8_t>(data[at + 1]) * scale});
    vertices += ring.size();
    hsr::GridRegion& r = region[role >> 1];
    if ((role & 1) && !r.empty())
      r.back().holes.push_back(ring);
    else
      r.push_back({ring, {}});
  }
  for (const hsr::GridRegion& r : region) {
    const std::string why = hsr::invalidRegionReason(r);
    if (!why.empty()) return 0;  // refused, with its reason
  }
  mpq_class area[4];
  for (int op = 0; op < 4; ++op)
    area[op] = mpq_class(
        hsr::exactArea(hsr::booleanOp(region[0], region[1], static_cast<hsr::BooleanOp>(op))));
  const mpq_class a(hsr::exactArea(region[0])), b(hsr::exactArea(region[1]));
  if (area[0] + area[2] != a || area[0] + area[3] != b || area[1] != a + b - area[0]) std::abort();
  // A result clipped again (its vertices now crossings): (A∪B)∩A is A, and (A∪B)−A is B−A
  const hsr::ExactRegion both = hsr::booleanOp(region[0], region[1], hsr::BooleanOp::Union);
  if (!hsr::invalidRegionReason(both).empty()) std::abort();
  const hsr::ExactRegion exact_a = hsr::exactRegion(region[0]);
  if (mpq_class(hsr::exactArea(hsr::booleanOp(both, exact_a, hsr::BooleanOp::Intersection))) != a ||
      mpq_class(hsr::exactArea(hsr::booleanOp(both, exact_a, hsr::BooleanOp::AMinusB))) != area[3])
    std::abort();
  return 0;
}
