#pragma once
// hsr explain: the teaching view. An algorithm runs with its steps traced (the named steps
// its file's comments give), and each step becomes a numbered picture: the colour buffer and
// the depth buffer side by side, with what the step works on outlined (the polygon being
// drawn, a tile, a quadrant...) and a caption in the notes' words. A contact sheet shows them
// all at once, and steps.md lists the captions with links to the pictures.

#include <filesystem>
#include <string>
#include <vector>

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
  std::filesystem::path picture;
};

struct Explanation {
  std::vector<ExplainedStep> steps;
  std::filesystem::path sheet;  // the contact sheet
  std::filesystem::path index;  // steps.md
  Frame frame;                  // the finished frame
};

// Explains options.algorithm on the scene into `dir`: NN-step-name.png per step, sheet.png,
// steps.md and manifest.json, put in place as a whole (hsr/output.hpp: `dir` must be new,
// empty or an earlier hsr output). Throws hsr::Error when the algorithm cannot explain
// itself (no kExplain capability) or a file cannot be written.
Explanation explain(const Scene& scene, const Camera& camera, const RenderOptions& options,
                    const std::filesystem::path& dir, const ExplainOptions& explain_options = {});

// `hsr explain bsp2d`: Doom's front-to-back walk of a map's tree (doom::renderView), the
// columns each seg drew outlined, into `dir` as above.
Explanation explainDoomView(const doom::Map& map, const doom::Nodes& nodes, const doom::Level& level,
                            const Camera& camera, const std::filesystem::path& dir,
                            const ExplainOptions& explain_options = {});

}  // namespace hsr
