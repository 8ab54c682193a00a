// The registry: the one table of visibility algorithms that the CLI, tests and benchmarks
// loop over, and render(), the library's entry point.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include "hsr/error.hpp"
#include "hsr/render.hpp"
#include "visibility/algorithm.hpp"
#include "visibility/zbuffer.hpp"

namespace hsr {
namespace detail {

const std::vector<AlgorithmEntry>& algorithmTable() {
  static const std::vector<AlgorithmEntry> table = {
      {{"zbuffer", "image", "z-buffer: tiled scan conversion, incremental depth along spans"},
       &renderZBuffer},
  };
  return table;
}

Frame makeClearedFrame(int width, int height, const RenderOptions& options) {
  Frame f;
  f.width = width;
  f.height = height;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  f.color.resize(3 * n);
  auto q = [](float v) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f));
  };
  const std::uint8_t rgb[3] = {q(options.clear_color.r), q(options.clear_color.g),
                               q(options.clear_color.b)};
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) f.color[3 * i + c] = rgb[c];
  const float clear_depth =
      std::isfinite(options.clear_depth) ? std::clamp(options.clear_depth, 0.0f, 1.0f) : 1.0f;
  f.depth.assign(n, clear_depth);
  f.ids.assign(n, kNoPolygon);
  f.overdraw.assign(n, 0);
  return f;
}

}  // namespace detail

const std::vector<AlgorithmInfo>& algorithms() {
  static const std::vector<AlgorithmInfo> infos = [] {
    std::vector<AlgorithmInfo> v;
    for (const auto& e : detail::algorithmTable()) v.push_back(e.info);
    return v;
  }();
  return infos;
}

Frame render(const Scene& scene, const Camera& camera, const RenderOptions& options) {
  camera.validate();
  const detail::AlgorithmEntry* entry = nullptr;
  for (const auto& e : detail::algorithmTable())
    if (e.info.name == options.algorithm) entry = &e;
  if (!entry) {
    std::string names;
    for (const auto& e : detail::algorithmTable()) names += (names.empty() ? "" : ", ") + std::string(e.info.name);
    throw Error("unknown algorithm '" + options.algorithm + "' (known: " + names + ")");
  }
  if (options.threads < 0) throw Error("threads must be >= 0");
  const int threads = options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  Frame frame;
  arena.execute([&] {
    detail::PreparedScene prepared = detail::prepare(scene, camera, options);
    frame = entry->run(detail::AlgorithmInput{scene, camera, options, prepared});
    // The pipeline's counts and stage times come first, then the algorithm's.
    Stats s = prepared.stats;
    for (const StageTime& st : frame.stats.stages) s.addStage(st.name, st.ms);
    s.fragments_tested = frame.stats.fragments_tested;
    s.fragments_written = frame.stats.fragments_written;
    s.state_bytes = frame.stats.state_bytes;
    frame.stats = std::move(s);
  });
  return frame;
}

namespace {
std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return std::tolower(c); });
  return out;
}
}  // namespace

CullMode parseCullMode(std::string_view s) {
  const std::string v = lower(s);
  if (v == "none") return CullMode::None;
  if (v == "back") return CullMode::Back;
  if (v == "front") return CullMode::Front;
  if (v == "both" || v == "front_and_back") return CullMode::FrontAndBack;
  throw Error("unknown cull mode '" + std::string(s) + "' (none, back, front, both)");
}

FrontFace parseFrontFace(std::string_view s) {
  const std::string v = lower(s);
  if (v == "ccw") return FrontFace::Ccw;
  if (v == "cw") return FrontFace::Cw;
  throw Error("unknown front face '" + std::string(s) + "' (ccw, cw)");
}

PolygonMode parsePolygonMode(std::string_view s) {
  const std::string v = lower(s);
  if (v == "fill") return PolygonMode::Fill;
  if (v == "line") return PolygonMode::Line;
  if (v == "point") return PolygonMode::Point;
  throw Error("unknown polygon mode '" + std::string(s) + "' (fill, line, point)");
}

DepthFunc parseDepthFunc(std::string_view s) {
  const std::string v = lower(s);
  if (v == "never") return DepthFunc::Never;
  if (v == "less") return DepthFunc::Less;
  if (v == "equal") return DepthFunc::Equal;
  if (v == "lequal") return DepthFunc::LEqual;
  if (v == "greater") return DepthFunc::Greater;
  if (v == "notequal") return DepthFunc::NotEqual;
  if (v == "gequal") return DepthFunc::GEqual;
  if (v == "always") return DepthFunc::Always;
  throw Error("unknown depth func '" + std::string(s) +
              "' (never, less, equal, lequal, greater, notequal, gequal, always)");
}

}  // namespace hsr
