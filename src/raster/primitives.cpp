// Screen triangles from snapped vertices.

#include "raster/primitives.hpp"

#include <algorithm>
#include <bit>
#include <utility>

#include "core/check.hpp"

namespace hsr::detail {

int windowOrientation(const std::int64_t x[3], const std::int64_t y_down[3]) {
  const std::int64_t area =
      (x[1] - x[0]) * (y_down[2] - y_down[0]) - (y_down[1] - y_down[0]) * (x[2] - x[0]);
  // y-down flips the sign: negative y-down area is counter-clockwise in GL's y-up window.
  return area < 0 ? 1 : (area > 0 ? -1 : 0);
}

TriangleFate makeScreenTriangle(const std::int64_t fx[3], const std::int64_t fy[3], int orientation,
                                int width, int height, const DepthPlane& depth,
                                ScreenTriangle* out, int margin) {
  if (orientation == 0) return TriangleFate::kZeroArea;
  // Order the vertices so the y-down area is positive (every edge function > 0 inside):
  // counter-clockwise in y-up is negative area in y-down.
  int o[3] = {0, 1, 2};
  if (orientation > 0) std::swap(o[1], o[2]);
  // Pixel bounding box (pixel centres are at multiples of 256), clamped to the viewport.
  auto ceilPixel = [](std::int64_t a) { return -((-a) >> kSubpixelBits); };
  const std::int64_t bx0 = std::max<std::int64_t>(0, ceilPixel(std::min({fx[0], fx[1], fx[2]}) - margin));
  const std::int64_t by0 = std::max<std::int64_t>(0, ceilPixel(std::min({fy[0], fy[1], fy[2]}) - margin));
  const std::int64_t bx1 =
      std::min<std::int64_t>(width - 1, (std::max({fx[0], fx[1], fx[2]}) + margin) >> kSubpixelBits);
  const std::int64_t by1 =
      std::min<std::int64_t>(height - 1, (std::max({fy[0], fy[1], fy[2]}) + margin) >> kSubpixelBits);
  if (bx0 > bx1 || by0 > by1) return TriangleFate::kMissesPixelCentres;
  ScreenTriangle& t = *out;
  // The box lies in the viewport and the vertices within the 2^30 the int32 fields hold.
  HSR_CHECK(bx1 < 32768 && by1 < 32768);
  for (int k = 0; k < 3; ++k) {
    t.x[k] = static_cast<std::int32_t>(fx[o[k]]);
    t.y[k] = static_cast<std::int32_t>(fy[o[k]]);
  }
  t.x0 = static_cast<std::int16_t>(bx0);
  t.y0 = static_cast<std::int16_t>(by0);
  t.x1 = static_cast<std::int16_t>(bx1);
  t.y1 = static_cast<std::int16_t>(by1);
  t.depth = depth;
  return TriangleFate::kMade;
}

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
  auto upTo = [](std::uint64_t word, std::size_t bit) { return word & (~std::uint64_t{0} >> (63 - bit)); };
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
