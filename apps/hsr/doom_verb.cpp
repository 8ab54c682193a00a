// `hsr doom`: build a WAD's node trees (and write them back), draw a map's partition from
// above, and see a level through its tree as Doom's renderer does, beside any algorithm of the
// registry drawing the same level as a 3D scene.

#include "doom_verb.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>

#include <fmt/core.h>

#include "args.hpp"
#include "common.hpp"
#include "hsr/doom.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/output.hpp"

namespace hsr::cli {

namespace {

namespace doom = hsr::doom;

std::vector<std::string> mapsToBuild(const doom::Wad& wad, const std::string& wanted) {
  if (!wanted.empty()) return {doom::readMap(wad, wanted).name};
  std::vector<std::string> maps = wad.maps();
  if (maps.empty()) throw hsr::Error("the WAD holds no map");
  return maps;
}

doom::Nodes nodesFor(const doom::Map& map, bool shipped, int split_cost) {
  if (shipped) {
    if (!map.shipped)
      throw hsr::Error(fmt::format("the WAD's own nodes cannot be used: {}", map.shipped_problem));
    return *map.shipped;
  }
  doom::BuildOptions options;
  if (split_cost > 0) options.split_cost = split_cost;
  return doom::buildNodes(map, options);
}

int runBuild(DoomVerb& v) {
  OutputPlan plan(v.wad);
  if (!v.output.empty()) plan.file("-o", v.output);
  const auto start = std::chrono::steady_clock::now();
  const doom::Wad wad = doom::readWad(v.wad);
  doom::BuildOptions options;
  if (v.split_cost != 0) options.split_cost = v.split_cost;
  std::map<std::string, doom::Nodes> built;
  doom::BuildStats total, shipped_total;
  std::uint64_t problems = 0, shipped_maps = 0;
  if (!v.quiet)
    fmt::print(
        "hsr doom build {} (split cost {})\n{:<8} {:>7} {:>7} {:>7} {:>6} {:>6} {:>5} {:>8}   "
        "{:>7} {:>5}{}\n",
        v.wad, options.split_cost, "map", "sides", "segs", "splits", "nodes", "ssecs", "depth",
        "ms", "shipped", "depth", v.check ? "   check" : "");
  for (const std::string& name : mapsToBuild(wad, v.map_name)) {
    const doom::Map map = doom::readMap(wad, name);
    doom::BuildStats s;
    doom::Nodes nodes = doom::buildNodes(map, options, &s);
    total.sides += s.sides, total.segs += s.segs, total.splits += s.splits, total.nodes += s.nodes;
    total.subsectors += s.subsectors, total.depth = std::max(total.depth, s.depth),
                                      total.build_ms += s.build_ms;
    std::string shipped = "      -      -";
    if (map.shipped) {
      const doom::BuildStats t = doom::nodeStats(map, *map.shipped);
      shipped = fmt::format("{:>7} {:>5}", t.splits, t.depth);
      shipped_total.splits += t.splits,
          shipped_total.depth = std::max(shipped_total.depth, t.depth);
      ++shipped_maps;
    }
    std::string check;
    if (v.check) {
      const auto found = doom::checkNodes(map, nodes);
      problems += found.size();
      check =
          found.empty() ? "   ok" : fmt::format("   {} problems: {}", found.size(), found.front());
    }
    if (!v.quiet) {
      fmt::print("{:<8} {:>7} {:>7} {:>7} {:>6} {:>6} {:>5} {:>8.1f}   {}{}\n", name, s.sides,
                 s.segs, s.splits, s.nodes, s.subsectors, s.depth, s.build_ms, shipped, check);
      std::fflush(stdout);
    }
    built.emplace(name, std::move(nodes));
  }
  if (!v.output.empty()) doom::writeWad(wad, built, v.output);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!v.quiet) {
    fmt::print(
        "{:<8} {:>7} {:>7} {:>7} {:>6} {:>6} {:>5} {:>8.1f}   {}\n", "total", total.sides,
        total.segs, total.splits, total.nodes, total.subsectors, total.depth, total.build_ms,
        shipped_maps ? fmt::format("{:>7} {:>5}", shipped_total.splits, shipped_total.depth) : "");
    fmt::print("  {} maps in {:.2f} s (reading, building{})\n", built.size(), seconds,
               v.output.empty() ? "" : ", writing");
    if (!v.output.empty()) fmt::print("  wrote {}\n", v.output);
    if (v.check)
      fmt::print("  check: {}\n",
                 problems ? fmt::format("{} problems", problems) : "every tree holds");
  }
  return problems ? 1 : 0;
}

int runMap(DoomVerb& v) {
  OutputPlan plan(v.wad);
  plan.file("--svg", v.svg);
  const doom::Map map = doom::readMap(doom::readWad(v.wad), v.map_name);
  const doom::Nodes nodes = nodesFor(map, v.shipped, v.split_cost);
  hsr::writeFileAtomically(v.svg, {doom::mapSvg(map, nodes, v.max_depth)});
  if (!v.quiet) {
    const doom::BuildStats s = doom::nodeStats(map, nodes);
    fmt::print("hsr doom map {} {}: {} nodes, {} subsectors, depth {}\n  wrote {}\n", v.wad,
               map.name, s.nodes, s.subsectors, s.depth, v.svg);
  }
  return 0;
}

doom::Viewpoint viewpoint(const doom::Map& map, const std::string& from) {
  if (from == "player") return doom::playerStart(map);
  doom::Viewpoint p;
  char extra = 0;
  if (std::sscanf(from.c_str(), "%lf,%lf,%lf%c", &p.x, &p.y, &p.angle_degrees, &extra) != 3 ||
      !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.angle_degrees))
    throw hsr::Error(fmt::format("--from must be player or X,Y,ANGLE (got '{}')", from));
  return p;
}

int runView(DoomVerb& v) {
  OutputPlan plan(v.wad);
  plan.file("-o", v.output);
  if (!v.raw_dir.empty()) plan.directory("--raw", v.raw_dir, hsr::kRawFiles);
  int width = 0, height = 0;
  parseImageSize(v.size, &width, &height);
  hsr::checkPngSize(v.output, width, height, 3);
  const doom::Map map = doom::readMap(doom::readWad(v.wad), v.map_name);
  const doom::Nodes nodes = nodesFor(map, v.shipped, v.split_cost);
  const doom::Level level = doom::levelScene(map, nodes);
  const doom::Viewpoint from = viewpoint(map, v.from);
  const hsr::Camera camera = doom::viewCamera(map, nodes, from, width, height);
  const auto start = std::chrono::steady_clock::now();
  hsr::Frame frame;
  if (v.algorithm == "bsp2d") {
    frame = doom::renderView(map, nodes, level, camera);
  } else {
    hsr::RenderOptions options;
    options.algorithm = v.algorithm;
    options.shade = false;  // the materials' flat colours, as the column renderer starts from
    frame = hsr::render(level.scene, camera, options);
  }
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  hsr::writePng(v.output, frame.width, frame.height, 3, hsr::picture(frame, "color").data());
  if (!v.raw_dir.empty())
    hsr::writeRawFrame(v.raw_dir, frame, v.wad + ":" + map.name, v.algorithm, level.scene, camera,
                       hsr::DepthKind::kWindow);
  if (!v.quiet) {
    fmt::print(
        "hsr doom view {} {} from ({:.0f}, {:.0f}) facing {:.0f} degrees: {}x{} by {} in {:.1f} "
        "ms\n",
        v.wad, map.name, camera.eye.x, camera.eye.y, from.angle_degrees, width, height, v.algorithm,
        ms);
    if (v.algorithm == "bsp2d") {
      hsr::RenderOptions options;
      const doom::Agreement a =
          doom::wallAgreement(level, frame, hsr::render(level.scene, camera, options));
      fmt::print(
          "  walls: {} of {} pixels the z-buffer shows as walls have its id ({:.3f}%); {} differ "
          "away "
          "from an edge\n",
          a.same, a.wall_pixels, 100.0 * a.fraction(), a.away_from_edges);
    }
    fmt::print("  wrote {}{}\n", v.output, v.raw_dir.empty() ? "" : ", " + v.raw_dir);
  }
  return 0;
}

// What `map` and `view` take alike: the WAD, one map, and whose tree.
void addOneMap(CLI::App* sub, DoomVerb& v) {
  sub->add_option("wad", v.wad, "a Doom-format WAD file")->required();
  sub->add_option("--map", v.map_name, "the map (MAP01, E1M1)")->required();
  sub->add_flag("--shipped", v.shipped, "the WAD's own nodes instead of building them");
  sub->add_option("--split-cost", v.split_cost, "as hsr doom build's");
  sub->add_flag("-q,--quiet", v.quiet, "no summary");
}

}  // namespace

void addDoomVerb(CLI::App& app, DoomVerb& v) {
  v.verb = app.add_subcommand(
      "doom", "Doom levels through their 2D BSP: build nodes, draw a map, see a level");
  v.verb->require_subcommand(1, 1);
  v.build = v.verb->add_subcommand(
      "build",
      "build the node trees of a WAD's maps, print their figures, and write them back with -o");
  v.build->add_option("wad", v.wad, "a Doom-format WAD file")->required();
  v.build->add_option("--map", v.map_name, "one map (MAP01, E1M1); default every map");
  v.build->add_option("-o", v.output,
                      "write the WAD with the new nodes (every other lump as it was)");
  v.build->add_option("--split-cost", v.split_cost,
                      "the cost of a split against one seg of imbalance (default 128)");
  v.build->add_flag("--check", v.check,
                    "check every tree (convex subsectors, segs covering each linedef side once)");
  v.build->add_flag("-q,--quiet", v.quiet, "no table");

  v.map = v.verb->add_subcommand("map", "draw a map's partition from above as SVG");
  addOneMap(v.map, v);
  v.map->add_option("--svg", v.svg, "the drawing to write")->required();
  v.map->add_option("--max-depth", v.max_depth, "partition lines drawn down to this depth")
      ->capture_default_str();

  v.view = v.verb->add_subcommand(
      "view", "see a level as its player does, through the tree (or any algorithm)");
  addOneMap(v.view, v);
  v.view->add_option("-o", v.output, "the picture (PNG)")->required();
  v.view
      ->add_option("--from", v.from,
                   "player (player 1's start) or X,Y,ANGLE in map units and degrees")
      ->capture_default_str();
  v.view->add_option("--size", v.size, "image size WxH")->capture_default_str();
  v.view->add_option("--raw", v.raw_dir, "write depth.npy, ids.npy, ... into DIR");
  v.view
      ->add_option("--algorithm", v.algorithm,
                   "bsp2d (Doom's front-to-back column renderer) or any algorithm of hsr scenes, "
                   "drawing the level as a 3D scene")
      ->capture_default_str();
}

int runDoom(DoomVerb& v) {
  if (v.split_cost < 0) throw hsr::Error("--split-cost must be at least 1");
  if (*v.build) return runBuild(v);
  if (*v.map) return runMap(v);
  return runView(v);
}

}  // namespace hsr::cli
