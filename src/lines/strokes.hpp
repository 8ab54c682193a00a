#pragma once
// Line segments made into pen strokes, for plotters and vector drawings: duplicates and
// overlaps merged, collinear pieces joined, segments chained into the longest polylines the
// drawing allows, and the polylines ordered so the pen travels little between them.
//
// Guarantees: the strokes cover exactly the union of the input segments of each layer (no
// length lost, none drawn twice: an overlap counts once); no stroke has a zero-length piece;
// every stroke is connected. A piece in both layers of mergeStrokes is kept in the first
// (the visible layer wins over the hidden one). Tolerances are in the input's units.
// Cost: O(n log n) for n segments. Tests: tests/lines/strokes_test.cpp.

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

namespace hsr::detail {

struct StrokeSegment {
  glm::dvec2 a{0.0}, b{0.0};
  std::uint8_t kind = 0;  // the caller's class; where pieces of several overlap, the lowest wins
};

struct Stroke {
  std::vector<glm::dvec2> points;  // at least two, consecutive ones apart
  std::uint8_t kind = 0;
};

struct StrokeStats {
  std::uint64_t segments = 0;  // given
  std::uint64_t strokes = 0;
  double length = 0;            // of the strokes (the union of the segments)
  double pen_up = 0;            // travel between consecutive strokes, in the order made
  double pen_up_unordered = 0;  // the same, before ordering (strokes as first chained)
};

// Two layers of segments (`first` wins where they overlap) into strokes: collinear segments
// (within `tolerance` of one line) merged into their union, pieces of `second` that `first`
// covers removed, then chained at shared ends (ends within `tolerance` are one point) into
// polylines of one kind, straight runs as one piece, and ordered by the nearest next end.
void mergeStrokes(const std::vector<StrokeSegment>& first, const std::vector<StrokeSegment>& second,
                  double tolerance, std::vector<Stroke>* first_out, std::vector<Stroke>* second_out,
                  StrokeStats* first_stats, StrokeStats* second_stats);

// Pen-up travel from the end of each stroke to the start of the next.
double penUpTravel(const std::vector<Stroke>& strokes);

}  // namespace hsr::detail
