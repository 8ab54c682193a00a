#pragma once
// The hidden-line computation behind `hsr svg` (line_drawing.cpp): which edges of the
// pipeline's polygons are lines of the drawing, and which parts of them are visible.
//
// It is Roberts' edge test (visibility/roberts.cpp, step 3) with every polygon a flat solid of
// its own, run only on the edges that are lines: classify the edges first (outlines, creases,
// intersection lines), then test each against the triangles whose screen boxes it crosses,
// found through a grid of screen cells. Each triangle in front hides one interval of the
// edge (both are straight in the window and depth is linear along both), and the edge is
// visible where no interval covers it. Same answers as the drawing on Roberts' segments
// (tests pin the two together), at a cost near linear in the scene: O(e k) for e line edges
// each crossing k triangles, against Roberts' sections of every face.
// Tests: tests/lines/line_drawing_test.cpp.

#include <cstdint>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "core/deadline.hpp"
#include "lines/strokes.hpp"
#include "hsr/scene.hpp"
#include "pipeline/pipeline.hpp"

namespace hsr::detail {

struct LineRequest {
  bool ortho = false;            // the camera's projection (which side the eye is on)
  double crease_angle_deg = 30;  // polygons meeting at more than this show their edge
  bool outlines = true, creases = true, intersections = true;  // which lines
  bool hidden = false;                                         // also the hidden parts
  bool keep_pieces = false;  // also LineVisibility's pieces in window space (for tests)
  const Deadline* deadline = nullptr;
};

// A piece of a line in window space (x, y pixels, z window depth) and the polygons it lies on
// (`other` kNoPolygon on an open border).
struct LinePiece {
  glm::dvec3 a{0.0}, b{0.0};
  PolygonId face = kNoPolygon, other = kNoPolygon;
  std::uint8_t kind = 0;
};

struct LineVisibility {
  // Pieces of lines in window pixels, kind = LineKind (0 outline, 1 crease, 2 intersection)
  std::vector<StrokeSegment> visible, hidden;
  std::uint64_t pieces[3] = {0, 0, 0};  // visible pieces by kind
  std::uint64_t smooth_edges = 0;       // edges between polygons within the crease angle
  std::uint64_t line_edges = 0;         // edges and intersection lines tested
  std::uint64_t occluder_tests = 0;     // edge against triangle tests made
  std::vector<LinePiece> visible_pieces, hidden_pieces;  // with LineRequest::keep_pieces
  // Milliseconds by step: edges (found), classify, occluders (triangles and grid),
  // intersections, hide
  std::vector<std::pair<const char*, double>> stages;
};

// The lines of `polygons` (the pipeline's window polygons of `scene`, id order) in a view of
// width x height pixels. Throws DeadlinePassed when the request's deadline passes.
LineVisibility lineVisibility(const Scene& scene, const std::vector<WindowPolygon>& polygons,
                              int width, int height, const LineRequest& request);

}  // namespace hsr::detail
