#pragma once
// The one orchestrator, for the library's own callers (render(), the GL facade, explain).

#include "core/trace.hpp"
#include "hsr/render.hpp"

namespace hsr::detail {

enum class DrawMode {
  kClear,  // size and clear the frame first (render())
  kOver,   // draw over what the frame holds (the GL facade's draw call)
};

// Validates the camera and options, looks the algorithm up, prepares what its entry asks for,
// clears (kClear), runs it and merges the stats (the pipeline's first, then the algorithm's).
// `given`: a structure the caller built beforehand for the algorithm (AlgorithmInput::given).
void renderInto(const Scene& scene, const Camera& camera, const RenderOptions& options,
                Frame& frame, DrawMode mode, Trace* trace = nullptr, const void* given = nullptr);

// Worker threads for a request: 0 = all; more than the machine has is clamped to what it has
// (results do not depend on the count, so nothing is lost). Throws hsr::Error when < 0.
int workerThreads(int requested);

}  // namespace hsr::detail
