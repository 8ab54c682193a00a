// libFuzzer target: the scene-description and camera arguments, exactly as the `hsr` command
// parses them (CLI11 options from apps/hsr/args.hpp). The bytes are split at NUL or newline
// into argv; the scene is a built-in spec (demo, cyclic, penetrating, spheres:N, soup:N:SEED);
// then the camera and render state are built and the scene rendered. hsr::Error and CLI11's
// parse errors are the expected answers to bad arguments; anything else is a finding.
//
// The fuzzer's budget per input is small, so the harness renders at most 64x64 and builds
// built-in scenes of at most 4096 polygons; larger sizes and counts are still parsed and
// validated (the CLI honours them, they are just slow, not wrong).

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

// The largest decimal number in a built-in spec ("soup:100000:7" -> 100000), saturating.
unsigned long long largestNumber(const std::string& s) {
  unsigned long long best = 0, cur = 0;
  for (char c : s) {
    if (c >= '0' && c <= '9') {
      cur = cur > 1'000'000'000'000ull ? cur : cur * 10 + static_cast<unsigned>(c - '0');
      best = std::max(best, cur);
    } else {
      cur = 0;
    }
  }
  return best;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> tokens(1, "");
  for (std::size_t i = 0; i < size && tokens.size() < 64; ++i) {
    const char c = static_cast<char>(data[i]);
    if (c == '\0' || c == '\n') tokens.emplace_back();
    else tokens.back() += c;
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
    // Built-in scenes only: a path would make the fuzzer read arbitrary files
    const bool small = largestNumber(a.scene) <= 4096;
    const hsr::Scene scene = hsr::makeBuiltinScene(small ? a.scene : "demo");
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
