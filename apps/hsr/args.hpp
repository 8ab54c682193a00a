#pragma once
// The command line's view arguments (scene, size, camera, render state): the CLI11 options and
// their conversion into a Camera and RenderOptions. Shared by the `hsr` command and the
// fuzz_args fuzz target, so that what is fuzzed is exactly what users type.

#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

#include "hsr/camera.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace hsr::cli {

// The parsed command line (strings are converted by makeCamera / makeOptions).
struct Args {
  std::string scene = "demo";
  std::string size;  // empty: 800x600, or the --camera file's size
  std::string eye, target, up;
  std::string fov;  // empty: 45, or the scene file's camera
  bool ortho = false;
  std::string near, far;           // empty: fitted to the scene
  std::string camera_file;         // --camera FILE.json: the whole view, as --stats writes it
  std::string camera_index = "0";  // the scene file's camera: N, or auto (none: auto-framed)
  std::string intrinsics;          // fx,fy,cx,cy (OpenCV convention, pixels)
  std::string pose_file;           // camera to world, 4x4
  std::string pose_convention = "opencv";
  std::string clear_depth;  // empty: 1.0, OpenGL's glClearDepth default
  float point_size = 1.0f;  // --polygon-mode point: glPointSize
  std::string cull = "none", front_face = "ccw", polygon_mode = "fill", depth_func = "less";
  std::string facing = "window";
  bool no_depth_test = false, no_depth_mask = false, outline = false, flat = false;
  std::string algorithm = "zbuffer";
  std::string outputs = "color";
  std::string output_file;
  std::string raw_dir, stats_file, sheet_file;
  std::string depth = "window";  // what --raw's depth.npy holds: window, linear, distance
  std::string normals;           // --raw's normals.npy: world or eye; empty: none
  int threads = 0;
  int samples = 0;  // 0: the algorithm's default
  double fragment_memory_mib = 2048;
  int views = 1;           // hsr compare --views
  std::string views_file;  // hsr render --views FILE.json
  int orbit = 0;           // hsr render --orbit N
  std::string bsp_splitter = "balanced";
  std::uint64_t bsp_seed = 1;
  int bsp_candidates = 8;
  bool quiet = false;
  bool allow_outside_refs = false;
};

// "WxH" -> width and height, each within Camera's limits; else hsr::Error naming --size.
void parseImageSize(const std::string& s, int* w, int* h);

// Adds SCENE and the view options (--size, --eye, ..., --threads) to a CLI11 (sub)command.
void addViewOptions(CLI::App* app, Args& a);

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
