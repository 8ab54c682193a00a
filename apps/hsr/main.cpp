// hsr: the command line. The only code that parses argv, prints, and picks exit codes:
// 0 success, 2 bad input or usage (one line on stderr), 1 internal error.

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/vector_relational.hpp>
#include <fmt/core.h>

#include "hsr/compare.hpp"
#include "hsr/error.hpp"
#include "hsr/explain.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "args.hpp"

namespace fs = std::filesystem;

namespace {

using hsr::cli::Args;
using hsr::cli::makeCamera;
using hsr::cli::makeOptions;
using hsr::cli::addViewOptions;

std::string sceneLabel(const std::string& spec) {
  std::string name = fs::exists(spec) ? fs::path(spec).stem().string() : spec;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return name;
}

// Rendering from inside an object is legitimate (the near plane clips what surrounds the
// eye), but often a mistake: say so on one line.
void warnIfEyeInside(const hsr::Scene& scene, const hsr::Camera& cam) {
  if (cam.ortho) return;
  for (const hsr::Object& o : scene.objects) {
    const hsr::Bounds& b = o.bounds;
    if (b.empty()) continue;
    if (glm::all(glm::greaterThanEqual(cam.eye, b.lo)) && glm::all(glm::lessThanEqual(cam.eye, b.hi))) {
      std::fprintf(stderr, "hsr: warning: the eye is inside the bounds of object '%s'; what "
                   "surrounds it is clipped at the near plane\n", o.name.c_str());
      return;
    }
  }
}

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == ',') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

void ensureParent(const fs::path& p) {
  if (p.has_parent_path()) fs::create_directories(p.parent_path());
}

void printSummary(const hsr::Frame& f, const std::string& scene, const std::string& algorithm,
                  const std::vector<std::string>& written) {
  const hsr::Stats& s = f.stats;
  fmt::print("hsr {} {}  {}x{}\n", algorithm, scene, f.width, f.height);
  // Every count of the one table, with what it counts (zero counts of rarer events omitted).
  for (const hsr::Stats::Field& field : hsr::Stats::fields()) {
    const std::uint64_t v = s.*field.value;
    if (field.name == "state_bytes") continue;
    if (v == 0 && field.name != "polygons_in" && field.name != "triangles_in" &&
        field.name != "triangles_rasterized" && field.name != "fragments_written")
      continue;
    std::string label(field.name);
    std::replace(label.begin(), label.end(), '_', ' ');
    fmt::print("  {:<22}{:>12}   {}\n", label, v, field.meaning);
  }
  for (const hsr::Counter& c : s.counters) fmt::print("  {:<22}{:>12}\n", c.name, c.value);
  fmt::print("  {:<22}{:>12.1f}   MiB ({:.1f} bytes/pixel)\n", "state memory",
             s.state_bytes / 1048576.0, double(s.state_bytes) / (double(f.width) * f.height));
  fmt::print("  time per stage:");
  for (const hsr::StageTime& st : s.stages) fmt::print("  {} {:.2f} ms", st.name, st.ms);
  fmt::print("\n  total {:.2f} ms\n", s.totalMs());
  for (const std::string& w : written) fmt::print("  wrote {}\n", w);
}

int runRender(const Args& a) {
  const hsr::Scene scene = hsr::loadScene(a.scene);
  const hsr::Camera cam = makeCamera(a, scene);
  warnIfEyeInside(scene, cam);
  const hsr::RenderOptions opt = makeOptions(a);
  const std::vector<std::string> kinds = splitList(a.outputs);
  if (kinds.empty()) throw hsr::Error("--output needs at least one of color,depth,ids,overdraw");
  for (const std::string& k : kinds)
    if (k != "color" && k != "depth" && k != "ids" && k != "overdraw")
      throw hsr::Error(fmt::format("unknown output '{}' (color, depth, ids, overdraw)", k));
  const hsr::Frame frame = hsr::render(scene, cam, opt);

  std::vector<std::string> written;
  const fs::path base = a.output_file.empty() ? fs::path("out") / (sceneLabel(a.scene) + ".png")
                                              : fs::path(a.output_file);
  for (const std::string& k : kinds) {
    fs::path p = base;
    if (kinds.size() > 1) p.replace_filename(base.stem().string() + "-" + k + ".png");
    ensureParent(p);
    hsr::writePng(p, frame.width, frame.height, 3, hsr::picture(frame, k).data());
    written.push_back(p.string());
  }
  if (!a.raw_dir.empty()) {
    const fs::path d(a.raw_dir);
    fs::create_directories(d);
    hsr::writeNpy(d / "depth.npy", frame.width, frame.height, frame.depth.data());
    hsr::writeNpy(d / "ids.npy", frame.width, frame.height, frame.ids.data());
    hsr::writeNpy(d / "overdraw.npy", frame.width, frame.height, frame.overdraw.data());
    written.push_back((d / "{depth,ids,overdraw}.npy").string());
  }
  if (!a.stats_file.empty()) {
    const fs::path p(a.stats_file);
    ensureParent(p);
    std::FILE* f = std::fopen(p.string().c_str(), "wb");
    if (!f) throw hsr::Error(fmt::format("{}: cannot open for writing", p.string()));
    const std::string json = hsr::statsJson(frame, a.scene, opt.algorithm);
    const bool ok = std::fwrite(json.data(), 1, json.size(), f) == json.size();
    if (std::fclose(f) != 0 || !ok) throw hsr::Error(fmt::format("{}: write failed", p.string()));
    written.push_back(p.string());
  }
  if (!a.quiet) printSummary(frame, a.scene, opt.algorithm, written);
  return 0;
}

int runCompare(const Args& a) {
  const hsr::Scene scene = hsr::loadScene(a.scene);
  const hsr::Camera cam = makeCamera(a, scene);
  const hsr::RenderOptions opt = makeOptions(a);
  const std::vector<hsr::ComparisonRow> rows = hsr::compareAlgorithms(scene, cam, opt);
  fmt::print("hsr compare {}  {}x{}  ({} polygons)\n", a.scene, cam.width, cam.height,
             scene.polygonCount());
  fmt::print("  {:<12} {:>10} {:>12} {:>10} {:>8} {:>12} {:>10}\n", "algorithm", "time ms",
             "memory MiB", "overdraw", "max", "ids = zbuf", "differ px");
  for (const hsr::ComparisonRow& r : rows)
    fmt::print("  {:<12} {:>10.2f} {:>12.1f} {:>10.2f} {:>8} {:>11.4f}% {:>10}\n", r.algorithm,
               r.ms, r.state_bytes / 1048576.0, r.mean_overdraw, r.max_overdraw,
               100.0 * r.id_agreement, r.differing_pixels);
  if (!a.sheet_file.empty()) {
    int w = 0, h = 0;
    const std::vector<std::uint8_t> sheet = hsr::comparisonSheet(rows, &w, &h);
    ensureParent(a.sheet_file);
    hsr::writePng(a.sheet_file, w, h, 3, sheet.data());
    fmt::print("  wrote {}\n", a.sheet_file);
  }
  return 0;
}

int runExplain(const Args& a, const std::string& dir_arg) {
  const hsr::Scene scene = hsr::loadScene(a.scene);
  const hsr::Camera cam = makeCamera(a, scene);
  const hsr::RenderOptions opt = makeOptions(a);
  const fs::path dir =
      dir_arg.empty() ? fs::path("out") / ("explain-" + opt.algorithm + "-" + sceneLabel(a.scene))
                      : fs::path(dir_arg);
  const hsr::Explanation e = hsr::explain(scene, cam, opt, dir);
  if (!a.quiet) {
    fmt::print("hsr explain {} {}  {}x{}: {} steps\n", opt.algorithm, a.scene, cam.width,
               cam.height, e.steps.size());
    for (const hsr::ExplainedStep& s : e.steps)
      fmt::print("  {:>2}. {:<14} {}\n", s.number, s.name, s.caption);
    fmt::print("  wrote {} pictures, {} and {}\n", e.steps.size(), e.sheet.string(),
               e.index.string());
  }
  return 0;
}

int runScenes() {
  fmt::print("built-in scenes (a file of the same name wins):\n");
  for (const hsr::BuiltinScene& s : hsr::builtinScenes()) fmt::print("  {:<16} {}\n", s.name, s.summary);
  fmt::print("algorithms:\n");
  for (const hsr::AlgorithmInfo& i : hsr::algorithms())
    fmt::print("  {:<18} {} precision{}: {}\n                     input: {}; can: {}\n", i.name,
               hsr::toString(i.precision), i.reference ? ", the reference" : "", i.summary,
               hsr::toString(i.input), hsr::capabilityList(i.capabilities));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hsr: hidden-surface removal with every classic algorithm.\n"
               "Examples:\n"
               "  hsr                                  render the demo scene to out/demo.png\n"
               "  hsr render spheres:100000 --size 1920x1080 --cull back -o out/s.png\n"
               "  hsr render model.obj --output color,depth,ids,overdraw --raw out/raw\n"
               "  hsr render demo --polygon-mode line --eye 4,3,6 --target 0,0,0\n"
               "  hsr compare demo --sheet out/sheet.png\n"
               "  hsr explain zbuffer-textbook demo -o out/explain\n"
               "  hsr scenes"};
  app.require_subcommand(0, 1);
  Args a;
  CLI::App* render = app.add_subcommand("render", "render SCENE with one algorithm");
  addViewOptions(render, a);
  render->add_option("--output", a.outputs, "pictures to write: color,depth,ids,overdraw")
      ->capture_default_str();
  render->add_option("-o", a.output_file, "output PNG (default out/SCENE.png; with several "
                                          "outputs, FILE-KIND.png)");
  render->add_option("--raw", a.raw_dir, "write depth.npy, ids.npy, overdraw.npy into DIR");
  render->add_option("--stats", a.stats_file, "write counts and stage times as JSON");
  render->add_flag("-q,--quiet", a.quiet, "no summary");
  CLI::App* compare = app.add_subcommand("compare", "run every algorithm on SCENE and compare");
  addViewOptions(compare, a);
  compare->add_option("--sheet", a.sheet_file, "write the pictures side by side, labelled");
  CLI::App* explain = app.add_subcommand(
      "explain", "explain ALGORITHM on SCENE step by step: numbered pictures and a contact sheet");
  explain->add_option("ALGORITHM", a.algorithm, "an algorithm that can explain itself")->required();
  addViewOptions(explain, a);
  std::string explain_dir;
  explain->add_option("-o", explain_dir, "output directory (default out/explain-ALGORITHM-SCENE)");
  explain->add_flag("-q,--quiet", a.quiet, "no summary");
  CLI::App* scenes = app.add_subcommand("scenes", "list built-in scenes and algorithms");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "hsr: %s (see hsr --help)\n", e.what());
    return 2;
  }

  try {
    if (*scenes) return runScenes();
    if (*compare) return runCompare(a);
    if (*explain) return runExplain(a, explain_dir);
    return runRender(a);  // `render`, or no verb at all: the demo scene
  } catch (const hsr::Error& e) {
    std::fprintf(stderr, "hsr: %s\n", e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "hsr: out of memory\n");
    return 1;
  } catch (const fs::filesystem_error& e) {
    std::fprintf(stderr, "hsr: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hsr: internal error: %s\n", e.what());
    return 1;
  }
}
