// Snap, triangulate on the grid, fill.

#include "raster/fill_polygons.hpp"

#include <algorithm>
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
  // Working memory kept per thread: object-order algorithms call this once per polygon piece,
  // hundreds of thousands of times a frame (fn never calls back in here).
  thread_local std::vector<std::int64_t> fx, fy;
  thread_local std::vector<glm::dvec2> grid;
  thread_local std::vector<std::array<std::uint32_t, 3>> tris;
  fx.clear(), fy.clear(), grid.clear(), tris.clear();
  for (const glm::dvec2& v : vertices) {
    if (!(std::abs(v.x) < kLimit && std::abs(v.y) < kLimit)) return 0;
    fx.push_back(std::llrint(v.x * kSubpixelOne));
    fy.push_back(std::llrint(v.y * kSubpixelOne));
    grid.emplace_back(static_cast<double>(fx.back()), static_cast<double>(fy.back()));
  }
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

std::size_t paintPolygonPart(std::span<const glm::dvec2> vertices,
                             std::span<const PixelHalfPlane> cuts, const PixelBox& box,
                             const DepthPlane& depth, PolygonId id, std::uint32_t rgba,
                             const FrameView& fb, FragmentCounts& counts, const PaintGroup* group) {
  return forEachSnappedTriangle(vertices, depth, id, rgba, fb, [&](const ScreenTriangle& st) {
    // The triangle's pixels as the shared setup gives them (raster/edge.hpp), within the box,
    // those outside a cut left to the other piece.
    const int y0 = std::max<int>(st.y0, box.y0), y1 = std::min<int>(st.y1, box.y1);
    if (y0 > y1) return;
    TriangleSetup edges = setupTriangle(st, y0);
    for (int y = y0; y <= y1; ++y, nextRow(edges)) {
      int lo = std::max<int>(st.x0, box.x0), hi = std::min<int>(st.x1, box.x1);
      if (lo > hi) break;
      if (!spanOfRow(edges, &lo, &hi)) continue;
      const double row = depthRowStart(depth, y);
      for (int x = lo; x <= hi; ++x) {
        bool inside = true;
        for (const PixelHalfPlane& h : cuts) inside = inside && h.contains(x, y);
        if (!inside) continue;
        const std::size_t idx = fb.index(x, y);
        const float z = depthInRow(row, depth, x);
        // A tie: the pixel holds this very depth from an earlier-submitted polygon, or a depth
        // one float step nearer. Painted back to front, the two are equally near here as far
        // as floats can tell; the z-buffer's GL_LESS keeps the first submitted (the nearer
        // float), and so does the painter (no other depth is looked at).
        const float held = fb.depth[idx];
        if ((held == z && fb.ids[idx] < id) || (z > held && z <= std::nextafter(held, 2.0f))) {
          counts.tested++;
          continue;
        }
        if (group) {
          if (group->stamps[idx] == group->stamp && !(z < fb.depth[idx])) {
            counts.tested++;
            continue;
          }
          group->stamps[idx] = group->stamp;
        }
        writeFragment<DepthFunc::Always>(st, fb, idx, z, /*depth_mask=*/true, counts);
      }
    }
  });
}

void forEachCentreIn(const ExactRegion& region, int width, int height,
                     const std::function<void(int y, int x0, int x1)>& span) {
  using i128 = __int128;
  struct RegionEdge {
    i128 y0, y1;  // ends' y as fractions of their d
    std::int64_t d0, d1;
    std::int64_t a, b, c;  // its line
  };
  thread_local std::vector<RegionEdge> edges;
  thread_local std::vector<std::int64_t> starts;
  edges.clear();
  // The rows the region's box spans (centres at y * 256 on the grid), with a row to spare
  double lo = 0, hi = 0;
  bool any = false;
  auto ring = [&](const ExactRing& r) {
    for (std::size_t i = 0, n = r.size(); i < n; ++i) {
      const ExactPoint &p = r[i], &q = r[(i + 1) % n];
      edges.push_back({p.y, q.y, p.d, q.d, p.a, p.b, p.c});
      lo = any ? std::min(lo, p.yd()) : p.yd();
      hi = any ? std::max(hi, p.yd()) : p.yd();
      any = true;
    }
  };
  for (const ExactPolygon& poly : region) {
    ring(poly.outer);
    for (const ExactRing& h : poly.holes) ring(h);
  }
  if (!any) return;
  auto floorDiv128 = [](i128 n, i128 d) {  // d > 0
    i128 q = n / d;
    if (q * d > n) --q;
    return q;
  };
  const int y0 = static_cast<int>(
      std::clamp(std::floor(lo / kSubpixelOne) - 1, 0.0, static_cast<double>(height)));
  const int y1 = static_cast<int>(
      std::clamp(std::ceil(hi / kSubpixelOne) + 1, -1.0, static_cast<double>(height - 1)));
  for (int y = y0; y <= y1; ++y) {
    const i128 Y = i128{y} * kSubpixelOne;
    // Each edge met by the row just above the centres (y - e²): one whose ends lie on either
    // side, an end on the row itself counting as below it. Where it meets the row, x = -(b Y +
    // c) / a; the centres from the first column at or right of x on are past it.
    starts.clear();
    for (const RegionEdge& e : edges) {
      const bool below0 = e.y0 >= Y * e.d0, below1 = e.y1 >= Y * e.d1;
      if (below0 == below1) continue;
      i128 num = -(i128{e.b} * Y + e.c), den = i128{e.a} * kSubpixelOne;
      if (den < 0) num = -num, den = -den;
      const i128 col = -floorDiv128(-num, den);
      starts.push_back(static_cast<std::int64_t>(std::clamp<i128>(col, -1, width)));
    }
    std::sort(starts.begin(), starts.end());
    for (std::size_t k = 0; k + 1 < starts.size(); k += 2) {
      const int x0 = static_cast<int>(std::max<std::int64_t>(starts[k], 0));
      const int x1 = static_cast<int>(std::min<std::int64_t>(starts[k + 1], width)) - 1;
      if (x0 <= x1) span(y, x0, x1);
    }
  }
}

std::size_t paintExactRegion(const ExactRegion& region, const DepthPlane& depth, PolygonId id,
                             std::uint32_t rgba, const FrameView& fb, FragmentCounts& counts,
                             DepthFunc func) {
  std::size_t written = 0;
  ScreenTriangle st{};
  st.id = id;
  st.rgba = rgba;
  forEachCentreIn(region, fb.width, fb.height, [&](int y, int x0, int x1) {
    const double row = depthRowStart(depth, y);
    for (int x = x0; x <= x1; ++x) {
      const std::size_t before = counts.written;
      if (func == DepthFunc::Less)
        writeFragment<DepthFunc::Less>(st, fb, fb.index(x, y), depthInRow(row, depth, x), true,
                                       counts);
      else
        writeFragment<DepthFunc::Always>(st, fb, fb.index(x, y), depthInRow(row, depth, x), true,
                                         counts);
      written += counts.written - before;
    }
  });
  return written;
}

}  // namespace hsr::detail
