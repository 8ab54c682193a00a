#pragma once
// The visible set: what of each polygon a camera sees, as exact 2D polygons rather than
// pixels. Computed by the Weiler-Atherton hidden-surface algorithm (algorithm
// "weiler-atherton", src/visibility/weiler_atherton.cpp) on the pipeline's polygons, clipped by
// the exact clipper (hsr/clipping.hpp).
//
// Coordinates: window space on the pipeline's sub-pixel grid, 256 units per pixel: a vertex
// (x, y, d) is at column x / (256 d), row y / (256 d) (y down, pixel centres at integers, as
// the pipeline snaps its vertices). Every input polygon is the pipeline's polygon with its
// vertices snapped to that grid, so the visible set covers exactly the pixel centres the
// z-buffer's triangles cover (the fill rule decides centres on edges), and what a polygon
// shows is its region there.
//
// Guarantees: the regions of different polygons never overlap (their pairwise intersections
// have area exactly 0) and together they make up the union of the polygons' snapped outlines;
// at every point each region's polygon is the nearest there, except within about one grid
// unit (1/256 pixel) of a line along which two polygons cross (the line is snapped to the
// grid: see the file above) and where two depths are within 1e-12 (the polygon found first,
// the nearer or, among equals, the lower id, keeps the point). See-through polygons hide
// nothing and are not in the set.

#include <cstdint>
#include <vector>

#include "hsr/camera.hpp"
#include "hsr/clipping.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace hsr {

inline constexpr int kVisibleSetGrid = 256;  // grid units per pixel

struct VisiblePolygon {
  PolygonId id = kNoPolygon;  // the scene polygon it is part of
  ExactRegion region;         // what of it is visible (see the top of this file)
  double dzdx = 0, dzdy = 0,
         z0 = 0;           // its depth plane: window depth z = z0 + dzdy y + dzdx x (pixels)
  double area = 0;         // visible area in square pixels
  std::uint32_t rgba = 0;  // its shaded colour, as the frame's pixels hold it
  bool resolved = true;    // false: what was left of it when the work limit was reached
                           // (see VisibleSet::unresolved); such regions may overlap and
                           // hide one another: draw them with a depth test
};

struct VisibleSet {
  int width = 0, height = 0;
  std::vector<VisiblePolygon> polygons;  // at most one per scene polygon, in the order decided
  std::uint64_t polygons_in = 0;         // opaque polygons that entered
  std::uint64_t see_through = 0;         // see-through polygons (pieces) in the view, left out
  std::uint64_t pairs = 0;               // clip polygon / other polygon pairs looked at
  std::uint64_t clips = 0;               // Boolean operations run
  std::uint64_t splits = 0;              // pieces split along where two polygons cross
  std::uint64_t work = 0;                // edges handed to the clipper (both operands, summed)
  // Polygons left unresolved: the work limit (1,024 clipped edges per polygon, plus 2^18) was
  // reached, as on a soup of large triangles all overlapping in a small picture. Meshes stay
  // far below it. 0 means the set is exact.
  std::uint64_t unresolved = 0;
};

// The visible set of `scene` seen by `camera`, with the pipeline's culling, clipping and facing
// as `options` says (options.algorithm is ignored; polygon mode must be fill: hsr::Error
// otherwise). Cost: about (pairs of polygons whose boxes overlap) Boolean operations, found
// through a grid of screen cells; memory linear in the polygons and their pieces.
VisibleSet visibleSet(const Scene& scene, const Camera& camera, const RenderOptions& options = {});

}  // namespace hsr
