#pragma once
// hsr explain: the teaching view. An algorithm runs with its steps traced (the named steps
// its file's comments give), and each step becomes a numbered picture: the colour buffer and
// the depth buffer side by side, with what the step works on outlined (the polygon being
// drawn, a tile, a quadrant...) and a caption in the notes' words. The steps come in memory
// (explainSteps, forEachExplainedStep: what the web page shows) or written to a
// directory (explain): a picture per step, a contact sheet that shows them all at once, and
// steps.md, the captions with links to the pictures.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "hsr/doom.hpp"
#include "hsr/render.hpp"

namespace hsr {

struct ExplainOptions {
  int pictures_per_step = 12;  // of a step that repeats (one polygon after another): evenly
                               // spaced, first and last always
};

struct ExplainedStep {
  int number = 0;    // 1-based, as in the file names
  std::string name;  // the step's name in the algorithm's file: "draw polygon"
  std::string caption;
  // The buffers at this step, RGB8, top row first, width x height each: the colour buffer, and
  // the depth buffer in grey (near is light) on the finished frame's scale, so that every
  // step's depth picture can be compared with every other's.
  int width = 0, height = 0;
  std::vector<std::uint8_t> color, depth;
  // What the step works on (the polygon being drawn, a tile, a quadrant...): closed outlines
  // in window coordinates (pixel centres, y down).
  std::vector<std::vector<glm::vec2>> outlines;
  // The step's picture (both buffers side by side, the outlines drawn, the caption above) when
  // the explanation was written to a directory; color and depth are then left empty.
  std::filesystem::path picture;
};

struct Explanation {
  std::vector<ExplainedStep> steps;
  std::filesystem::path sheet;  // the contact sheet (written explanations)
  std::filesystem::path index;  // steps.md (written explanations)
  Frame frame;                  // the finished frame
};

// In memory: options.algorithm on the scene, every step with its pictures and outlines;
// nothing is written. Throws hsr::Error when the algorithm cannot explain itself (no kExplain
// capability) or the camera and options are refused as render() refuses them.
Explanation explainSteps(const Scene& scene, const Camera& camera, const RenderOptions& options,
                         const ExplainOptions& explain_options = {});

// The same, one step at a time as the algorithm reaches it (a long explanation need not be
// held whole); returns the finished frame.
using StepSink = std::function<void(ExplainedStep&&)>;
Frame forEachExplainedStep(const Scene& scene, const Camera& camera, const RenderOptions& options,
                           const StepSink& each, const ExplainOptions& explain_options = {});

// Written: the steps as above into `dir`: NN-step-name.png per step, sheet.png, steps.md and
// manifest.json, put in place as a whole (hsr/output.hpp: `dir` must be new, empty or an
// earlier hsr output). Throws as explainSteps, and when a file cannot be written.
Explanation explain(const Scene& scene, const Camera& camera, const RenderOptions& options,
                    const std::filesystem::path& dir, const ExplainOptions& explain_options = {});

// `hsr explain bsp2d`: Doom's front-to-back walk of a map's tree (doom::renderView), the
// columns each seg drew outlined: in memory, and into `dir` as explain() writes.
Explanation explainDoomViewSteps(const doom::Map& map, const doom::Nodes& nodes,
                                 const doom::Level& level, const Camera& camera,
                                 const ExplainOptions& explain_options = {});
Explanation explainDoomView(const doom::Map& map, const doom::Nodes& nodes,
                            const doom::Level& level, const Camera& camera,
                            const std::filesystem::path& dir,
                            const ExplainOptions& explain_options = {});

}  // namespace hsr
