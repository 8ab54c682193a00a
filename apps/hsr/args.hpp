#pragma once
// The command line's view arguments (scene, size, camera, render state): the CLI11 options and
// their conversion into a Camera and RenderOptions. Shared by the `hsr` command and the
// fuzz_args fuzz target, so that what is fuzzed is exactly what users type.

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include "hsr/camera.hpp"
#include "hsr/frontend.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace hsr::cli {

// The parsed command line. The view and render options are the library's table
// (hsr/frontend.hpp), kept as typed and read by makeCamera / makeOptions through one
// hsr::OptionRequest, so that the command line checks them as Python and the web page do.
struct Args {
  std::string scene = "demo";
  // By the table's names ("clear_depth"): the text given; absent or empty: not given
  std::map<std::string, std::string, std::less<>> option_text;
  std::string outputs = "color";
  std::string output_file;
  std::string raw_dir, stats_file, sheet_file;
  std::string depth = "window";  // what --raw's depth.npy holds: window, linear, distance
  std::string normals;           // --raw's normals.npy: world or eye; empty: none
  int views = 1;                 // hsr compare --views
  std::string views_file;        // hsr render --views FILE.json
  int orbit = 0;                 // hsr render --orbit N
  bool quiet = false;
  bool allow_outside_refs = false;

  bool given(std::string_view name) const;
  // As given, else the table's default ("zbuffer" for the algorithm)
  std::string text(std::string_view name) const;
};

// "WxH" -> width and height, each within Camera's limits; else hsr::Error naming --size.
void parseImageSize(const std::string& s, int* w, int* h);

// Adds SCENE and the view options (--size, --eye, ..., --threads) to a CLI11 (sub)command.
void addViewOptions(CLI::App* app, Args& a);

// The table's options the arguments give, checked (files named by --camera and --pose read and
// parsed); throws hsr::Error with one line.
hsr::OptionRequest requestOf(const Args& a);

// The camera the arguments describe for SCENE (fitted to it where not given); throws
// hsr::Error with one line for malformed or inconsistent values.
hsr::Camera makeCamera(const Args& a, const hsr::Scene& scene);

// A small text file the user named (a camera, a pose, a list of views), whole; Error when it
// cannot be read or passes `limit` bytes.
std::string readUserFile(const std::string& path, const char* option, std::uintmax_t limit);

// What a model file may read and spend (the import's limits).
hsr::ImportLimits importLimits(const Args& a);

// Adds --bsp-splitter, --bsp-seed and --bsp-candidates (how a BSP tree is built).
void addBspBuildOptions(CLI::App* app, Args& a);

// The render state the arguments describe; throws hsr::Error on unknown names.
hsr::RenderOptions makeOptions(const Args& a);

}  // namespace hsr::cli
