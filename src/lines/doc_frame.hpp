#pragma once
// Where a drawing's window pixels land on its document (SVG or PDF): shared by the writers.

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include "hsr/line_drawing.hpp"
#include "hsr/visible_set.hpp"

namespace hsr::detail {

// Window pixels (centres at integers) to the document's units. Without a page the view's
// pixel squares fill [0, W] x [0, H]; on a page, the drawing's bounds [lo, hi] are scaled and
// centred inside the margins, in millimetres.
struct DocFrame {
  double scale = 1, ox = 0.5, oy = 0.5, width = 0, height = 0;
  bool on_page = false;
  glm::dvec2 at(glm::dvec2 q) const { return {ox + scale * q.x, oy + scale * q.y}; }
};

inline DocFrame docFrame(int view_w, int view_h, const SvgPage& page, glm::dvec2 lo,
                         glm::dvec2 hi) {
  DocFrame f;
  f.on_page = page.width_mm > 0 && page.height_mm > 0;
  f.width = f.on_page ? page.width_mm : view_w;
  f.height = f.on_page ? page.height_mm : view_h;
  if (!f.on_page) return f;
  if (!(lo.x <= hi.x && lo.y <= hi.y))
    lo = glm::dvec2(-0.5), hi = glm::dvec2(view_w - 0.5, view_h - 0.5);
  const glm::dvec2 size = glm::max(hi - lo, glm::dvec2(1e-9));
  const double w = std::max(page.width_mm - 2 * page.margin_mm, 1e-3);
  const double h = std::max(page.height_mm - 2 * page.margin_mm, 1e-3);
  f.scale = std::min(w / size.x, h / size.y);
  f.ox = (page.width_mm - f.scale * size.x) / 2 - f.scale * lo.x;
  f.oy = (page.height_mm - f.scale * size.y) / 2 - f.scale * lo.y;
  return f;
}

// A visible-set vertex in window pixels.
inline glm::dvec2 pixelOf(const ExactPoint& q) {
  return {q.xd() / kVisibleSetGrid, q.yd() / kVisibleSetGrid};
}

// The documents' frames: a line drawing's by its lines' bounds, a visible set's by its regions'.
inline DocFrame docFrame(const LineDrawing& d, const SvgPage& page) {
  glm::dvec2 lo(INFINITY), hi(-INFINITY);
  for (const auto* layer : {&d.visible, &d.hidden})
    for (const LineStroke& s : *layer)
      for (const glm::dvec2& q : s.points) lo = glm::min(lo, q), hi = glm::max(hi, q);
  return docFrame(d.width, d.height, page, lo, hi);
}
inline DocFrame docFrame(const VisibleSet& set, const SvgPage& page) {
  glm::dvec2 lo(INFINITY), hi(-INFINITY);
  for (const VisiblePolygon& v : set.polygons)
    for (const ExactPolygon& p : v.region)
      for (const ExactPoint& q : p.outer)
        lo = glm::min(lo, pixelOf(q)), hi = glm::max(hi, pixelOf(q));
  return docFrame(set.width, set.height, page, lo, hi);
}

}  // namespace hsr::detail
