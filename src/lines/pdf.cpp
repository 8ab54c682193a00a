// PDF of a hidden-line drawing or of the visible set, through cairo (Debian's libcairo2): the
// same strokes, layers, page and colours as the SVG writers (svg.cpp), drawn with cairo's
// paths. Units: millimetres on a page, else a view pixel as a CSS pixel (0.75 point).

#include <cairo-pdf.h>
#include <cairo.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "hsr/error.hpp"
#include "hsr/line_drawing.hpp"
#include "hsr/visible_set.hpp"
#include "lines/doc_frame.hpp"

namespace hsr {

namespace {

cairo_status_t append(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

// A PDF document of one page, the size of the frame, drawn in the frame's units.
class PdfDocument {
 public:
  explicit PdfDocument(const detail::DocFrame& f) {
    const double pt = f.on_page ? 72.0 / 25.4 : 0.75;  // points per unit
    surface_ = cairo_pdf_surface_create_for_stream(append, &bytes_, f.width * pt, f.height * pt);
    cr_ = cairo_create(surface_);
    cairo_scale(cr_, pt, pt);
  }
  ~PdfDocument() {
    cairo_destroy(cr_);
    cairo_surface_destroy(surface_);
  }
  PdfDocument(const PdfDocument&) = delete;
  PdfDocument& operator=(const PdfDocument&) = delete;
  cairo_t* cr() const { return cr_; }
  std::string finish() {
    cairo_surface_finish(surface_);
    if (const cairo_status_t st = cairo_surface_status(surface_); st != CAIRO_STATUS_SUCCESS)
      throw Error(std::string("PDF: ") + cairo_status_to_string(st));
    return std::move(bytes_);
  }

 private:
  std::string bytes_;
  cairo_surface_t* surface_ = nullptr;
  cairo_t* cr_ = nullptr;
};

std::vector<double> dashesOf(const std::string& pattern) {
  std::vector<double> out;
  const char* p = pattern.c_str();
  while (*p) {
    char* end = nullptr;
    const double v = std::strtod(p, &end);
    if (end == p) {
      ++p;
      continue;
    }
    if (v > 0) out.push_back(v);
    p = end;
  }
  return out;
}

}  // namespace

std::string lineDrawingPdf(const LineDrawing& d, const SvgPage& page) {
  const detail::DocFrame f = detail::docFrame(d, page);
  PdfDocument doc(f);
  cairo_t* cr = doc.cr();
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, f.on_page ? page.stroke_mm : 1.0);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  for (const bool hidden : {false, true}) {
    const std::vector<double> dashes = hidden ? dashesOf(page.dash) : std::vector<double>{};
    cairo_set_dash(cr, dashes.data(), static_cast<int>(dashes.size()), 0);
    for (const LineStroke& s : hidden ? d.hidden : d.visible) {
      const bool closed = s.points.size() > 3 && s.points.front() == s.points.back();
      const std::size_t n = closed ? s.points.size() - 1 : s.points.size();
      for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2 q = f.at(s.points[i]);
        (i == 0 ? cairo_move_to : cairo_line_to)(cr, q.x, q.y);
      }
      if (closed) cairo_close_path(cr);
      cairo_stroke(cr);
    }
  }
  return doc.finish();
}

std::string visibleSetPdf(const VisibleSet& set, const SvgPage& page) {
  const detail::DocFrame f = detail::docFrame(set, page);
  PdfDocument doc(f);
  cairo_t* cr = doc.cr();
  cairo_set_fill_rule(cr, CAIRO_FILL_RULE_EVEN_ODD);
  for (const VisiblePolygon& v : set.polygons) {
    if (v.region.empty()) continue;
    auto ring = [&](const ExactRing& r) {
      for (std::size_t i = 0; i < r.size(); ++i) {
        const glm::dvec2 q = f.at(detail::pixelOf(r[i]));
        (i == 0 ? cairo_move_to : cairo_line_to)(cr, q.x, q.y);
      }
      cairo_close_path(cr);
    };
    for (const ExactPolygon& p : v.region) {
      ring(p.outer);
      for (const ExactRing& h : p.holes) ring(h);
    }
    cairo_set_source_rgb(cr, (v.rgba & 0xFF) / 255.0, ((v.rgba >> 8) & 0xFF) / 255.0,
                         ((v.rgba >> 16) & 0xFF) / 255.0);
    cairo_fill(cr);
  }
  return doc.finish();
}

}  // namespace hsr
