// render(): the one orchestrator. Validate, look the algorithm up, prepare what its entry
// asks for, clear, run, merge stats. The GL facade and `hsr explain` draw through it too.

#include "orchestrator.hpp"

#include <algorithm>
#include <memory>
#include <string>

#include "core/check.hpp"
#include "core/frame.hpp"
#include "core/parallel.hpp"
#include "hsr/bsp.hpp"
#include "hsr/error.hpp"
#include "core/stopwatch.hpp"
#include "raster/samples.hpp"
#include "visibility/algorithm.hpp"

namespace hsr {
namespace detail {
namespace {

// Memory kept in a Frame between renders: the pipeline's output and the algorithm's scratch.
struct RenderCache {
  PreparedScene prepared;
  std::shared_ptr<void> algorithm;
  const AlgorithmEntry* owner = nullptr;  // the entry that made `algorithm`
};

// What the options ask for that the algorithm cannot do: refused in one line, never ignored.
void checkSupported(const AlgorithmInfo& info, const Camera& camera, const RenderOptions& o) {
  if (std::string why = unsupported(info, camera, o); !why.empty()) throw Error(why);
}

}  // namespace

int workerThreads(int requested) {
  if (requested < 0) throw Error("threads must be >= 0 (got " + std::to_string(requested) + ")");
  const int available = tbb::info::default_concurrency();
  return requested == 0 ? available : std::min(requested, available);
}

void renderInto(const Scene& scene, const Camera& camera, const RenderOptions& options,
                Frame& frame, DrawMode mode, Trace* trace, const void* given) {
  camera.validate();
  const AlgorithmEntry& entry = findEntry(options.algorithm);
  checkSupported(entry.info, camera, options);
  if (mode == DrawMode::kOver) {
    if (!entry.info.has(kDrawOver))
      throw Error("algorithm '" + std::string(entry.info.name) + "' cannot draw over a frame");
    if (frame.width != camera.width || frame.height != camera.height)
      throw Error("frame size differs from the camera's");
  }
  const int threads = workerThreads(options.threads);
  if (!frame.scratch.ptr) frame.scratch.ptr = std::make_shared<RenderCache>();
  auto& cache = *static_cast<RenderCache*>(frame.scratch.ptr.get());
  // Scratch made by another algorithm is dropped (each algorithm owns its scratch type).
  if (cache.owner != &entry) cache.algorithm.reset();
  cache.owner = &entry;
  runWithThreads(threads, [&] {
    PreparedScene& prepared = cache.prepared;
    prepare(scene, camera, options,
            {.window_polygons = entry.info.input == InputKind::kWindowPolygons,
             .samples = entry.info.has(kAntialiasing)},
            prepared);
    Stats stats = prepared.stats;
    if (mode == DrawMode::kClear) {
      const detail::Stopwatch t0;
      clearFrame(frame, camera.width, camera.height, options);
      stats.addStage("clear", t0.ms());
    }
    HSR_CHECK_EQ(frame.ids.size(), static_cast<std::size_t>(camera.width) * camera.height);
    frame.stats = Stats{};
    entry.draw(AlgorithmInput{scene, camera, options, prepared, &cache.algorithm, trace, given},
               frame);
    // The pipeline's counts and stage times first, then the algorithm's.
    stats.merge(frame.stats);
    frame.stats = std::move(stats);
  });
}

}  // namespace detail

std::string unsupported(const AlgorithmInfo& info, const Camera& camera, const RenderOptions& o) {
  const std::string lacks = "algorithm '" + std::string(info.name) + "' does not support ";
  if (o.polygon_mode != PolygonMode::Fill && !info.has(kPolygonModes))
    return lacks + "polygon modes other than fill";
  if (!(o.point_size >= 1.0f && o.point_size <= 64.0f))
    return "the point size must be from 1 to 64 pixels (got " + std::to_string(o.point_size) + ")";
  if (o.outline && !info.has(kOutline)) return lacks + "--outline";
  if ((o.depth_func != DepthFunc::Less || !o.depth_test) && !info.has(kDepthFuncs))
    return lacks + "depth functions other than less";
  if (!o.depth_mask && !info.has(kDepthMask)) return lacks + "a disabled depth mask";
  if (o.samples != 0 && !info.has(kAntialiasing)) return lacks + "--samples (sub-pixel samples)";
  if (o.samples != 0 && !detail::validSampleCount(o.samples))
    return "--samples must be 1, 4, 8, 16, 32 or 64 (got " + std::to_string(o.samples) + ")";
  const std::uint64_t pixels = static_cast<std::uint64_t>(camera.width) * camera.height;
  if (info.max_pixels != 0 && pixels > info.max_pixels)
    return "algorithm '" + std::string(info.name) + "' is limited to " +
           std::to_string(info.max_pixels) + " pixels; " + std::to_string(camera.width) + "x" +
           std::to_string(camera.height) + " has " + std::to_string(pixels);
  return {};
}

Frame render(const Scene& scene, const Camera& camera, const RenderOptions& options) {
  Frame frame;
  render(scene, camera, options, frame);
  return frame;
}

void render(const Scene& scene, const Camera& camera, const RenderOptions& options, Frame& frame) {
  detail::renderInto(scene, camera, options, frame, detail::DrawMode::kClear);
}

Frame render(const Bsp& bsp, const Camera& camera, RenderOptions options) {
  Frame frame;
  render(bsp, camera, std::move(options), frame);
  return frame;
}

void render(const Bsp& bsp, const Camera& camera, RenderOptions options, Frame& frame) {
  options.algorithm = "bsp";
  detail::renderInto(bsp.scene(), camera, options, frame, detail::DrawMode::kClear, nullptr,
                     &bsp.tree());
}

}  // namespace hsr
