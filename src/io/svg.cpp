// SVG of a hidden-line drawing (hsr/line_drawing.hpp): plain paths in groups, coordinates
// written out (no transforms), so plotter drivers that know only paths read it as meant.

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <glm/common.hpp>

#include "hsr/error.hpp"
#include "hsr/line_drawing.hpp"

namespace hsr {

SvgPage svgPageNamed(const std::string& name) {
  std::string base = name;
  bool landscape = false;
  if (const std::string suffix = "-landscape";
      base.size() > suffix.size() &&
      base.compare(base.size() - suffix.size(), suffix.size(), suffix) == 0) {
    base.resize(base.size() - suffix.size());
    landscape = true;
  }
  std::string lower = base;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  SvgPage page;
  if (lower == "a4")
    page.width_mm = 210, page.height_mm = 297;
  else if (lower == "a3")
    page.width_mm = 297, page.height_mm = 420;
  else if (lower == "letter")
    page.width_mm = 215.9, page.height_mm = 279.4;
  else
    throw Error("--page " + name + ": unknown page (A4, A3, letter, with -landscape to turn it)");
  if (landscape) std::swap(page.width_mm, page.height_mm);
  return page;
}

std::string lineDrawingSvg(const LineDrawing& d, const SvgPage& page) {
  const bool on_page = page.width_mm > 0 && page.height_mm > 0;
  // Window pixels (centres at integers) to the document's units: the view's pixel squares
  // fill [0, W] x [0, H], scaled and centred inside the margins on a page.
  double scale = 1, ox = 0.5, oy = 0.5;
  if (on_page) {
    // The lines' bounds (the view's when there are none) fill the page inside its margins
    glm::dvec2 lo(-0.5), hi(d.width - 0.5, d.height - 0.5);
    if (!d.visible.empty() || !d.hidden.empty()) {
      lo = glm::dvec2(INFINITY), hi = glm::dvec2(-INFINITY);
      for (const auto* layer : {&d.visible, &d.hidden})
        for (const LineStroke& s : *layer)
          for (const glm::dvec2& q : s.points) lo = glm::min(lo, q), hi = glm::max(hi, q);
    }
    const glm::dvec2 size = glm::max(hi - lo, glm::dvec2(1e-9));
    const double w = std::max(page.width_mm - 2 * page.margin_mm, 1e-3);
    const double h = std::max(page.height_mm - 2 * page.margin_mm, 1e-3);
    scale = std::min(w / size.x, h / size.y);
    ox = (page.width_mm - scale * size.x) / 2 - scale * lo.x;
    oy = (page.height_mm - scale * size.y) / 2 - scale * lo.y;
  }
  const double doc_w = on_page ? page.width_mm : d.width,
               doc_h = on_page ? page.height_mm : d.height;
  const double stroke = on_page ? page.stroke_mm : 1.0;
  std::string out;
  out.reserve(256 + 24 * (d.visible_stats.length > 0 ? d.visible.size() + d.hidden.size() : 0));
  fmt::format_to(
      std::back_inserter(out),
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}{2}\" height=\"{1}{2}\" "
      "viewBox=\"0 0 {0} {1}\">\n"
      "<!-- hsr hidden-line drawing of a {3}x{4} view: {5} visible strokes, {6} hidden -->\n",
      doc_w, doc_h, on_page ? "mm" : "", d.width, d.height, d.visible.size(), d.hidden.size());
  auto layer = [&](const std::vector<LineStroke>& strokes, const char* id, bool dashed) {
    fmt::format_to(std::back_inserter(out),
                   "<g id=\"{}\"{} fill=\"none\" stroke=\"black\" stroke-width=\"{}\" "
                   "stroke-linecap=\"round\" stroke-linejoin=\"round\"",
                   id, dashed ? " class=\"hidden\"" : "", stroke);
    if (dashed) fmt::format_to(std::back_inserter(out), " stroke-dasharray=\"{}\"", page.dash);
    out += ">\n";
    for (const LineStroke& s : strokes) {
      fmt::format_to(std::back_inserter(out), "<path class=\"{}\" d=\"", lineKindName(s.kind));
      const bool closed = s.points.size() > 3 && s.points.front() == s.points.back();
      const std::size_t n = closed ? s.points.size() - 1 : s.points.size();
      for (std::size_t i = 0; i < n; ++i)
        fmt::format_to(std::back_inserter(out), "{}{:.4f},{:.4f}", i == 0 ? "M" : " L",
                       ox + scale * s.points[i].x, oy + scale * s.points[i].y);
      out += closed ? " Z\"/>\n" : "\"/>\n";
    }
    out += "</g>\n";
  };
  layer(d.visible, "visible", false);
  if (!d.hidden.empty()) layer(d.hidden, "hidden", true);
  out += "</svg>\n";
  return out;
}

}  // namespace hsr
