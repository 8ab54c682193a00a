#pragma once
// Turns an algorithm's trace of named steps into ExplainedSteps in memory: each step's
// buffers as pictures, its caption and outlines. Part of the core (the web page explains with
// it); explain.cpp writes the steps out.

#include <algorithm>
#include <string_view>

#include "core/trace.hpp"
#include "hsr/explain.hpp"
#include "hsr/io.hpp"

namespace hsr::detail {

// The algorithm's trace as ExplainedSteps: each step's buffers as pictures, in memory, handed
// on one at a time.
class StepMaker : public Trace {
 public:
  // `scene` and `options` draw the views a step asks for (TraceStep::seen_from); null where
  // no step does (Doom's walk).
  StepMaker(const StepSink& each, DepthRange range, int per_step, const Scene* scene = nullptr,
            const RenderOptions* options = nullptr)
      : each_(each),
        range_(range),
        per_step_(std::max(per_step, 2)),
        scene_(scene),
        options_(options) {}

  bool wants(std::string_view, std::uint64_t index, std::uint64_t count) override;
  void record(const TraceStep& step) override;

 private:
  // The scene drawn plainly from `camera` (one thread, the frame's clear colour), drawn once
  // for all the steps seen from it.
  const Frame& seenFrom(const Camera* camera);

  const StepSink& each_;
  DepthRange range_;
  int per_step_;
  int steps_ = 0;
  const Scene* scene_;
  const RenderOptions* options_;
  const Camera* seen_from_ = nullptr;
  Frame view_;
};

}  // namespace hsr::detail
