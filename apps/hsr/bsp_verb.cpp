// `hsr bsp`: build a scene's BSP tree once and save it, render the saved tree from any
// viewpoint (or a ring of them), print its statistics and its tree.

#include "bsp_verb.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include <fmt/core.h>
#include <glm/geometric.hpp>

#include "common.hpp"
#include "hsr/bsp.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/output.hpp"

namespace hsr::cli {

namespace {

void printStats(const hsr::Bsp& bsp) {
  const hsr::BspStats& s = bsp.stats();
  fmt::print("  splitter choice      {} (seed {}, {} candidates)\n", bsp.options().splitter,
             bsp.options().seed, bsp.options().candidates);
  fmt::print("  scene polygons       {:>12}   with a plane: {}\n", bsp.scene().polygonCount(),
             s.input_polygons);
  fmt::print("  polygons in the tree {:>12}   pieces included\n", s.polygons);
  fmt::print("  splits               {:>12}   {:.3f} per polygon\n", s.splits,
             s.input_polygons ? double(s.splits) / double(s.input_polygons) : 0.0);
  fmt::print("  nodes                {:>12}\n", s.nodes);
  fmt::print("  depth                {:>12}   mean depth of a polygon {:.1f}\n", s.depth,
             s.mean_depth);
  fmt::print("  balance              {:>12.3f}   mean min/max of the two subtrees (1 = even)\n",
             s.balance);
  fmt::print("  epsilon              {:>12.3g}   a vertex this near a plane is on it\n",
             bsp.epsilon());
  fmt::print("  memory               {:>12.1f}   MiB ({:.0f} bytes per polygon in the tree)\n",
             double(s.bytes) / 1048576.0, s.polygons ? double(s.bytes) / double(s.polygons) : 0.0);
  fmt::print("  build time           {:>12.1f}   ms\n", s.build_ms);
}

int runBuild(BspVerb& v) {
  const Args& a = v.build_args;
  OutputPlan plan(a.scene);
  plan.file("-o", v.output);
  const hsr::Scene scene = hsr::loadScene(a.scene, importLimits(a));
  // Progress on a terminal, a line redrawn at most five times a second.
  const bool terminal = ::isatty(STDERR_FILENO) && !v.quiet;
  auto last = std::chrono::steady_clock::now();
  bool drew = false;
  auto progress = [&](std::uint64_t done, std::uint64_t total) {
    if (!terminal) return;
    const auto now = std::chrono::steady_clock::now();
    if (done < total && now - last < std::chrono::milliseconds(200)) return;
    last = now;
    drew = true;
    fmt::print(stderr, "\rhsr bsp build: {} of {} polygons placed ({:.0f}%)   ", done, total,
               total ? 100.0 * double(done) / double(total) : 100.0);
    std::fflush(stderr);
  };
  const hsr::BspOptions options = makeOptions(a).bsp;
  const hsr::Bsp bsp = hsr::buildBsp(scene, options, progress);
  if (drew) fmt::print(stderr, "\n");
  hsr::saveBsp(bsp, v.output);
  if (!v.quiet) {
    fmt::print("hsr bsp build {}\n", a.scene);
    printStats(bsp);
    fmt::print("  wrote {}\n", v.output);
  }
  return 0;
}

int runRender(BspVerb& v) {
  const Args& a = v.render_args;
  for (const char* option : {"--bsp-splitter", "--bsp-seed", "--bsp-candidates"})
    if (v.render->count(option) > 0)
      throw hsr::Error(
          fmt::format("{} applies when a tree is built (hsr bsp build); {} holds a built one",
                      option, a.scene));
  if (v.render->count("--algorithm") > 0 && a.text("algorithm") != "bsp")
    throw hsr::Error("hsr bsp render draws with the tree (--algorithm bsp); use hsr render for " +
                     a.text("algorithm"));
  OutputPlan plan(a.scene);
  const bool orbit = v.orbit > 0;
  if (v.render->count("--orbit") > 0 && v.orbit < 1) throw hsr::Error("--orbit must be at least 1");
  if (v.orbit > 10000) throw hsr::Error("--orbit is limited to 10000 views");
  const std::string out = v.output.empty() ? (orbit ? "out/bsp-orbit" : "out/bsp.png") : v.output;
  if (orbit)
    plan.directory("-o", out);
  else
    plan.file("-o", out);
  if (v.render->count("--raw") > 0) {
    if (orbit) throw hsr::Error("--raw writes one frame; with --orbit the views are pictures");
    plan.directory("--raw", v.raw_dir, {"depth.npy", "ids.npy", "overdraw.npy"});
  }
  if (v.render->count("--stats") > 0) plan.file("--stats", v.stats_file);

  const hsr::Bsp bsp = hsr::loadBsp(a.scene);
  const hsr::Camera camera = makeCamera(a, bsp.scene());
  warnIfDepthUnresolvable(camera);
  const hsr::RenderOptions options = makeOptions(a);
  if (!orbit) {
    hsr::checkPngSize(out, camera.width, camera.height, 3);
    warnIfEyeInside(bsp.scene(), camera);
    const hsr::Frame frame = hsr::render(bsp, camera, options);
    std::vector<std::string> written;
    hsr::writePng(out, frame.width, frame.height, 3, hsr::picture(frame, "color").data());
    written.push_back(out);
    if (v.render->count("--raw") > 0) {
      hsr::writeRawFrame(v.raw_dir, frame, a.scene, "bsp");
      written.push_back(v.raw_dir + "/{depth,ids,overdraw}.npy");
    }
    if (v.render->count("--stats") > 0) {
      hsr::writeFileAtomically(v.stats_file, {hsr::statsJson(frame, a.scene, "bsp")});
      written.push_back(v.stats_file);
    }
    if (!v.quiet) printSummary(frame, a.scene, "bsp (from a built tree)", written);
    return 0;
  }
  // N views on a ring around the target, about the up axis, at the camera's distance.
  hsr::OutputDirectory dir(out);
  double total_ms = 0;
  for (int k = 0; k < v.orbit; ++k) {
    const hsr::Frame frame = hsr::render(bsp, hsr::orbitView(camera, k, v.orbit), options);
    total_ms += frame.stats.totalMs();
    dir.write(fmt::format("view-{:04}.png", k),
              {hsr::encodePng(frame.width, frame.height, 3, hsr::picture(frame, "color").data())});
    if (::isatty(STDERR_FILENO) && !v.quiet) {
      fmt::print(stderr, "\rhsr bsp render: view {} of {}   ", k + 1, v.orbit);
      std::fflush(stderr);
    }
  }
  if (::isatty(STDERR_FILENO) && !v.quiet) fmt::print(stderr, "\n");
  dir.commit(fmt::format("{{\"views\": {}}}", v.orbit));
  if (!v.quiet)
    fmt::print("hsr bsp render {}: {} views {}x{} from one tree, {:.1f} ms per view\n  wrote {}\n",
               a.scene, v.orbit, camera.width, camera.height, total_ms / v.orbit, out);
  return 0;
}

int runInfo(BspVerb& v) {
  OutputPlan plan(v.file);
  if (v.info->count("--dot") > 0) plan.file("--dot", v.dot_file);
  const hsr::Bsp bsp = hsr::loadBsp(v.file);
  fmt::print("hsr bsp info {}\n", v.file);
  printStats(bsp);
  fmt::print("tree (front subtree first; counts are polygons below):\n{}",
             hsr::bspOutline(bsp, v.nodes));
  if (v.info->count("--dot") > 0) {
    hsr::writeFileAtomically(v.dot_file, {hsr::bspDot(bsp)});
    fmt::print("  wrote {}\n", v.dot_file);
  }
  return 0;
}

}  // namespace

void addBspVerb(CLI::App& app, BspVerb& v) {
  v.verb = app.add_subcommand("bsp", "build a scene's BSP tree once, render it from any viewpoint");
  v.verb->require_subcommand(1, 1);
  v.build = v.verb->add_subcommand(
      "build", "build SCENE's BSP tree and save it: hsr bsp build SCENE -o FILE");
  v.build->add_option("scene", v.build_args.scene, "mesh file or built-in scene")->required();
  v.build->add_option("-o", v.output, "the tree file to write")->required();
  addBspBuildOptions(v.build, v.build_args);
  v.build->add_flag("--allow-outside-refs", v.build_args.allow_outside_refs,
                    "let a model read files it references outside its own folder");
  v.build->add_flag("-q,--quiet", v.quiet, "no summary, no progress");

  v.render = v.verb->add_subcommand(
      "render",
      "render a saved tree with every camera flag of hsr render, or --orbit N views into -o DIR");
  addViewOptions(v.render, v.render_args);
  v.render->get_option("scene")->description("a tree file written by hsr bsp build")->required();
  v.render->add_option("-o", v.output,
                       "output PNG (default out/bsp.png), or with --orbit a directory");
  v.render->add_option("--orbit", v.orbit, "render N views on a ring around the target");
  v.render->add_option("--raw", v.raw_dir, "write depth.npy, ids.npy, overdraw.npy into DIR");
  v.render->add_option("--stats", v.stats_file, "write counts and stage times as JSON");
  v.render->add_flag("-q,--quiet", v.quiet, "no summary");

  v.info = v.verb->add_subcommand("info", "print a saved tree's statistics and its tree");
  v.info->add_option("file", v.file, "a tree file written by hsr bsp build")->required();
  v.info->add_option("--dot", v.dot_file, "write the whole tree as Graphviz dot");
  v.info->add_option("--nodes", v.nodes, "tree lines printed")->capture_default_str();
}

int runBsp(BspVerb& v) {
  if (*v.build) return runBuild(v);
  if (*v.render) return runRender(v);
  return runInfo(v);
}

}  // namespace hsr::cli
