#pragma once
// Roberts' algorithm over the pipeline's window polygons, for the algorithm's entry
// (roberts.cpp) and the hidden-line drawings (lines/line_drawing.cpp).

#include <vector>

#include "core/deadline.hpp"
#include "core/trace.hpp"
#include "hsr/render.hpp"
#include "hsr/roberts.hpp"
#include "hsr/scene.hpp"
#include "pipeline/pipeline.hpp"

namespace hsr::detail {

// Roberts' visible edges of the pipeline's window polygons (roberts.cpp); with `frame`, the
// visible faces are filled into it; with `trace`, the steps are recorded (`hsr explain`); with
// `hidden_parts`, the hidden parts of the edges are kept too (RobertsDrawing::hidden); with
// `deadline`, it throws DeadlinePassed (core/deadline.hpp) once that has passed.
RobertsDrawing robertsDrawingOf(const Scene& scene, const std::vector<WindowPolygon>& polygons,
                                int width, int height, Frame* frame, Trace* trace,
                                bool hidden_parts = false, const Deadline* deadline = nullptr);

}  // namespace hsr::detail
