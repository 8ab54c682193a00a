#pragma once
// What every visibility algorithm implements: prepared (culled, clipped, snapped) primitives
// in, a Frame out. The registry (registry.cpp) is the one table of them.

#include "hsr/render.hpp"
#include "pipeline/pipeline.hpp"

namespace hsr::detail {

struct AlgorithmInput {
  const Scene& scene;
  const Camera& camera;
  const RenderOptions& options;
  const PreparedScene& prepared;
};

using AlgorithmFn = Frame (*)(const AlgorithmInput& input);

struct AlgorithmEntry {
  AlgorithmInfo info;
  AlgorithmFn run;
};

const std::vector<AlgorithmEntry>& algorithmTable();

// Frame with cleared buffers (colour = clear colour, depth = clear depth, no ids).
Frame makeClearedFrame(int width, int height, const RenderOptions& options);

}  // namespace hsr::detail
