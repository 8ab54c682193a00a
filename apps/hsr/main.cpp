// hsr: the command line. The only code that parses argv, prints, and picks exit codes:
// 0 success, 2 bad input or usage (one line on stderr), 1 internal error.

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/vector_relational.hpp>
#include <fmt/core.h>

#include "hsr/compare.hpp"
#include "hsr/error.hpp"
#include "hsr/explain.hpp"
#include "hsr/io.hpp"
#include "hsr/output.hpp"
#include "hsr/render.hpp"
#include "args.hpp"

namespace fs = std::filesystem;

namespace {

using hsr::cli::Args;
using hsr::cli::makeCamera;
using hsr::cli::makeOptions;
using hsr::cli::addViewOptions;

// A message as one line on a terminal: control characters (a newline in a file name, an
// escape sequence) are shown escaped, never acted on.
std::string printable(std::string_view s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    const bool c1 = c == 0xC2 && i + 1 < s.size() &&  // U+0080..U+009F, the C1 controls
                    static_cast<unsigned char>(s[i + 1]) >= 0x80 &&
                    static_cast<unsigned char>(s[i + 1]) <= 0x9F;
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c < 0x20 || c == 0x7F) {
      out += fmt::format("\\x{:02x}", c);
    } else if (c1) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned char>(s[++i]));
    } else {
      out += static_cast<char>(c);
    }
  }
  return out;
}

void printError(std::string_view message) {
  std::fprintf(stderr, "hsr: %s\n", printable(message).c_str());
}

// The outputs of one run, checked before any work: no empty name, no output that is the input
// model or another output of the run, no file inside a directory that is replaced as a whole.
class OutputPlan {
 public:
  explicit OutputPlan(const std::string& scene) {
    std::error_code ec;
    if (fs::is_regular_file(scene, ec)) input_ = key(scene);
  }
  void file(std::string_view option, const std::string& path) {
    if (path.empty()) throw hsr::Error(fmt::format("{} \"\": an empty path names no file", option));
    add(option, path, false);
  }
  void directory(std::string_view option, const std::string& path,
                 const std::vector<std::string>& own_names = {}) {
    if (path.empty()) throw hsr::Error(fmt::format("{} \"\": an empty path names no directory", option));
    add(option, path, true);
    hsr::checkOutputDirectory(path, own_names);
  }

 private:
  static fs::path key(const fs::path& p) {
    std::error_code ec;
    fs::path k = fs::weakly_canonical(fs::absolute(p), ec);
    return ec ? fs::absolute(p).lexically_normal() : k;
  }
  static bool inside(const fs::path& p, const fs::path& dir) {
    const auto [d, q] = std::mismatch(dir.begin(), dir.end(), p.begin(), p.end());
    return d == dir.end() && q != p.end();
  }
  void add(std::string_view option, const std::string& path, bool is_directory) {
    const fs::path k = key(path);
    if (!input_.empty() && (k == input_ || (is_directory && inside(input_, k))))
      throw hsr::Error(fmt::format("{} {}: {} the input model; refused, it would be overwritten",
                                   option, path, k == input_ ? "is" : "holds"));
    for (const Planned& o : planned_) {
      if (o.key == k)
        throw hsr::Error(fmt::format("{} {} and {} {} name the same output", o.option, o.path,
                                     option, path));
      if ((o.is_directory && inside(k, o.key)) || (is_directory && inside(o.key, k)))
        throw hsr::Error(fmt::format(
            "{} {} lies inside {} {}, a directory that is replaced as a whole",
            o.is_directory ? option : o.option, o.is_directory ? path : o.path,
            o.is_directory ? o.option : option, o.is_directory ? o.path : path));
    }
    planned_.push_back({std::string(option), path, k, is_directory});
  }
  struct Planned {
    std::string option, path;
    fs::path key;
    bool is_directory;
  };
  fs::path input_;
  std::vector<Planned> planned_;
};

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
      printError(fmt::format("warning: the eye is inside the bounds of object '{}'; what "
                             "surrounds it is clipped at the near plane",
                             o.name));
      return;
    }
  }
}

// A perspective depth buffer of floats resolves about 2^24 steps between near and far, most of
// them close to the near plane: past far/near = 2^24 every surface's depth rounds towards the
// clear value 1.0, and the picture comes out blank or merged. Valid, so a warning.
void warnIfDepthUnresolvable(const hsr::Camera& cam) {
  if (cam.ortho || !(cam.far / cam.near > 16777216.0f)) return;
  printError(fmt::format("warning: far/near = {:.3g} (near {:g}, far {:g}) is more than a float "
                         "depth buffer resolves (2^24): depths round to the clear value and "
                         "surfaces vanish or merge; raise --near",
                         cam.far / cam.near, cam.near, cam.far));
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

// An object-order algorithm that ran out of its split budget painted some polygons in the
// order reached: said on stderr even with --quiet, never silently.
void warnIfUnresolved(const hsr::Frame& f, const std::string& algorithm) {
  for (const hsr::Counter& c : f.stats.counters)
    if (c.value > 0 && c.name.ends_with(": unresolved"))
      fmt::print(stderr,
                 "hsr: warning: {} left {} orderings unresolved (its split budget was spent); "
                 "those polygons were painted in the order reached and may hide nearer ones\n",
                 algorithm, c.value);
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

// Which options were given on the command line (an empty value differs from none).
struct Given {
  bool output_file = false, raw = false, stats = false, sheet = false, explain_dir = false;
};

int runRender(const Args& a, const Given& given) {
  const std::vector<std::string> kinds = splitList(a.outputs);
  if (kinds.empty()) throw hsr::Error("--output needs at least one of color,depth,ids,overdraw");
  for (const std::string& k : kinds)
    if (k != "color" && k != "depth" && k != "ids" && k != "overdraw")
      throw hsr::Error(fmt::format("unknown output '{}' (color, depth, ids, overdraw)", k));
  // Every output is named and checked before the scene is loaded
  if (given.output_file && a.output_file.empty())
    throw hsr::Error("-o \"\": an empty path names no file");
  const fs::path base = a.output_file.empty() ? fs::path("out") / (sceneLabel(a.scene) + ".png")
                                              : fs::path(a.output_file);
  std::vector<std::pair<std::string, fs::path>> pngs;
  for (const std::string& k : kinds) {
    fs::path p = base;
    if (kinds.size() > 1) p.replace_filename(base.stem().string() + "-" + k + ".png");
    pngs.emplace_back(k, p);
  }
  OutputPlan plan(a.scene);
  for (const auto& [kind, p] : pngs) plan.file("-o", p.string());
  if (given.raw) plan.directory("--raw", a.raw_dir, {"depth.npy", "ids.npy", "overdraw.npy"});
  if (given.stats) plan.file("--stats", a.stats_file);

  const hsr::Scene scene = hsr::loadScene(a.scene, hsr::cli::importLimits(a));
  const hsr::Camera cam = makeCamera(a, scene);
  for (const auto& [kind, p] : pngs) hsr::checkPngSize(p, cam.width, cam.height, 3);
  warnIfEyeInside(scene, cam);
  warnIfDepthUnresolvable(cam);
  const hsr::RenderOptions opt = makeOptions(a);
  const hsr::Frame frame = hsr::render(scene, cam, opt);
  warnIfUnresolved(frame, opt.algorithm);

  std::vector<std::string> written;
  for (const auto& [kind, p] : pngs) {
    hsr::writePng(p, frame.width, frame.height, 3, hsr::picture(frame, kind).data());
    written.push_back(p.string());
  }
  if (given.raw) {
    hsr::writeRawFrame(a.raw_dir, frame, a.scene, opt.algorithm);
    written.push_back((fs::path(a.raw_dir) / "{depth,ids,overdraw}.npy").string());
  }
  if (given.stats) {
    hsr::writeFileAtomically(a.stats_file, {hsr::statsJson(frame, a.scene, opt.algorithm)});
    written.push_back(a.stats_file);
  }
  if (!a.quiet) printSummary(frame, a.scene, opt.algorithm, written);
  return 0;
}

int runCompare(const Args& a, const Given& given) {
  OutputPlan plan(a.scene);
  if (given.sheet) plan.file("--sheet", a.sheet_file);
  const hsr::Scene scene = hsr::loadScene(a.scene, hsr::cli::importLimits(a));
  const hsr::Camera cam = makeCamera(a, scene);
  warnIfDepthUnresolvable(cam);
  const hsr::RenderOptions opt = makeOptions(a);
  if (given.sheet) {
    const hsr::SheetSize size = hsr::comparisonSheetSize(
        static_cast<int>(hsr::algorithms().size()), cam.width, cam.height);
    hsr::checkPngSize(a.sheet_file, size.width, size.height, 3);
  }
  const std::vector<hsr::ComparisonRow> rows = hsr::compareAlgorithms(scene, cam, opt);
  fmt::print("hsr compare {}  {}x{}  ({} polygons)\n", a.scene, cam.width, cam.height,
             scene.polygonCount());
  fmt::print("  {:<17} {:>10} {:>12} {:>10} {:>8} {:>12} {:>10}\n", "algorithm", "time ms",
             "memory MiB", "overdraw", "max", "ids = zbuf", "differ px");
  for (const hsr::ComparisonRow& r : rows)
    if (!r.not_run.empty())
      fmt::print("  {:<17} not run: {}\n", r.algorithm, r.not_run);
    else
      fmt::print("  {:<17} {:>10.2f} {:>12.1f} {:>10.2f} {:>8} {:>11.4f}% {:>10}\n", r.algorithm,
               r.ms, r.state_bytes / 1048576.0, r.mean_overdraw, r.max_overdraw,
               100.0 * r.id_agreement, r.differing_pixels);
  if (given.sheet) {
    int w = 0, h = 0;
    const std::vector<std::uint8_t> sheet = hsr::comparisonSheet(rows, &w, &h);
    hsr::writePng(a.sheet_file, w, h, 3, sheet.data());
    fmt::print("  wrote {}\n", a.sheet_file);
  }
  return 0;
}

int runExplain(const Args& a, const std::string& dir_arg, const Given& given) {
  if (given.explain_dir && dir_arg.empty())
    throw hsr::Error("-o \"\": an empty path names no directory");
  const fs::path dir =
      dir_arg.empty() ? fs::path("out") / ("explain-" + a.algorithm + "-" + sceneLabel(a.scene))
                      : fs::path(dir_arg);
  OutputPlan plan(a.scene);
  plan.directory("-o", dir.string());
  const hsr::Scene scene = hsr::loadScene(a.scene, hsr::cli::importLimits(a));
  const hsr::Camera cam = makeCamera(a, scene);
  warnIfDepthUnresolvable(cam);
  const hsr::RenderOptions opt = makeOptions(a);
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

extern "C" void onTerminatingSignal(int sig) {
  hsr::removeTemporaryOutputs();
  ::raise(sig);  // SA_RESETHAND: the default action now, so the exit status names the signal
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
    printError(std::string(e.what()) + " (see hsr --help)");
    return 2;
  }
  Given given;
  given.output_file = render->count("-o") > 0;
  given.raw = render->count("--raw") > 0;
  given.stats = render->count("--stats") > 0;
  given.sheet = compare->count("--sheet") > 0;
  given.explain_dir = explain->count("-o") > 0;

  // SIGINT, SIGTERM, SIGHUP: no temporary file is left behind, then the default action
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction action {};
    action.sa_handler = onTerminatingSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND;
    ::sigaction(sig, &action, nullptr);
  }

  int status = 0;
  try {
    if (*scenes)
      status = runScenes();
    else if (*compare)
      status = runCompare(a, given);
    else if (*explain)
      status = runExplain(a, explain_dir, given);
    else
      status = runRender(a, given);  // `render`, or no verb at all: the demo scene
  } catch (const hsr::Error& e) {
    printError(e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    printError("out of memory");
    return 1;
  } catch (const fs::filesystem_error& e) {
    printError(e.what());
    return 2;
  } catch (const std::system_error& e) {
    // fmt::print's failed write to stdout, among others: the system's reason
    printError(e.what());
    return 2;
  } catch (const std::exception& e) {
    printError(std::string("internal error: ") + e.what());
    return 1;
  }
  // What was printed must have reached stdout (a full disk, a closed pipe)
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    printError(fmt::format("cannot write to standard output: {}", std::strerror(errno)));
    return 2;
  }
  return status;
}
