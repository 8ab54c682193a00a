#pragma once
// What an algorithm shows while it works, for `hsr explain`: a sequence of named steps, each
// with a caption and the state of the frame at that moment. An algorithm holds a Trace
// pointer that is null except when explaining, so tracing costs one branch per step:
//
//   if (trace && trace->wants(kStepDrawPolygon, k, n))
//     trace->record({kStepDrawPolygon, caption, &frame, outlines});
//
// Step names are the algorithm file's own step comments, so code and pictures share one
// vocabulary. Algorithms never draw pictures; src/explain/ does.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

#include "hsr/camera.hpp"
#include "hsr/render.hpp"

namespace hsr::detail {

// A closed outline in window space (pixel-centre coordinates, y down), e.g. the triangles of
// the polygon being drawn, or a Warnock quadrant.
using TraceOutline = std::vector<glm::vec2>;

// One pixel seen close up (the A-buffer's magnified pixel): what each of its samples resolves
// to, and the true edges through it. src/explain/ pictures it over the whole view.
struct TracePixel {
  struct Sample {
    glm::dvec2 at;         // from the pixel's centre, in pixels: each coordinate in [-0.5, 0.5]
    std::uint32_t colour;  // RGBA8, as Frame::color
    float depth;           // of the nearest opaque fragment (NaN: none, the background)
    PolygonId id;          // kNoPolygon where none
  };
  int x = 0, y = 0;  // the pixel, window coordinates
  std::vector<Sample> samples;
  // in window coordinates (pixel centres at integers)
  std::vector<std::array<glm::dvec2, 2>> edges;
};

struct TraceStep {
  std::string_view name;               // "draw polygon"
  std::string caption;                 // in the notes' words, with this step's figures
  const Frame* frame = nullptr;        // the buffers after the step (the trace copies them)
  std::vector<TraceOutline> outlines;  // what to outline on the pictures
  // Or, for a step pictured on another view of the scene (the BSP build's plan from above):
  // that camera, the scene drawn plainly from it by src/explain/ (frame null).
  const Camera* seen_from = nullptr;
  // Or a pixel magnified to fill a view of the frame's size (frame then gives only the size;
  // src/explain/ adds the pixel's square, its samples and the edges to the outlines).
  const TracePixel* magnified = nullptr;
};

class Trace {
 public:
  virtual ~Trace() = default;
  // Whether the algorithm should record occurrence `index` (0-based) of step `name`, of
  // `count` in all: a long run keeps a few evenly spaced pictures, always the last.
  virtual bool wants(std::string_view name, std::uint64_t index, std::uint64_t count) = 0;
  virtual void record(const TraceStep& step) = 0;
};

// Which occurrences of a step that repeats `count` times a teaching view keeps when it shows
// `per_step` of them: evenly spaced, the first and the last always (hsr explain and the web
// page both keep 12).
inline bool evenlySpaced(std::uint64_t index, std::uint64_t count, std::uint64_t per_step) {
  if (per_step < 2) per_step = 2;
  if (count <= per_step || index == 0 || index + 1 == count) return true;
  const std::uint64_t slots = per_step - 1;
  return index * slots / (count - 1) != (index - 1) * slots / (count - 1);
}

}  // namespace hsr::detail
