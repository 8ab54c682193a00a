// The registry: the one table of visibility algorithms that the CLI, tests and benchmarks
// loop over, and render(), the library's entry point.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/info.h>
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

int workerThreads(int requested) {
  if (requested < 0) throw Error("threads must be >= 0 (got " + std::to_string(requested) + ")");
  const int available = tbb::info::default_concurrency();
  return requested == 0 ? available : std::min(requested, available);
}

void clearFrame(Frame& f, int width, int height, const RenderOptions& options) {
  f.width = width;
  f.height = height;
  f.stats = Stats{};
  const std::size_t n = static_cast<std::size_t>(width) * height;
  auto q = [](float v) {
    return static_cast<std::uint32_t>(std::lround(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f));
  };
  const std::uint32_t clear = q(options.clear_color.r) | (q(options.clear_color.g) << 8) |
                              (q(options.clear_color.b) << 16) | 0xFF000000u;
  const float clear_depth =
      std::isfinite(options.clear_depth) ? std::clamp(options.clear_depth, 0.0f, 1.0f) : 1.0f;
  f.color.resize(n);
  f.depth.resize(n);
  f.ids.resize(n);
  f.overdraw.resize(n);
  // Cleared in parallel bands of rows: first touch spreads the pages over the workers.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16), [&](const auto& r) {
    std::fill(f.color.begin() + r.begin(), f.color.begin() + r.end(), clear);
    std::fill(f.depth.begin() + r.begin(), f.depth.begin() + r.end(), clear_depth);
    std::fill(f.ids.begin() + r.begin(), f.ids.begin() + r.end(), kNoPolygon);
    std::fill(f.overdraw.begin() + r.begin(), f.overdraw.begin() + r.end(), 0u);
  });
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
  Frame frame;
  render(scene, camera, options, frame);
  return frame;
}

void render(const Scene& scene, const Camera& camera, const RenderOptions& options, Frame& frame) {
  camera.validate();
  const detail::AlgorithmEntry* entry = nullptr;
  for (const auto& e : detail::algorithmTable())
    if (e.info.name == options.algorithm) entry = &e;
  if (!entry) {
    std::string names;
    for (const auto& e : detail::algorithmTable()) names += (names.empty() ? "" : ", ") + std::string(e.info.name);
    throw Error("unknown algorithm '" + options.algorithm + "' (known: " + names + ")");
  }
  tbb::task_arena arena(detail::workerThreads(options.threads));
  if (!frame.scratch.ptr) frame.scratch.ptr = std::make_shared<detail::RenderCache>();
  auto& cache = *static_cast<detail::RenderCache*>(frame.scratch.ptr.get());
  // Scratch made by another algorithm is dropped (each algorithm owns its scratch type).
  if (cache.owner != entry) cache.algorithm.reset();
  cache.owner = entry;
  arena.execute([&] {
    detail::PreparedScene& prepared = cache.prepared;
    detail::prepare(scene, camera, options, prepared);
    entry->run(detail::AlgorithmInput{scene, camera, options, prepared, &cache.algorithm}, frame);
    // The pipeline's counts and stage times come first, then the algorithm's.
    Stats s = prepared.stats;
    for (const StageTime& st : frame.stats.stages) s.addStage(st.name, st.ms);
    s.fragments_tested = frame.stats.fragments_tested;
    s.fragments_written = frame.stats.fragments_written;
    s.state_bytes = frame.stats.state_bytes;
    frame.stats = std::move(s);
  });
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
