// Snap, triangulate on the grid, fill.

#include "raster/fill_polygons.hpp"

#include <array>
#include <cmath>
#include <vector>

#include "geometry/triangulate.hpp"
#include "raster/triangle.hpp"

namespace hsr::detail {

std::size_t fillPolygon(std::span<const glm::dvec2> vertices, const DepthPlane& depth, PolygonId id,
                        std::uint32_t rgba, const FrameView& fb, DepthFunc func, bool depth_mask,
                        FragmentCounts& counts) {
  // Snap as the pipeline does: 8 sub-pixel bits, round to nearest (for a coordinate that is a
  // float, as the pipeline's are, this is exactly its lrint(x * 256.0f)).
  constexpr double kLimit = 4194304.0;  // 2^22 pixels
  std::vector<std::int64_t> fx, fy;
  std::vector<glm::dvec2> grid;
  for (const glm::dvec2& v : vertices) {
    if (!(std::abs(v.x) < kLimit && std::abs(v.y) < kLimit)) return 0;
    fx.push_back(std::llrint(v.x * kSubpixelOne));
    fy.push_back(std::llrint(v.y * kSubpixelOne));
    grid.emplace_back(static_cast<double>(fx.back()), static_cast<double>(fy.back()));
  }
  std::vector<std::array<std::uint32_t, 3>> tris;
  triangulate2d(grid, tris);
  const PixelBox viewport{0, 0, fb.width - 1, fb.height - 1};
  std::size_t filled = 0;
  for (const auto& t : tris) {
    const std::int64_t tx[3] = {fx[t[0]], fx[t[1]], fx[t[2]]};
    const std::int64_t ty[3] = {fy[t[0]], fy[t[1]], fy[t[2]]};
    ScreenTriangle st;
    if (makeScreenTriangle(tx, ty, windowOrientation(tx, ty), fb.width, fb.height, depth, &st) !=
        TriangleFate::kMade)
      continue;
    st.id = id;
    st.rgba = rgba;
    rasterTriangle(st, viewport, fb, func, depth_mask, counts);
    ++filled;
  }
  return filled;
}

}  // namespace hsr::detail
