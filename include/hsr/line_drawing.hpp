#pragma once
// Hidden-line drawings: the visible parts of a scene's outlines (silhouettes and open borders),
// creases and intersection lines, as pen strokes, and an SVG of them for plotters, laser
// cutters and technical illustration (`hsr svg`).
//
// Exact, not sampled: the visible parts of the edges are computed in object space on the
// pipeline's polygons (LineEngine below), with the hidden parts of the same edges on request.
// An edge is drawn when it is
//   - an outline: its two polygons fold over each other in the picture (one faces the eye,
//     the other away: a silhouette), or it has one polygon (an open border), or its other
//     polygon is culled or clipped away;
//   - a crease: its two polygons meet at an angle above `crease_angle_deg` (so a smooth
//     mesh does not show every triangle);
//   - an intersection line: where a polygon passes through another (Roberts' junction lines).
// Where the pieces of a non-planar polygon meet is no edge of the model and is not drawn.
// Coordinates are window pixels (y down, pixel centres at integers), as the pictures'.
//
// Strokes: segments merged into the longest polylines (no duplicates, no zero-length pieces,
// collinear runs joined; a line both visible and hidden is drawn visible only) and ordered so
// the pen travels little between them; the stats compare that travel with the unordered one.
// Cost: see LineEngine; then O(n log n) for n segments.
// Tests: tests/lines/line_drawing_test.cpp.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>

#include "hsr/camera.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace hsr {

struct VisibleSet;

enum class LineKind : std::uint8_t { kOutline = 0, kCrease = 1, kIntersection = 2 };
const char* lineKindName(LineKind kind);  // "outline", "crease", "intersection"

struct LineStroke {
  std::vector<glm::dvec2> points;  // a polyline in window pixels, at least two points
  LineKind kind = LineKind::kOutline;
};

struct LineLayerStats {
  std::uint64_t segments = 0;   // pieces of lines drawn in the layer
  std::uint64_t strokes = 0;    // polylines they became
  double length = 0;            // pixels
  double pen_up = 0;            // pen-up travel between strokes, in the order drawn (pixels)
  double pen_up_unordered = 0;  // the same, in the order the strokes were first chained
};

// How the visible parts are found. Both are exact (object space, in floating point) and draw
// the same lines; tests hold them to each other.
//   kEdges: classify the edges first, then test only the lines against the triangles in front
//     of them, found through a grid of screen cells (lines/line_visibility.cpp): near
//     linear in the scene, the default.
//   kRoberts: Roberts' visible segments of every edge (hsr/roberts.hpp), then classified: the
//     notes' algorithm, as a reference; its cost grows with the faces' sections.
enum class LineEngine : std::uint8_t { kEdges, kRoberts };

struct LineDrawingOptions {
  double crease_angle_deg = 30;  // polygons meeting at more than this show their edge
  bool hidden = false;           // also the hidden parts of the same lines (LineDrawing::hidden)
  // A time limit for the exact computation in seconds (0: none). When it would run longer, it
  // stops: hsr::Error says so, or with `raster_fallback` the drawing is made instead from the
  // z-buffer's ids (LineDrawing::exact false): the boundaries between pixels of different
  // polygons where a line belongs, by the same rules, as staircase strokes along pixel edges,
  // and no hidden layer (a picture keeps nothing of what it hides).
  double time_limit_s = 0;
  bool raster_fallback = false;
  // Which lines to draw (all three by default; outlines alone: a silhouette drawing)
  bool outlines = true, creases = true, intersections = true;
  LineEngine engine = LineEngine::kEdges;
};

struct LineDrawing {
  int width = 0, height = 0;
  std::vector<LineStroke> visible, hidden;
  LineLayerStats visible_stats, hidden_stats;
  std::uint64_t outline_segments = 0, crease_segments = 0, intersection_segments = 0;
  std::uint64_t smooth_segments = 0;  // left out: polygons meeting within the crease angle
                                      // (kEdges: edges; kRoberts: Roberts' segments)
  double visibility_ms = 0, strokes_ms = 0;
  // visibility_ms by step: the pipeline, then (LineEngine::kEdges) edges, classify, occluders,
  // intersections, hide; or (kRoberts) roberts
  std::vector<std::pair<std::string, double>> stage_ms;
  bool exact = true;  // false: drawn from the z-buffer's ids after the time limit (see above)
  LineEngine engine = LineEngine::kEdges;  // which engine found the lines (when exact)
};

// The drawing of `scene` seen by `camera`, with the pipeline's culling and clipping as
// `options` says (polygon mode fill; options.algorithm is ignored). Throws hsr::Error on a
// crease angle outside [0, 180], a negative time limit, or a time limit reached without the
// raster fallback.
LineDrawing lineDrawing(const Scene& scene, const Camera& camera, const RenderOptions& options = {},
                        const LineDrawingOptions& lines = {});

// How the SVG is laid out. With a page, the drawing (its lines' bounds) is scaled to fill the
// page inside its margins, centred, and sizes are in millimetres; without, one unit is one
// pixel of the view and the document is the view (rendered at its size, pixels match the
// pictures').
struct SvgPage {
  double width_mm = 0, height_mm = 0;  // 0: no page, the view's size in pixels
  double margin_mm = 10;
  double stroke_mm = 0.35;   // a common plotter pen (with a page)
  std::string dash = "2,1";  // the hidden layer's dash pattern, in stroke units: mm on
                             // a page, pixels without
};

// A page by name: "A4", "A3", "letter" (portrait); with "-landscape" appended, turned.
// Throws hsr::Error on an unknown name.
SvgPage svgPageNamed(const std::string& name);

// The drawing as an SVG document: a group per layer (id "visible", and "hidden" with
// class="hidden" and the dash pattern when it has strokes), each stroke one <path>.
std::string lineDrawingSvg(const LineDrawing& drawing, const SvgPage& page = {});

// The visible set (hsr/visible_set.hpp) as an SVG of filled regions, flat-shaded in the
// pictures' colours, holes kept (even-odd rule), nothing hidden in the file: a path per visible
// polygon (id "p" and the polygon's id) in one group (id "visible-set"). See-through polygons,
// which are not in the set, are not drawn.
std::string visibleSetSvg(const VisibleSet& set, const SvgPage& page = {});

// The same two as PDF documents of one page, through cairo: the strokes (the hidden layer
// dashed), or the filled regions. Units: millimetres on a page, else a view pixel as a CSS
// pixel (0.75 point). Throws hsr::Error when cairo fails.
std::string lineDrawingPdf(const LineDrawing& drawing, const SvgPage& page = {});
std::string visibleSetPdf(const VisibleSet& set, const SvgPage& page = {});

}  // namespace hsr
