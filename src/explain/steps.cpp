// The steps of an explanation in memory (src/explain/steps.hpp). The algorithm runs twice:
// once to learn the finished frame's depth range (so every step's depth picture shares one
// grey scale), once traced. A step names the frame it is seen on, or a view (TraceStep::
// seen_from) drawn here: never a picture drawn in an algorithm.

#include "explain/steps.hpp"

#include <array>
#include <cmath>

#include <glm/geometric.hpp>

#include "hsr/error.hpp"
#include "orchestrator.hpp"

namespace hsr {
namespace detail {
namespace {

// The part of segment ab inside the square of half-width r around c (Liang and Barsky's
// clipping), or false when none is.
bool clipToSquare(glm::dvec2& a, glm::dvec2& b, glm::dvec2 c, double r) {
  double t0 = 0, t1 = 1;
  const glm::dvec2 d = b - a;
  for (int axis = 0; axis < 2; ++axis)
    for (const double side : {-1.0, 1.0}) {
      // Inside: side * (a + t d - c) <= r along this axis
      const double p = side * d[axis], q = r - side * (a[axis] - c[axis]);
      if (p == 0) {
        if (q < 0) return false;
      } else if (p > 0) {
        t1 = std::min(t1, q / p);
      } else {
        t0 = std::max(t0, q / p);
      }
    }
  if (t0 > t1) return false;
  const glm::dvec2 a0 = a;
  a = a0 + t0 * d;
  b = a0 + t1 * d;
  return true;
}

// A pixel magnified to fill the middle of a w x h view: each point shows what the sample
// nearest it resolves to (colour, and depth of the nearest opaque fragment), the samples are
// small squares, and the edges through the pixel are drawn across it (added to `outlines`).
Frame magnify(const TracePixel& px, int w, int h, std::vector<TraceOutline>& outlines) {
  Frame z;
  z.width = w;
  z.height = h;
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  z.color.assign(n, 0xFF303030u);
  z.depth.assign(n, 1.0f);
  z.ids.assign(n, kNoPolygon);
  z.overdraw.assign(n, 0);
  if (px.samples.empty()) return z;
  // The pixel square: side `size` from (left, top) of the view
  const int size = std::max(1, std::min(w, h) - 8);
  const int left = (w - size) / 2, top = (h - size) / 2;
  const auto toView = [&](glm::dvec2 from_centre) {  // pixel-centre coordinates of the view
    return glm::dvec2(left - 0.5 + (0.5 + from_centre.x) * size,
                      top - 0.5 + (0.5 + from_centre.y) * size);
  };
  for (int v = top; v < top + size; ++v)
    for (int u = left; u < left + size; ++u) {
      std::size_t nearest = 0;
      double best = INFINITY;
      for (std::size_t s = 0; s < px.samples.size(); ++s) {
        const glm::dvec2 d = toView(px.samples[s].at) - glm::dvec2(u, v);
        if (glm::dot(d, d) < best) best = glm::dot(d, d), nearest = s;
      }
      const TracePixel::Sample& s = px.samples[nearest];
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      z.color[i] = s.colour;
      z.depth[i] = std::isnan(s.depth) ? 1.0f : s.depth;
      z.ids[i] = s.id;
    }
  // The pixel's square, round its outermost pixels
  const float x0 = static_cast<float>(left) - 0.5f, y0 = static_cast<float>(top) - 0.5f;
  const float x1 = static_cast<float>(left + size - 1) + 0.5f,
              y1 = static_cast<float>(top + size - 1) + 0.5f;
  outlines.push_back({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}});
  for (const TracePixel::Sample& s : px.samples) {
    const glm::vec2 c(toView(s.at));
    outlines.push_back(
        {c + glm::vec2(-2, -2), c + glm::vec2(2, -2), c + glm::vec2(2, 2), c + glm::vec2(-2, 2)});
  }
  // The edges, clipped to the pixel
  const glm::dvec2 centre(px.x, px.y);
  for (std::array<glm::dvec2, 2> edge : px.edges)
    if (clipToSquare(edge[0], edge[1], centre, 0.5))
      outlines.push_back(
          {glm::vec2(toView(edge[0] - centre)), glm::vec2(toView(edge[1] - centre))});
  return z;
}

}  // namespace

bool StepMaker::wants(std::string_view, std::uint64_t index, std::uint64_t count) {
  return evenlySpaced(index, count, static_cast<std::uint64_t>(per_step_));
}

void StepMaker::record(const TraceStep& step) {
  std::vector<TraceOutline> outlines = step.outlines;
  Frame close_up;
  if (step.magnified && step.frame)
    close_up = magnify(*step.magnified, step.frame->width, step.frame->height, outlines);
  const Frame& f = step.magnified ? close_up : step.frame ? *step.frame : seenFrom(step.seen_from);
  ExplainedStep s;
  s.number = ++steps_;
  s.name = std::string(step.name);
  s.caption = step.caption;
  s.width = f.width;
  s.height = f.height;
  s.color = picture(f, "color");
  s.depth = depthPicture(f, range_);
  s.outlines = std::move(outlines);
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
  if (const std::string why = unsupported(info, camera, options); !why.empty()) throw Error(why);
  // A fast sibling that does not explain itself is explained by its textbook file, which draws
  // the same frame bit for bit (hsr/algorithms.hpp)
  const AlgorithmInfo* walked = explainedBy(info);
  if (!walked)
    throw Error("algorithm '" + std::string(info.name) + "' cannot explain its steps yet");
  RenderOptions traced_options = options;
  traced_options.algorithm = std::string(walked->name);
  // First the finished frame, whose depth range every step's depth picture uses; then the run
  // traced.
  Frame frame;
  render(scene, camera, options, frame);
  detail::StepMaker maker(each, drawnDepthRange(frame), explain_options.pictures_per_step, &scene,
                          &options);
  Frame traced;
  detail::renderInto(scene, camera, traced_options, traced, detail::DrawMode::kClear, &maker);
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
