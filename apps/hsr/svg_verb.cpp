// `hsr svg SCENE -o FILE.svg`: the visible outlines, creases and intersection lines of SCENE as
// pen strokes (hsr/line_drawing.hpp), with the hidden parts dashed on request, on a page in
// millimetres on request.

#include "svg_verb.hpp"

#include <chrono>
#include <cmath>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "common.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/line_drawing.hpp"
#include "hsr/output.hpp"
#include "hsr/visible_set.hpp"

namespace hsr::cli {

void addSvgVerb(CLI::App& app, SvgVerb& v) {
  v.verb = app.add_subcommand(
      "svg", "draw SCENE's visible lines (outlines, creases, intersections) exactly as SVG");
  addViewOptions(v.verb, v.args);
  v.verb->add_option("-o", v.output, "output SVG (default out/SCENE.svg)");
  v.verb
      ->add_option("--style", v.style,
                   "lines (the visible lines), or filled (the visible set: each polygon's visible "
                   "region, flat-shaded)")
      ->capture_default_str();
  v.verb->add_option("--hidden", v.hidden, "the hidden parts of the same lines: none or dashed")
      ->capture_default_str();
  v.verb->add_option("--dash", v.dash,
                     "the hidden lines' dash pattern (SVG stroke-dasharray: mm on a page, else "
                     "pixels; default 2,1 on a page, 6,3 without)");
  v.verb
      ->add_option("--crease-angle", v.crease_angle,
                   "draw the edge where two polygons meet at more than this (degrees)")
      ->capture_default_str();
  v.verb
      ->add_option("--lines", v.kinds,
                   "which lines, comma-separated: outline, crease, intersection (outline alone: "
                   "silhouettes and borders)")
      ->capture_default_str();
  v.verb
      ->add_option("--engine", v.engine,
                   "edges (classify the edges, then test the lines against the triangles in "
                   "front), or roberts (Roberts' segments of every edge, the reference)")
      ->capture_default_str();
  v.verb->add_option("--page", v.page,
                     "fit the drawing on a page, sizes in mm: A4, A3, letter (add -landscape)");
  v.verb->add_option("--margin", v.margin, "page margin (mm)")->capture_default_str();
  v.verb->add_option("--stroke", v.stroke, "pen width on a page (mm)")->capture_default_str();
  v.verb->add_option("--pdf", v.pdf, "also write the drawing as PDF (through cairo)");
  v.verb->add_option(
      "--time-limit", v.time_limit,
      "seconds the exact lines may take (0: no limit); past it, stop with a message, or "
      "see --fallback");
  v.verb
      ->add_option("--fallback", v.fallback,
                   "past the time limit: none (stop), or raster (lines from the z-buffer's ids, "
                   "said so)")
      ->capture_default_str();
  v.verb->add_option("--stats", v.stats_file, "write the counts, lengths and times as JSON");
  v.verb->add_flag("-q,--quiet", v.quiet, "no summary");
}

namespace {

// --style filled: the visible set as filled regions.
int runFilled(const SvgVerb& v, const hsr::Scene& scene, const hsr::Camera& camera,
              const hsr::SvgPage& page, const std::string& out) {
  const auto t0 = std::chrono::steady_clock::now();
  const hsr::VisibleSet set = hsr::visibleSet(scene, camera, makeOptions(v.args));
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (set.unresolved > 0)
    fmt::print(
        stderr,
        "hsr: warning: {} polygons were left unresolved (the visible set's work limit): their "
        "regions may overlap\n",
        set.unresolved);
  if (set.see_through > 0)
    fmt::print(stderr,
               "hsr: warning: {} see-through polygons are not drawn: the visible set holds the "
               "opaque ones\n",
               set.see_through);
  hsr::writeFileAtomically(out, {hsr::visibleSetSvg(set, page)});
  std::vector<std::string> written{out};
  if (!v.pdf.empty()) {
    hsr::writeFileAtomically(v.pdf, {hsr::visibleSetPdf(set, page)});
    written.push_back(v.pdf);
  }
  if (v.verb->count("--stats") > 0) {
    const nlohmann::json j{{"scene", v.args.scene},
                           {"width", set.width},
                           {"height", set.height},
                           {"style", "filled"},
                           {"polygons", set.polygons.size()},
                           {"unresolved", set.unresolved},
                           {"visibility_ms", ms}};
    hsr::writeFileAtomically(v.stats_file, {j.dump(2) + "\n"});
    written.push_back(v.stats_file);
  }
  if (!v.quiet) {
    fmt::print("hsr svg {}: {}x{} view, filled: the visible set (Weiler-Atherton), exact\n",
               v.args.scene, set.width, set.height);
    fmt::print("  regions  {} visible polygons of {}, {} Boolean operations\n", set.polygons.size(),
               set.polygons_in, set.clips);
    fmt::print("  time     {:.1f} ms\n", ms);
    for (const std::string& w : written) fmt::print("  wrote {}\n", w);
  }
  return 0;
}

}  // namespace

int runSvg(SvgVerb& v) {
  const Args& a = v.args;
  if (v.verb->count("--algorithm") > 0)
    throw hsr::Error(
        "hsr svg computes its lines exactly in object space (see --engine); --algorithm does not "
        "apply");
  if (v.engine != "edges" && v.engine != "roberts")
    throw hsr::Error("--engine " + printable(v.engine) + ": edges or roberts");
  bool kind[3] = {false, false, false};
  {
    std::size_t from = 0;
    while (from <= v.kinds.size()) {
      const std::size_t comma = std::min(v.kinds.find(',', from), v.kinds.size());
      const std::string k = v.kinds.substr(from, comma - from);
      if (k == "outline")
        kind[0] = true;
      else if (k == "crease")
        kind[1] = true;
      else if (k == "intersection")
        kind[2] = true;
      else
        throw hsr::Error("--lines " + printable(v.kinds) +
                         ": outline, crease and intersection, comma-separated");
      from = comma + 1;
    }
  }
  if (v.hidden != "none" && v.hidden != "dashed")
    throw hsr::Error("--hidden " + printable(v.hidden) + ": none or dashed");
  if (v.style != "lines" && v.style != "filled")
    throw hsr::Error("--style " + printable(v.style) + ": lines or filled");
  if (v.fallback != "none" && v.fallback != "raster")
    throw hsr::Error("--fallback " + printable(v.fallback) + ": none or raster");
  if (!(v.time_limit >= 0) || !std::isfinite(v.time_limit))
    throw hsr::Error("--time-limit must be a number of seconds (0: no limit)");
  if (v.verb->count("--fallback") > 0 && v.time_limit == 0)
    throw hsr::Error("--fallback applies past a time limit (--time-limit S)");
  const bool filled = v.style == "filled";
  if (filled)
    for (const char* option : {"--hidden", "--crease-angle", "--dash", "--time-limit", "--fallback",
                               "--lines", "--engine"})
      if (v.verb->count(option) > 0)
        throw hsr::Error(std::string(option) + " applies to lines; --style filled draws no lines");
  hsr::SvgPage page;
  if (!v.page.empty()) page = hsr::svgPageNamed(v.page);
  if (v.verb->count("--margin") > 0 || v.verb->count("--stroke") > 0) {
    if (v.page.empty()) throw hsr::Error("--margin and --stroke apply to a page (--page)");
    if (!(v.margin >= 0) || 2 * v.margin >= std::min(page.width_mm, page.height_mm))
      throw hsr::Error(fmt::format("--margin {}: must leave room on the page", v.margin));
    if (!(v.stroke > 0) || !std::isfinite(v.stroke))
      throw hsr::Error("--stroke must be a positive width");
  }
  page.margin_mm = v.margin;
  page.stroke_mm = v.stroke;
  page.dash = v.dash.empty() ? (v.page.empty() ? "6,3" : "2,1") : v.dash;
  for (const char c : page.dash)
    if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == ',' || c == ' '))
      throw hsr::Error("--dash " + printable(v.dash) +
                       ": numbers separated by commas, such as 2,1");
  const std::string out = v.output.empty() ? "out/" + sceneLabel(a.scene) + ".svg" : v.output;
  OutputPlan plan(a.scene);
  plan.file("-o", out);
  requireExtension("-o", out, ".svg", "an SVG drawing");
  if (v.verb->count("--stats") > 0) plan.file("--stats", v.stats_file);
  if (v.verb->count("--pdf") > 0) {
    plan.file("--pdf", v.pdf);
    requireExtension("--pdf", v.pdf, ".pdf", "a PDF drawing");
  }

  const hsr::Scene scene = hsr::loadScene(a.scene, importLimits(a));
  const hsr::Camera camera = makeCamera(a, scene);
  warnIfDepthUnresolvable(camera);
  warnIfEyeInside(scene, camera);
  if (filled) return runFilled(v, scene, camera, page, out);
  hsr::LineDrawingOptions lines;
  lines.crease_angle_deg = v.crease_angle;
  lines.hidden = v.hidden == "dashed";
  lines.time_limit_s = v.time_limit;
  lines.raster_fallback = v.fallback == "raster";
  lines.outlines = kind[0], lines.creases = kind[1], lines.intersections = kind[2];
  lines.engine = v.engine == "roberts" ? hsr::LineEngine::kRoberts : hsr::LineEngine::kEdges;
  const hsr::LineDrawing d = hsr::lineDrawing(scene, camera, makeOptions(a), lines);
  hsr::writeFileAtomically(out, {hsr::lineDrawingSvg(d, page)});
  std::vector<std::string> written{out};
  if (!v.pdf.empty()) {
    hsr::writeFileAtomically(v.pdf, {hsr::lineDrawingPdf(d, page)});
    written.push_back(v.pdf);
  }
  auto layerJson = [](const hsr::LineLayerStats& s) {
    return nlohmann::json{{"segments", s.segments},
                          {"strokes", s.strokes},
                          {"length_px", s.length},
                          {"pen_up_px", s.pen_up},
                          {"pen_up_unordered_px", s.pen_up_unordered}};
  };
  if (v.verb->count("--stats") > 0) {
    nlohmann::json stages = nlohmann::json::object();
    for (const auto& [stage, ms] : d.stage_ms) stages[stage] = ms;
    const nlohmann::json j{{"scene", a.scene},
                           {"width", d.width},
                           {"height", d.height},
                           {"visible", layerJson(d.visible_stats)},
                           {"hidden", layerJson(d.hidden_stats)},
                           {"segments",
                            {{"outline", d.outline_segments},
                             {"crease", d.crease_segments},
                             {"intersection", d.intersection_segments},
                             {"smooth_left_out", d.smooth_segments}}},
                           {"exact", d.exact},
                           {"engine", d.exact ? v.engine : "raster"},
                           {"visibility_ms", d.visibility_ms},
                           {"visibility_stages_ms", stages},
                           {"strokes_ms", d.strokes_ms}};
    hsr::writeFileAtomically(v.stats_file, {j.dump(2) + "\n"});
    written.push_back(v.stats_file);
  }
  if (!v.quiet) {
    fmt::print("hsr svg {}: {}x{} view, {}\n", a.scene, d.width, d.height,
               d.exact
                   ? (v.engine == "roberts" ? "lines exact (Roberts' visible segments)"
                                            : "lines exact (edges tested against the triangles in "
                                              "front)")
                   : fmt::format("NOT exact: the exact lines passed the time limit of {} s; these "
                                 "are lines from the z-buffer's ids (pixel edges), no hidden layer",
                                 v.time_limit));
    auto layer = [](const char* name, const hsr::LineLayerStats& s) {
      fmt::print(
          "  {:<8} {:>7} strokes from {:>7} segments, {:>10.0f} px long; pen-up travel {:.0f} px "
          "({:.0f} px unordered)\n",
          name, s.strokes, s.segments, s.length, s.pen_up, s.pen_up_unordered);
    };
    layer("visible", d.visible_stats);
    if (lines.hidden) layer("hidden", d.hidden_stats);
    fmt::print(
        "  lines    {} outline, {} crease, {} intersection pieces; {} {} within {} degrees "
        "left out\n",
        d.outline_segments, d.crease_segments, d.intersection_segments, d.smooth_segments,
        v.engine == "roberts" ? "segments" : "edges", v.crease_angle);
    std::string steps;
    for (const auto& [stage, ms] : d.stage_ms)
      steps += fmt::format("{}{} {:.1f}", steps.empty() ? "" : ", ", stage, ms);
    fmt::print("  time     visibility {:.1f} ms ({}), strokes {:.1f} ms\n", d.visibility_ms, steps,
               d.strokes_ms);
    for (const std::string& w : written) fmt::print("  wrote {}\n", w);
  }
  return 0;
}

}  // namespace hsr::cli
