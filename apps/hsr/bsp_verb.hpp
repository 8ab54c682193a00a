#pragma once
// `hsr bsp build|render|info`: one BSP tree, built once, saved, rendered from any viewpoint.

#include <string>

#include <CLI/CLI.hpp>

#include "args.hpp"

namespace hsr::cli {

struct BspVerb {
  CLI::App* verb = nullptr;
  CLI::App *build = nullptr, *render = nullptr, *info = nullptr;
  Args build_args, render_args;
  std::string file, output, raw_dir, stats_file, dot_file;
  int orbit = 0;
  std::size_t nodes = 40;
  bool quiet = false;
};

// Adds the verb and its three sub-verbs to `app`.
void addBspVerb(CLI::App& app, BspVerb& v);

// Runs whichever sub-verb was parsed; throws hsr::Error on bad input.
int runBsp(BspVerb& v);

}  // namespace hsr::cli
