#pragma once
// Roberts' algorithm (Roberts 1963; the notes' "Roberts Algorithm"): the visible edges of a
// scene of convex polyhedra, as line segments. Computed on the pipeline's polygons by
// src/visibility/roberts.cpp, which also fills the visible faces for `--algorithm roberts`.
//
// Solids. An object of the scene is a convex polyhedron when its polygons close up (every edge
// shared by two of them, in opposite directions), are flat and convex, and have every vertex
// of the object on the inner side of each one's plane (within 1e-6 of the object's size).
// Such a solid is used whole when the view volume does not cut it (its front faces are all in
// the view, none touched by the clipper). Every other object, and a solid the view cuts, is
// decomposed: each of its polygons, as the pipeline clips it (a concave one as its
// triangles), is taken as a flat solid of its own; the result says which and why. Back faces
// are removed from the solids, and from every closed object the view does not cut. See-through
// polygons hide nothing and are not drawn here (the picture blends them afterwards).
//
// Coordinates: window pixels as the pipeline gives them (y down, pixel centres at integers),
// with every vertex snapped to the sub-pixel grid (1/256 pixel) as the screen triangles' are,
// so the segments lie on the Weiler-Atherton visible set's edges (hsr/visible_set.hpp).
// Segments along the picture's border (the view volume's cut) are not edges of the model and
// are left out.

#include <cstdint>
#include <string>
#include <vector>

#include "hsr/camera.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace hsr {

struct RobertsSegment {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // window pixels, y down
  PolygonId face = kNoPolygon;            // the visible face it bounds
  PolygonId other = kNoPolygon;           // the face on its other side when that one is visible too
                                          // (kNoPolygon on a silhouette or an open border); for a
                                          // junction, the face of the other object
  bool junction = false;                  // where two objects penetrate: the line the faces meet on
  PolygonId neighbour = kNoPolygon;       // across an edge: the polygon of the same object that
                                          // shares it, visible or not (a back face removed, or
                                          // `face` itself where a non-planar polygon's pieces
                                          // meet); kNoPolygon on an open border and a junction
};

struct RobertsObject {
  std::uint32_t object = 0;  // index into Scene::objects
  bool solid = false;        // used whole as a convex solid
  std::string reason;        // when decomposed: why ("not convex: ...", "cut by the view volume")
};

struct RobertsDrawing {
  int width = 0, height = 0;
  std::vector<RobertsSegment> segments;
  std::vector<RobertsSegment> hidden;  // on request: the parts of the same edges that are hidden,
                                       // the back faces' edges included (whole)
  std::vector<RobertsObject> objects;  // every object with an opaque polygon in the view
  std::uint64_t solids = 0;            // objects used whole
  std::uint64_t back_faces = 0;        // faces the back-face test removed (solids, and closed
                                       // objects the view does not cut)
  std::uint64_t faces = 0;             // faces left: the solids' front faces and every face
                                       // of the decomposed objects
  std::uint64_t volumes = 0;           // volumes edges are tested against (solids and flat faces)
  std::uint64_t edges = 0;             // edges tested (shared edges once)
  std::uint64_t junctions = 0;         // junction lines found
  std::uint64_t tests = 0;             // face against volume tests (each face's edges share one)
};

// Roberts' visible edges of `scene` seen by `camera`, with the pipeline's culling and clipping
// as `options` says (options.algorithm is ignored; polygon mode must be fill: hsr::Error
// otherwise). Cost: for each face, one test per volume whose screen box overlaps it and that
// comes nearer than it, found through a grid of screen cells; each test O(v) for a volume of
// v vertices and edges.
// With `hidden_parts`, RobertsDrawing::hidden is filled too.
RobertsDrawing robertsDrawing(const Scene& scene, const Camera& camera,
                              const RenderOptions& options = {}, bool hidden_parts = false);

}  // namespace hsr
