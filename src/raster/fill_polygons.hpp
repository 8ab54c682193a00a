#pragma once
// Filling a frame from exact visible polygons: what the object-precision algorithms
// (painter's, BSP, Weiler-Atherton, Roberts) draw their answer with, so that they are compared
// on ids with the image-precision ones through the same edge setup, fill rule and depth
// definition, with no second rasterizer.
//
// A polygon here is in window space (pixel-centre coordinates, y down) with the depth plane
// of the scene polygon it came from. Its vertices are snapped to the sub-pixel grid exactly as
// the pipeline snaps its own, it is triangulated on that grid, and its triangles are filled
// with rasterTriangle. Guarantee: a polygon the pipeline produced (WindowPolygon), filled
// whole, covers the pixels its screen triangles cover (any triangulation of the same snapped
// vertices covers the same pixel centres, by the fill rule) and writes the same depths; a
// piece of it writes, where it covers, what the whole would.

#include <cstdint>
#include <functional>
#include <span>

#include <glm/vec2.hpp>

#include "hsr/clipping.hpp"
#include "raster/fragment.hpp"
#include "raster/primitives.hpp"

namespace hsr::detail {

// Fills one polygon (either winding; an alpha below 1 in rgba blends) in the caller's order, with
// the depth test `func` and depth writes as `depth_mask` says. A polygon with a vertex beyond 2^22
// pixels, or of zero area on the grid, draws nothing. Returns the triangles filled.
std::size_t fillPolygon(std::span<const glm::dvec2> vertices, const DepthPlane& depth, PolygonId id,
                        std::uint32_t rgba, const FrameView& fb, DepthFunc func, bool depth_mask,
                        FragmentCounts& counts);

// The same for any polygon type with `vertices` (glm::dvec2 or dvec3, x and y used), `depth`,
// `id` and `rgba` members, e.g. the pipeline's WindowPolygon.
template <class P>
std::size_t fillPolygon(const P& p, const FrameView& fb, DepthFunc func, bool depth_mask,
                        FragmentCounts& counts) {
  std::vector<glm::dvec2> xy;
  xy.reserve(p.vertices.size());
  for (const auto& v : p.vertices) xy.emplace_back(v.x, v.y);
  return fillPolygon(xy, p.depth, p.id, p.rgba, fb, func, depth_mask, counts);
}

// A half-plane of the picture: the pixel centres (x, y) (column, row; pixel centres at
// integers, as depth planes) where value = (c + b y) + a x is >= 0, or < 0 when `negative`.
// Two pieces cut from one polygon by the same line take opposite sides of one PixelHalfPlane,
// so every pixel centre of the polygon goes to exactly one of them, on the line as well.
struct PixelHalfPlane {
  double a = 0, b = 0, c = 0;
  bool negative = false;
  bool contains(int x, int y) const {
    const double v = (c + b * static_cast<double>(y)) + a * static_cast<double>(x);
    return negative ? v < 0.0 : v >= 0.0;
  }
};

// Paints, with no depth test (depth written, an alpha below 1 blending), the pixels of polygon
// `vertices` (filled exactly as fillPolygon fills it) whose centres lie in every half-plane of
// `cuts`: a piece of a polygon split along lines, covering exactly its share of the whole
// polygon's pixels, within `box` (the piece's pixels all lie in it; it only saves work). For
// painting back to front. One exception, ties: where the pixel already holds exactly this
// depth (as a float) from a polygon of lower id, or a depth one float step (ulp) nearer, it is
// left as it is: the z-buffer's answer (GL_LESS keeps the first submitted, and the nearer
// float). A float depth buffer cannot order surfaces closer than a step (at the far end of a
// perspective view a step is 6e-8 of the range), so there the painter's exact order and the
// z-buffer's may differ; no depth further apart is looked at. Such a fragment counts as
// tested, not written.
// Returns the triangles filled.
//
// `group`, when given, makes a set of polygons painted one after another act as one: each
// pixel remembers (in group->stamps, a frame-sized buffer) the group that last painted it, and
// a pixel already painted by the same group (group->stamp) is painted again only where the
// depth test GL_LESS would pass (the BSP tree's coplanar polygons at one node: in exact
// arithmetic they are equally near, in floats the z-buffer decides pixel by pixel).
struct PaintGroup {
  std::span<std::uint32_t> stamps;
  std::uint32_t stamp = 0;
};
std::size_t paintPolygonPart(std::span<const glm::dvec2> vertices,
                             std::span<const PixelHalfPlane> cuts, const PixelBox& box,
                             const DepthPlane& depth, PolygonId id, std::uint32_t rgba,
                             const FrameView& fb, FragmentCounts& counts,
                             const PaintGroup* group = nullptr);

// Paints, with no depth test by default (depth written), the pixel centres inside an exact region
// (hsr/clipping.hpp) given on the sub-pixel grid (x / (d * 256) pixels, as the pipeline snaps):
// what the Weiler-Atherton algorithm's visible pieces are filled with. A centre on the
// region's boundary counts as inside exactly when the fill rule would give it to a triangle
// with that edge (raster/edge.hpp): the test is made at the centre moved right by an
// infinitesimal e and up by e² (no edge then passes through it). So pieces that tile a
// polygon share out its pixels exactly, and a region that is a whole snapped polygon covers
// the pixels fillPolygon covers. Each pixel's depth is the plane's (raster/depth.hpp), as every
// other algorithm writes it. Cost: per row of the region's box, its edges and a sort of their
// crossings. Returns the fragments written.
// With `func` Less, a fragment is written only where it is nearer than what the pixel holds.
std::size_t paintExactRegion(const ExactRegion& region, const DepthPlane& depth, PolygonId id,
                             std::uint32_t rgba, const FrameView& fb, FragmentCounts& counts,
                             DepthFunc func = DepthFunc::Always);

// The pixel centres paintExactRegion paints, within a width x height picture, as spans:
// span(y, x0, x1) for columns x0..x1 of row y.
void forEachCentreIn(const ExactRegion& region, int width, int height,
                     const std::function<void(int y, int x0, int x1)>& span);

}  // namespace hsr::detail
