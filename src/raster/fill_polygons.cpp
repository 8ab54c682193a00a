// Snap, triangulate on the grid, fill.

#include "raster/fill_polygons.hpp"

#include <array>
#include <cmath>
#include <vector>

#include "geometry/triangulate.hpp"
#include "raster/edge.hpp"
#include "raster/triangle.hpp"

namespace hsr::detail {

namespace {

constexpr double kLimit = 4194304.0;  // 2^22 pixels

// Snap as the pipeline does: 8 sub-pixel bits, round to nearest (for a coordinate that is a
// float, as the pipeline's are, this is exactly its lrint(x * 256.0f)); triangulate on the
// grid; call fn(screen triangle) for each triangle that covers pixel centres of the viewport.
template <class Fn>
std::size_t forEachSnappedTriangle(std::span<const glm::dvec2> vertices, const DepthPlane& depth,
                                   PolygonId id, std::uint32_t rgba, const FrameView& fb, Fn&& fn) {
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
    fn(st);
    ++filled;
  }
  return filled;
}

}  // namespace

std::size_t fillPolygon(std::span<const glm::dvec2> vertices, const DepthPlane& depth, PolygonId id,
                        std::uint32_t rgba, const FrameView& fb, DepthFunc func, bool depth_mask,
                        FragmentCounts& counts) {
  const PixelBox viewport{0, 0, fb.width - 1, fb.height - 1};
  return forEachSnappedTriangle(vertices, depth, id, rgba, fb, [&](const ScreenTriangle& st) {
    rasterTriangle(st, viewport, fb, func, depth_mask, counts);
  });
}

std::size_t paintPolygonPart(std::span<const glm::dvec2> vertices, std::span<const PixelHalfPlane> cuts,
                             const DepthPlane& depth, PolygonId id, std::uint32_t rgba,
                             const FrameView& fb, FragmentCounts& counts) {
  if (cuts.empty())
    return fillPolygon(vertices, depth, id, rgba, fb, DepthFunc::Always, true, counts);
  return forEachSnappedTriangle(vertices, depth, id, rgba, fb, [&](const ScreenTriangle& st) {
    // The triangle's pixels as the shared setup gives them (raster/edge.hpp), those outside a
    // cut left to the other piece.
    TriangleSetup edges = setupTriangle(st, st.y0);
    for (int y = st.y0; y <= st.y1; ++y, nextRow(edges)) {
      int lo = st.x0, hi = st.x1;
      if (!spanOfRow(edges, &lo, &hi)) continue;
      const double row = depthRowStart(depth, y);
      for (int x = lo; x <= hi; ++x) {
        bool inside = true;
        for (const PixelHalfPlane& h : cuts) inside = inside && h.contains(x, y);
        if (!inside) continue;
        writeFragment<DepthFunc::Always>(st, fb, fb.index(x, y), depthInRow(row, depth, x),
                                         /*depth_mask=*/true, counts);
      }
    }
  });
}

}  // namespace hsr::detail
