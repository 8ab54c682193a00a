// Screen triangles from snapped vertices.

#include "raster/primitives.hpp"

#include <algorithm>
#include <bit>
#include <utility>

#include "core/check.hpp"

namespace hsr::detail {

bool samePolygon(const ScreenTriangle& a, const ScreenTriangle& b) {
  return a.id == b.id && a.rgba == b.rgba && a.depth.dzdx == b.depth.dzdx &&
         a.depth.dzdy == b.depth.dzdy && a.depth.z0 == b.depth.z0;
}

std::uint64_t numberPolygons(const ScreenTriangles& tris, std::vector<std::uint32_t>& polygon_of) {
  polygon_of.resize(tris.size());
  std::uint64_t polygons = 0;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const bool continues = i > 0 && samePolygon(tris[i - 1], tris[i]);
    polygon_of[i] = continues ? polygon_of[i - 1] : static_cast<std::uint32_t>(i);
    polygons += !continues;
  }
  return polygons;
}

std::uint64_t PolygonStarts::build(const ScreenTriangles& tris) {
  bits_.assign((tris.size() + 63) / 64, 0);
  summary_.assign((bits_.size() + 63) / 64, 0);
  std::uint64_t polygons = 0;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    if (i > 0 && samePolygon(tris[i - 1], tris[i])) continue;
    bits_[i / 64] |= std::uint64_t{1} << (i % 64);
    summary_[i / 4096] |= std::uint64_t{1} << (i / 64 % 64);
    polygons++;
  }
  return polygons;
}

std::uint32_t PolygonStarts::polygonOf(std::uint32_t triangle) const {
  auto upTo = [](std::uint64_t word, std::size_t bit) {
    return word & (~std::uint64_t{0} >> (63 - bit));
  };
  std::size_t w = triangle / 64;
  std::uint64_t word = upTo(bits_[w], triangle % 64);
  if (word == 0) {  // the polygon began in an earlier word (triangle 0 starts one: w > 0)
    std::size_t s = (w - 1) / 64;
    std::uint64_t sw = upTo(summary_[s], (w - 1) % 64);
    while (sw == 0) sw = summary_[--s];
    w = s * 64 + 63 - static_cast<std::size_t>(std::countl_zero(sw));
    word = bits_[w];
  }
  return static_cast<std::uint32_t>(w * 64 + 63 - static_cast<std::size_t>(std::countl_zero(word)));
}

}  // namespace hsr::detail
