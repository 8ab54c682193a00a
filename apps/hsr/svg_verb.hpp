#pragma once
// `hsr svg`: a scene's hidden-line drawing as SVG, exact and plotter-ready.

#include <string>

#include <CLI/CLI.hpp>

#include "args.hpp"

namespace hsr::cli {

struct SvgVerb {
  CLI::App* verb = nullptr;
  Args args;
  std::string output, style = "lines", hidden = "none", dash, page, stats_file, pdf,
                      fallback = "none", engine = "edges", kinds = "outline,crease,intersection";
  double crease_angle = 30, margin = 10, stroke = 0.35, time_limit = 0;
  bool quiet = false;
};

// Adds the verb to `app`.
void addSvgVerb(CLI::App& app, SvgVerb& v);

// Runs it; throws hsr::Error on bad input.
int runSvg(SvgVerb& v);

}  // namespace hsr::cli
