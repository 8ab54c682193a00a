// The steps of an explanation in memory (src/explain/steps.hpp). The algorithm runs twice:
// once to learn the finished frame's depth range (so every step's depth picture shares one
// grey scale), once traced. A step names the frame it is seen on, or a view (TraceStep::
// seen_from) drawn here: never a picture drawn in an algorithm.

#include "explain/steps.hpp"

#include "hsr/error.hpp"
#include "orchestrator.hpp"

namespace hsr {
namespace detail {

bool StepMaker::wants(std::string_view, std::uint64_t index, std::uint64_t count) {
  return evenlySpaced(index, count, static_cast<std::uint64_t>(per_step_));
}

void StepMaker::record(const TraceStep& step) {
  const Frame& f = step.frame ? *step.frame : seenFrom(step.seen_from);
  ExplainedStep s;
  s.number = ++steps_;
  s.name = std::string(step.name);
  s.caption = step.caption;
  s.width = f.width;
  s.height = f.height;
  s.color = picture(f, "color");
  s.depth = depthPicture(f, range_);
  s.outlines = step.outlines;
  each_(std::move(s));
}

const Frame& StepMaker::seenFrom(const Camera* camera) {
  if (!camera || !scene_) throw Error("explain: a step has neither a frame nor a view to draw");
  if (camera != seen_from_) {
    RenderOptions o;
    o.threads = 1;
    o.clear_color = options_->clear_color;
    view_ = render(*scene_, *camera, o);
    seen_from_ = camera;
  }
  return view_;
}

}  // namespace detail

Frame forEachExplainedStep(const Scene& scene, const Camera& camera, const RenderOptions& options,
                           const StepSink& each, const ExplainOptions& explain_options) {
  const AlgorithmInfo& info = findAlgorithm(options.algorithm);
  if (!info.has(kExplain))
    throw Error("algorithm '" + std::string(info.name) + "' cannot explain its steps yet");
  if (const std::string why = unsupported(info, camera, options); !why.empty()) throw Error(why);
  // First the finished frame, whose depth range every step's depth picture uses; then the run
  // traced.
  Frame frame;
  render(scene, camera, options, frame);
  detail::StepMaker maker(each, drawnDepthRange(frame), explain_options.pictures_per_step, &scene, &options);
  Frame traced;
  detail::renderInto(scene, camera, options, traced, detail::DrawMode::kClear, &maker);
  return frame;
}

Explanation explainSteps(const Scene& scene, const Camera& camera, const RenderOptions& options,
                         const ExplainOptions& explain_options) {
  Explanation out;
  out.frame = forEachExplainedStep(
      scene, camera, options, [&](ExplainedStep&& s) { out.steps.push_back(std::move(s)); },
      explain_options);
  return out;
}

}  // namespace hsr
