// libFuzzer target: the scene-description and camera arguments, exactly as the `hsr` command
// parses them (CLI11 options from apps/hsr/args.hpp). The bytes are split at NUL or newline
// into argv; the scene is a built-in spec (demo, cyclic, penetrating, spheres:N, soup:N:SEED);
// then the camera and render state are built and the scene rendered. hsr::Error and CLI11's
// parse errors are the expected answers to bad arguments; anything else is a finding.
//
// The fuzzer's budget per input is small, so the harness renders at most 64x64 and builds
// built-in scenes of at most 4096 polygons; larger sizes and counts are still parsed and
// validated by the library (the CLI honours them, they are just slow, not wrong).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "args.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"

namespace {

// Built-in scenes the harness builds: at most this many triangles (the library's own count
// parser decides, so "soup:739K" is 739,000, not 739; found by fuzz_args, see
// FuzzFindings.ArgsSceneCountSuffixIsCountedByTheLibrary).
constexpr std::uint64_t kMaxFuzzTriangles = 4096;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> tokens(1, "");
  for (std::size_t i = 0; i < size && tokens.size() < 64; ++i) {
    const char c = static_cast<char>(data[i]);
    if (c == '\0' || c == '\n')
      tokens.emplace_back();
    else
      tokens.back() += c;
  }
  std::vector<const char*> argv{"render"};
  for (const std::string& t : tokens) argv.push_back(t.c_str());

  hsr::cli::Args a;
  CLI::App app{"fuzz"};
  hsr::cli::addViewOptions(&app, a);
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::ParseError&) {
    return 0;
  }
  try {
    // Built-in scenes only: a path would make the fuzzer read arbitrary files. A spec that
    // is refused (malformed, or over the harness's size) still has its camera and options
    // run, on the demo scene.
    hsr::Scene scene;
    try {
      scene = hsr::makeBuiltinScene(a.scene, kMaxFuzzTriangles);
    } catch (const hsr::Error&) {
      scene = hsr::makeBuiltinScene("demo");
    }
    // Files named by --camera and --pose are not read either (fuzz_camera reads their text)
    a.option_text.erase("camera");
    a.option_text.erase("pose");
    hsr::Camera camera = hsr::cli::makeCamera(a, scene);
    hsr::RenderOptions options = hsr::cli::makeOptions(a);
    options.threads = std::min(options.threads, 2);
    camera.width = std::min(camera.width, 64);
    camera.height = std::min(camera.height, 64);
    hsr::render(scene, camera, options);
  } catch (const hsr::Error&) {
  }
  return 0;
}
