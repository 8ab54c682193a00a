// hsr: the command line. The only code that parses argv, prints, and picks exit codes:
// 0 success, 2 bad input or usage (one line on stderr), 1 internal error.

#include <algorithm>
#include <cctype>
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

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <glm/vector_relational.hpp>
#include <fmt/core.h>

#include "hsr/compare.hpp"
#include "hsr/error.hpp"
#include "hsr/explain.hpp"
#include "hsr/hsr.hpp"
#include "hsr/io.hpp"
#include "hsr/output.hpp"
#include "hsr/render.hpp"
#include "args.hpp"
#include "bsp_verb.hpp"
#include "svg_verb.hpp"
#include "doom_verb.hpp"
#include "hsr/doom.hpp"
#include "common.hpp"

namespace fs = std::filesystem;

namespace {

using hsr::cli::addViewOptions;
using hsr::cli::Args;
using hsr::cli::makeCamera;
using hsr::cli::makeOptions;
using hsr::cli::OutputPlan;
using hsr::cli::printError;
using hsr::cli::printSummary;
using hsr::cli::sceneLabel;
using hsr::cli::splitList;
using hsr::cli::warnIfDepthUnresolvable;
using hsr::cli::warnIfEyeInside;
using hsr::cli::warnIfUnresolved;

// Which options were given on the command line (an empty value differs from none).
struct Given {
  bool output_file = false, raw = false, stats = false, sheet = false, explain_dir = false;
  bool depth = false, views_file = false, orbit = false;
};

// The views of one run: one camera from the arguments, N on an orbit around it, or a list read
// from --views (read before the scene, so that every output can be named first).
struct ViewPlan {
  hsr::ViewList listed;  // from --views (near and far left out are fitted once the scene is read)
  int count = 1;
  bool many = false;  // numbered outputs
};

ViewPlan planViews(const Args& a, const Given& given) {
  ViewPlan v;
  if (given.views_file && given.orbit)
    throw hsr::Error("--views and --orbit both give the views: give one");
  if (given.views_file) {
    for (const char* name :
         {"eye", "target", "up", "fov", "ortho", "camera", "intrinsics", "pose", "near", "far"})
      if (a.given(name))
        throw hsr::Error(fmt::format("{} and --views both set the view: the file gives each view",
                                     hsr::spelled(name, hsr::FrontEnd::kCli)));
    hsr::ViewDefaults defaults;  // --size: the size of every view that names none
    if (a.given("size"))
      hsr::cli::parseImageSize(a.text("size"), &defaults.width, &defaults.height);
    // names itself
    const std::string text = hsr::cli::readUserFile(a.views_file, "--views", 256u << 20);
    try {
      v.listed = hsr::viewsFromJson(text, defaults);
    } catch (const hsr::Error& e) {
      throw hsr::Error(fmt::format("--views {}: {}", a.views_file, e.what()));
    }
    v.count = static_cast<int>(v.listed.cameras.size());
    v.many = true;
  } else if (given.orbit) {
    if (a.orbit < 1 || a.orbit > 100000)
      throw hsr::Error(fmt::format("--orbit must be 1 to 100000 views (got {})", a.orbit));
    v.count = a.orbit;
    v.many = true;
  }
  return v;
}

int runRender(const Args& a, const Given& given) {
  std::vector<std::string> kinds = splitList(a.outputs);
  if (kinds.empty())
    throw hsr::Error("--output needs at least one of color,depth,ids,overdraw, or none");
  // none: no picture (the raw buffers or the stats alone, or a timing)
  const bool none = std::find(kinds.begin(), kinds.end(), "none") != kinds.end();
  if (none && kinds.size() > 1) throw hsr::Error("--output none stands alone");
  if (none && given.output_file)
    throw hsr::Error("-o names a picture, and --output none writes none");
  if (none) kinds.clear();
  for (const std::string& k : kinds)
    if (k != "color" && k != "depth" && k != "ids" && k != "overdraw")
      throw hsr::Error(
          fmt::format("unknown output '{}' (color, depth, ids, overdraw, or none)", k));
  const hsr::DepthKind depth = hsr::depthKindNamed(a.depth);
  if (given.depth && !given.raw)
    throw hsr::Error("--depth says what --raw DIR/depth.npy holds: give --raw");
  const hsr::NormalSpace normals =
      a.normals.empty() ? hsr::NormalSpace::kNone : hsr::normalSpaceNamed(a.normals);
  if (!a.normals.empty() && !given.raw)
    throw hsr::Error("--normals adds DIR/normals.npy to --raw: give --raw");
  ViewPlan views = planViews(a, given);

  // Every output is named and checked before the scene is loaded: FILE.png, or FILE-KIND.png
  // for several pictures (and a single one other than colour when no name is given), with
  // -NNNN before the kind for many views; --raw DIR, or DIR/NNNN/ for many views
  if (given.output_file && a.output_file.empty())
    throw hsr::Error("-o \"\": an empty path names no file");
  const fs::path base = a.output_file.empty() ? fs::path("out") / (sceneLabel(a.scene) + ".png")
                                              : fs::path(a.output_file);
  const bool stats_to_stdout = given.stats && a.stats_file == "-";
  const bool kind_suffix =
      kinds.size() > 1 || (kinds.size() == 1 && kinds[0] != "color" && !given.output_file);
  auto viewTag = [&](int k) { return views.many ? fmt::format("-{:04d}", k) : std::string(); };
  auto pngPath = [&](int k, const std::string& kind) {
    if (!views.many && !kind_suffix) return base;  // exactly as named (/dev/full included)
    fs::path p = base;
    p.replace_filename(base.stem().string() + viewTag(k) + (kind_suffix ? "-" + kind : "") +
                       ".png");
    return p;
  };
  auto rawPath = [&](int k) {
    return views.many ? fs::path(a.raw_dir) / fmt::format("{:04d}", k) : fs::path(a.raw_dir);
  };
  OutputPlan plan(a.scene);
  for (int k = 0; k < views.count; ++k) {
    for (const std::string& kind : kinds) plan.file("-o", pngPath(k, kind).string());
    if (given.raw) plan.directory("--raw", rawPath(k).string(), hsr::kRawFiles);
  }
  if (given.stats && !stats_to_stdout) plan.file("--stats", a.stats_file);
  if (!kinds.empty()) hsr::cli::requireExtension("-o", a.output_file, ".png", "PNG pictures");

  const hsr::Scene scene = hsr::loadScene(a.scene, hsr::cli::importLimits(a));
  if (given.views_file) {
    try {
      views.listed.fitDepth(scene.bounds());
    } catch (const hsr::Error& e) {
      throw hsr::Error(fmt::format("--views {}: {}", a.views_file, e.what()));
    }
  }
  std::vector<hsr::Camera> cameras = std::move(views.listed.cameras);
  if (cameras.empty()) {
    const hsr::Camera cam = makeCamera(a, scene);
    for (int k = 0; k < views.count; ++k)
      cameras.push_back(views.count > 1 ? hsr::orbitView(cam, k, views.count) : cam);
  }
  for (const hsr::Camera& cam : cameras)
    for (const std::string& kind : kinds)
      hsr::checkPngSize(pngPath(0, kind), cam.width, cam.height, 3);
  warnIfEyeInside(scene, cameras.front());
  const bool depth_unresolved = hsr::cli::depthUnresolvable(cameras.front());
  const hsr::RenderOptions opt = makeOptions(a);

  // One frame for every view: what an algorithm builds once (a BSP tree, an octree, a BVH)
  // and its buffers are kept from view to view
  hsr::Frame frame;
  const bool progress = views.many && !a.quiet && ::isatty(STDERR_FILENO);
  std::vector<std::string> written, stats;
  double first_ms = 0, rest_ms = 0;
  for (int k = 0; k < views.count; ++k) {
    const hsr::Camera& cam = cameras[k];
    hsr::render(scene, cam, opt, frame);
    (k == 0 ? first_ms : rest_ms) += frame.stats.totalMs();
    if (k == 0) warnIfUnresolved(frame, opt.algorithm);
    if (k == 0 && depth_unresolved) {
      hsr::cli::refuseIfNothingResolved(frame, cam);  // before any file is written
      hsr::cli::warnIfDepthUnresolvable(cam);         // drawn, but depths may merge: said why
    }
    if (k == 0 && !depth_unresolved) hsr::cli::warnIfNothingDrawn(frame, opt);
    std::vector<std::pair<std::string, fs::path>> pictures;
    for (const std::string& kind : kinds) pictures.emplace_back(kind, pngPath(k, kind));
    hsr::writePictures(frame, pictures, [&](std::string_view kind, std::vector<std::uint8_t>& rgb) {
      hsr::cli::addLegend(frame, kind, rgb, cam, depth);
    });
    if (!views.many)
      for (const auto& [kind, p] : pictures) written.push_back(p.string());
    if (given.raw) {
      hsr::writeRawFrame(rawPath(k), frame, a.scene, opt.algorithm, scene, cam, depth, normals);
      if (!views.many) {
        std::string names = "depth,ids,objects,materials";
        if (normals != hsr::NormalSpace::kNone) names += ",normals";
        names += frame.coverage.empty() ? ",overdraw" : ",overdraw,coverage";
        written.push_back((fs::path(a.raw_dir) / ("{" + names + "}.npy")).string());
      }
    }
    if (given.stats) stats.push_back(hsr::statsJson(frame, a.scene, opt.algorithm, scene, cam));
    if (progress) fmt::print(stderr, "\r  view {}/{}", k + 1, views.count);
  }
  if (given.stats) {
    std::string json;
    if (!views.many) {
      json = stats.front();
    } else {
      json = "{\"views\": [\n";
      for (std::size_t k = 0; k < stats.size(); ++k) json += (k ? ",\n" : "") + stats[k];
      json += "]}\n";
    }
    if (stats_to_stdout) {
      std::fwrite(json.data(), 1, json.size(), stdout);
      return 0;  // stdout holds the JSON alone
    }
    hsr::writeFileAtomically(a.stats_file, {json});
    written.push_back(a.stats_file);
  }
  if (a.quiet) return 0;
  if (!views.many) {
    printSummary(frame, a.scene, opt.algorithm, written, &cameras.front());
    return 0;
  }
  if (progress) fmt::print(stderr, "\n");
  fmt::print("hsr render {} --algorithm {}: {} views, {} polygons\n", a.scene, opt.algorithm,
             views.count, scene.polygonCount());
  fmt::print("  first view {:.2f} ms (with what the algorithm builds once){}\n", first_ms,
             views.count > 1
                 ? fmt::format(", the other views {:.2f} ms each", rest_ms / (views.count - 1))
                 : "");
  if (!kinds.empty())
    fmt::print("  wrote {} ... {}\n", pngPath(0, kinds.front()).string(),
               pngPath(views.count - 1, kinds.back()).string());
  if (given.raw)
    fmt::print("  wrote {}/ ... {}/\n", rawPath(0).string(), rawPath(views.count - 1).string());
  for (const std::string& w : written) fmt::print("  wrote {}\n", w);
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
    const hsr::SheetSize size =
        hsr::comparisonSheetSize(static_cast<int>(hsr::algorithms().size()), cam.width, cam.height);
    hsr::checkPngSize(a.sheet_file, size.width, size.height, 3);
  }
  if (a.views < 1 || a.views > hsr::kMaxCompareViews)
    throw hsr::Error("--views must be 1 to " + std::to_string(hsr::kMaxCompareViews) + " (got " +
                     std::to_string(a.views) + ")");
  const std::vector<hsr::ComparisonRow> rows = hsr::compareAlgorithms(scene, cam, opt, a.views);
  const bool orbit = a.views > 1;
  fmt::print("hsr compare {}  {}x{}  ({} polygons{})\n", a.scene, cam.width, cam.height,
             scene.polygonCount(), orbit ? fmt::format(", {} views on an orbit", a.views) : "");
  fmt::print("  {:<17} {:>10}{} {:>12} {:>10} {:>8} {:>12} {:>10}\n", "algorithm", "time ms",
             orbit ? fmt::format(" {:>13}", "next views ms") : "", "memory MiB", "overdraw", "max",
             "ids = zbuf", "differ px");
  for (const hsr::ComparisonRow& r : rows)
    if (!r.not_run.empty())
      fmt::print("  {:<17} not run: {}\n", r.algorithm, r.not_run);
    else
      fmt::print("  {:<17} {:>10.2f}{} {:>12.1f} {:>10.2f} {:>8} {:>11.4f}% {:>10}\n", r.algorithm,
                 r.ms, orbit ? fmt::format(" {:>13.2f}", r.view_ms) : "", r.state_bytes / 1048576.0,
                 r.mean_overdraw, r.max_overdraw, 100.0 * r.id_agreement, r.differing_pixels);
  if (orbit)
    fmt::print(
        "  (time ms: the first view, with what an algorithm builds once; next views ms: the mean "
        "of\n"
        "   the other views, drawn into the same frame; ids compared on every view)\n");
  if (given.sheet) {
    int w = 0, h = 0;
    const std::vector<std::uint8_t> sheet = hsr::comparisonSheet(rows, &w, &h);
    hsr::writePng(a.sheet_file, w, h, 3, sheet.data());
    fmt::print("  wrote {}\n", a.sheet_file);
  }
  return 0;
}

// `hsr explain bsp2d WAD --map MAP`: Doom's walk of the map's tree from player 1's start.
int runExplainDoom(const Args& a, const std::string& map_name, const fs::path& dir) {
  namespace doom = hsr::doom;
  if (map_name.empty())
    throw hsr::Error("explain bsp2d draws a Doom map: give the WAD and --map MAP01");
  int width = 640, height = 400;
  if (a.given("size")) hsr::cli::parseImageSize(a.text("size"), &width, &height);
  const doom::Map map = doom::readMap(doom::readWad(a.scene), map_name);
  const doom::Nodes nodes = doom::buildNodes(map);
  const doom::Level level = doom::levelScene(map, nodes);
  const hsr::Camera camera = doom::viewCamera(map, nodes, doom::playerStart(map), width, height);
  const hsr::Explanation e = hsr::explainDoomView(map, nodes, level, camera, dir);
  if (!a.quiet) {
    fmt::print("hsr explain bsp2d {} {}  {}x{}: {} steps\n", a.scene, map.name, width, height,
               e.steps.size());
    for (const hsr::ExplainedStep& s : e.steps)
      fmt::print("  {:>2}. {:<19} {}\n", s.number, s.name, s.caption);
    fmt::print("  wrote {} pictures, {} and {}\n", e.steps.size(), e.sheet.string(),
               e.index.string());
  }
  return 0;
}

int runExplain(const Args& a, const std::string& dir_arg, const std::string& map_name,
               const Given& given) {
  if (given.explain_dir && dir_arg.empty())
    throw hsr::Error("-o \"\": an empty path names no directory");
  const fs::path dir =
      dir_arg.empty()
          ? fs::path("out") / ("explain-" + a.text("algorithm") + "-" + sceneLabel(a.scene))
          : fs::path(dir_arg);
  OutputPlan plan(a.scene);
  plan.directory("-o", dir.string());
  if (a.text("algorithm") == "bsp2d") return runExplainDoom(a, map_name, dir);
  if (!map_name.empty()) throw hsr::Error("--map names a Doom map, for explain bsp2d");
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
  for (const hsr::BuiltinScene& s : hsr::builtinScenes())
    fmt::print("  {:<16} {}\n", s.name, s.summary);
  fmt::print("algorithms:\n");
  for (const hsr::AlgorithmInfo& i : hsr::algorithms()) {
    fmt::print("  {:<18} {} precision{}: {}\n                     input: {}; can: {}\n", i.name,
               hsr::toString(i.precision), i.reference ? ", the reference" : "", i.summary,
               hsr::toString(i.input), hsr::capabilityList(i.capabilities));
    if (i.sibling.empty()) continue;
    const hsr::AlgorithmInfo* walked = hsr::explainedBy(i);
    if (i.textbook)
      fmt::print("                     the notes' loop of {}: the same frame, bit for bit\n",
                 i.sibling);
    else
      fmt::print("                     its textbook sibling: {}, the same frame bit for bit{}\n",
                 i.sibling, walked && walked->name == i.sibling ? "; `hsr explain` walks it" : "");
  }
  return 0;
}

extern "C" void onTerminatingSignal(int sig) {
  hsr::removeTemporaryOutputs();
  hsr::reportReplacedOutputs(STDERR_FILENO);  // which outputs are this run's, which an earlier's
  ::raise(sig);  // SA_RESETHAND: the default action now, so the exit status names the signal
}

}  // namespace

int main(int argc, char** argv) {
  // SIGINT, SIGTERM, SIGHUP: no temporary file is left behind, then the default action.
  // First of all, so that a signal at any moment of the run gets its one line.
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction action {};
    action.sa_handler = onTerminatingSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND;
    ::sigaction(sig, &action, nullptr);
  }

  CLI::App app{
      "hsr: hidden-surface removal with every classic algorithm.\n"
      "Examples:\n"
      "  hsr                                  render the demo scene to out/demo.png\n"
      "  hsr model.ply --raw out/raw          render a model (render is the default verb)\n"
      "  hsr render spheres:100000 --size 1920x1080 --cull back -o out/s.png\n"
      "  hsr render model.obj --output color,depth,ids,overdraw --raw out/raw\n"
      "  hsr render demo --polygon-mode line --eye 4,3,6 --target 0,0,0\n"
      "  hsr compare demo --sheet out/sheet.png\n"
      "  hsr compare spheres:100000 --views 12\n"
      "  hsr explain zbuffer-textbook demo -o out/explain\n"
      "  hsr explain bsp2d /usr/share/games/doom/freedoom2.wad --map MAP01 -o out/explain-doom\n"
      "  hsr bsp build spheres:100000 -o out/spheres.bsp\n"
      "  hsr bsp render out/spheres.bsp --orbit 12 -o out/orbit\n"
      "  hsr svg solids --hidden dashed --page A4-landscape -o out/solids.svg\n"
      "  hsr doom build /usr/share/games/doom/freedoom2.wad -o out/freedoom2.wad\n"
      "  hsr doom view /usr/share/games/doom/freedoom2.wad --map MAP01 -o out/map01.png\n"
      "  hsr scenes"};
  app.require_subcommand(0, 1);
  Args a;
  CLI::App* render = app.add_subcommand("render", "render SCENE with one algorithm");
  addViewOptions(render, a);
  render->add_option("--output", a.outputs, "pictures to write: color,depth,ids,overdraw, or none")
      ->capture_default_str();
  render->add_option("-o", a.output_file,
                     "output PNG (default out/SCENE.png; with several "
                     "outputs, FILE-KIND.png)");
  render->add_option(
      "--raw", a.raw_dir,
      "write depth.npy, ids.npy, objects.npy, overdraw.npy (and coverage.npy from abuffer) "
      "into DIR, with manifest.json");
  render
      ->add_option("--depth", a.depth,
                   "what --raw's depth.npy holds: window (window z, 1 = nothing), linear (depth "
                   "along the view axis) or distance (along the pixel's ray), in scene units, "
                   "inf = nothing")
      ->capture_default_str();
  render->add_option("--normals", a.normals,
                     "add --raw's normals.npy: the polygon shown's unit normal, facing the eye, in "
                     "world or eye space");
  render->add_option(
      "--stats", a.stats_file,
      "write counts, stage times and the camera as JSON (- : to stdout, instead of the summary)");
  render->add_option("--views", a.views_file,
                     "render every camera of a JSON list (as --stats writes them) from one import: "
                     "numbered outputs FILE-NNNN.png, DIR/NNNN/. A view needs only eye and target: "
                     "size from --size, up +y, fov 45 and near/far fitted unless it gives them");
  render->add_option(
      "--orbit", a.orbit,
      "render N views on a ring around the target from one import: numbered outputs");
  render->add_flag("-q,--quiet", a.quiet, "no summary");
  CLI::App* compare = app.add_subcommand("compare", "run every algorithm on SCENE and compare");
  addViewOptions(compare, a);
  compare->add_option("--sheet", a.sheet_file, "write the pictures side by side, labelled");
  compare->add_option(
      "--views", a.views,
      "also draw views 2..N of an orbit around the target into the same frame "
      "(what an algorithm keeps, such as the octree, is reused); ids compared on every view");
  CLI::App* explain = app.add_subcommand(
      "explain", "explain ALGORITHM on SCENE step by step: numbered pictures and a contact sheet");
  explain
      ->add_option("ALGORITHM", a.option_text["algorithm"],
                   "an algorithm that can explain itself, or bsp2d (a WAD and --map)")
      ->required();
  addViewOptions(explain, a);
  std::string explain_dir;
  explain->add_option("-o", explain_dir, "output directory (default out/explain-ALGORITHM-SCENE)");
  explain->add_flag("-q,--quiet", a.quiet, "no summary");
  std::string explain_map;
  explain->add_option(
      "--map", explain_map,
      "with ALGORITHM bsp2d and a WAD for SCENE: the Doom map whose tree is walked");
  CLI::App* scenes = app.add_subcommand("scenes", "list built-in scenes and algorithms");
  hsr::cli::BspVerb bsp;
  hsr::cli::addBspVerb(app, bsp);
  hsr::cli::SvgVerb svg;
  hsr::cli::addSvgVerb(app, svg);
  hsr::cli::DoomVerb doom;
  hsr::cli::addDoomVerb(app, doom);

  app.set_version_flag("--version", "hsr " + std::string(hsr::version()));
  hsr::cli::refuseFlagsAsValues(&app);
  hsr::cli::lowercaseNameValues(&app);
  // `hsr SCENE [options]` is `hsr render SCENE [options]`
  std::vector<const char*> args(argv, argv + argc);
  if (argc > 1) {
    const std::string_view first = argv[1];
    const std::vector<std::string_view> verbs = {"render", "compare", "explain", "scenes",
                                                 "bsp",    "svg",     "doom"};
    const bool verb = std::find(verbs.begin(), verbs.end(), first) != verbs.end();
    if (!verb) {
      const std::string hint = hsr::cli::verbMissHint(first, verbs);
      if (!hint.empty()) {
        printError(hint);
        return 2;
      }
    }
    if (!verb && first != "-h" && first != "--help" && first != "--version")
      args.insert(args.begin() + 1, "render");
  }
  try {
    app.parse(static_cast<int>(args.size()), args.data());
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string hint = hsr::cli::commaHint(static_cast<int>(args.size()), args.data());
    if (hint.empty())
      hint = hsr::cli::nearMissHint(&app, static_cast<int>(args.size()), args.data());
    const std::string what = hsr::cli::plainParseMessage(e.what());
    printError(hint.empty() ? what + " (see hsr --help)" : what + "; " + hint);
    return 2;
  }
  Given given;
  given.output_file = render->count("-o") > 0;
  given.raw = render->count("--raw") > 0;
  given.stats = render->count("--stats") > 0;
  given.depth = render->count("--depth") > 0;
  given.views_file = render->count("--views") > 0;
  given.orbit = render->count("--orbit") > 0;
  given.sheet = compare->count("--sheet") > 0;
  given.explain_dir = explain->count("-o") > 0;

  int status = 0;
  try {
    if (*scenes)
      status = runScenes();
    else if (*bsp.verb)
      status = hsr::cli::runBsp(bsp);
    else if (*svg.verb)
      status = hsr::cli::runSvg(svg);
    else if (*doom.verb)
      status = hsr::cli::runDoom(doom);
    else if (*compare)
      status = runCompare(a, given);
    else if (*explain)
      status = runExplain(a, explain_dir, explain_map, given);
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
    // fmt::print's failed write to stdout (a listing longer than stdio's buffer on a full
    // device), whose message names no file, among others: the system's reason
    if (std::ferror(stdout))
      printError(fmt::format("cannot write to standard output: {}", e.code().message()));
    else
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
