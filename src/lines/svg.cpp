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
#include "hsr/visible_set.hpp"
#include "lines/doc_frame.hpp"

namespace hsr {

using detail::DocFrame;
using detail::docFrame;

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

namespace {

void header(std::string& out, const DocFrame& f, int view_w, int view_h, const std::string& what) {
  fmt::format_to(std::back_inserter(out),
                 "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                 "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}{2}\" height=\"{1}{2}\" "
                 "viewBox=\"0 0 {0} {1}\">\n"
                 "<!-- hsr {3} of a {4}x{5} view -->\n",
                 f.width, f.height, f.on_page ? "mm" : "", what, view_w, view_h);
}

}  // namespace

std::string lineDrawingSvg(const LineDrawing& d, const SvgPage& page) {
  const DocFrame f = docFrame(d, page);
  const double stroke = f.on_page ? page.stroke_mm : 1.0;
  std::string out;
  out.reserve(256 + 24 * (d.visible_stats.length > 0 ? d.visible.size() + d.hidden.size() : 0));
  header(
      out, f, d.width, d.height,
      fmt::format("hidden-line drawing ({}): {} visible strokes, {} hidden",
                  !d.exact ? "NOT exact: lines from the z-buffer's ids, the exact drawing passed "
                             "the time limit"
                  : d.engine == LineEngine::kRoberts
                      ? "exact, engine roberts: Roberts' visible segments of every edge"
                      : "exact, engine edges: the edges classified, then tested against the "
                        "triangles in front of them",
                  d.visible.size(), d.hidden.size()));
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
                       f.at(s.points[i]).x, f.at(s.points[i]).y);
      out += closed ? " Z\"/>\n" : "\"/>\n";
    }
    out += "</g>\n";
  };
  layer(d.visible, "visible", false);
  if (!d.hidden.empty()) layer(d.hidden, "hidden", true);
  out += "</svg>\n";
  return out;
}

std::string visibleSetSvg(const VisibleSet& set, const SvgPage& page) {
  const DocFrame f = docFrame(set, page);
  std::string out;
  header(out, f, set.width, set.height,
         fmt::format("visible set: {} polygons", set.polygons.size()));
  out += "<g id=\"visible-set\" stroke=\"none\" fill-rule=\"evenodd\">\n";
  for (const VisiblePolygon& v : set.polygons) {
    if (v.region.empty()) continue;
    fmt::format_to(std::back_inserter(out), "<path id=\"p{}\" fill=\"#{:02x}{:02x}{:02x}\" d=\"",
                   v.id, v.rgba & 0xFF, (v.rgba >> 8) & 0xFF, (v.rgba >> 16) & 0xFF);
    bool first = true;
    auto ring = [&](const ExactRing& r) {
      for (std::size_t i = 0; i < r.size(); ++i) {
        const glm::dvec2 q = f.at(detail::pixelOf(r[i]));
        fmt::format_to(std::back_inserter(out), "{}{}{:.4f},{:.4f}", first ? "" : " ",
                       i == 0 ? "M" : "L", q.x, q.y);
        first = false;
      }
      out += " Z";
    };
    for (const ExactPolygon& p : v.region) {
      ring(p.outer);
      for (const ExactRing& h : p.holes) ring(h);
    }
    out += "\"/>\n";
  }
  out += "</g>\n</svg>\n";
  return out;
}

}  // namespace hsr
