#pragma once
// What every visibility algorithm implements: prepared (culled, clipped, snapped) primitives
// in, a Frame out. The registry (registry.cpp) is the one table of them.

#include <memory>

#include "hsr/render.hpp"
#include "pipeline/pipeline.hpp"

namespace hsr::detail {

struct AlgorithmInput {
  const Scene& scene;
  const Camera& camera;
  const RenderOptions& options;
  const PreparedScene& prepared;
  std::shared_ptr<void>* scratch = nullptr;  // the algorithm's own reusable memory, if any
};

// Memory kept in a Frame between renders: the pipeline's output and the algorithm's scratch.
struct RenderCache {
  PreparedScene prepared;
  std::shared_ptr<void> algorithm;
  const void* owner = nullptr;  // the registry entry that made `algorithm`
};

// The algorithm's scratch of type T, created on first use (a fresh one without a cache).
template <class T>
T& algorithmScratch(const AlgorithmInput& in, std::unique_ptr<T>& fallback) {
  if (in.scratch) {
    if (!*in.scratch) *in.scratch = std::make_shared<T>();
    return *static_cast<T*>(in.scratch->get());
  }
  fallback = std::make_unique<T>();
  return *fallback;
}

// Renders into `frame`, reusing its buffers' memory when their size already fits.
using AlgorithmFn = void (*)(const AlgorithmInput& input, Frame& frame);

struct AlgorithmEntry {
  AlgorithmInfo info;
  AlgorithmFn run;
};

const std::vector<AlgorithmEntry>& algorithmTable();

// Worker threads for a request: 0 = all; more than the machine has is clamped to what it has
// (results do not depend on the count, so nothing is lost). Throws hsr::Error when < 0.
int workerThreads(int requested);

// Sizes and clears the buffers (colour = clear colour, depth = clear depth, no ids, overdraw
// 0), reusing their memory; stats are reset.
void clearFrame(Frame& frame, int width, int height, const RenderOptions& options);

}  // namespace hsr::detail
