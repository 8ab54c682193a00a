#pragma once
// `hsr doom build|map|view`: Doom levels through their 2D BSP (include/hsr/doom.hpp).

#include <string>

#include <CLI/CLI.hpp>

namespace hsr::cli {

struct DoomVerb {
  CLI::App* verb = nullptr;
  CLI::App *build = nullptr, *map = nullptr, *view = nullptr;
  std::string wad, map_name, output, svg, from = "player", size = "960x600", raw_dir,
                                          algorithm = "bsp2d";
  int split_cost = 0, max_depth = 64;
  bool check = false, shipped = false, quiet = false;
};

// Adds the verb and its sub-verbs to `app`.
void addDoomVerb(CLI::App& app, DoomVerb& v);

// Runs whichever sub-verb was parsed; throws hsr::Error on bad input.
int runDoom(DoomVerb& v);

}  // namespace hsr::cli
