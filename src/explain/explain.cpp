// The steps of an explanation (src/explain/steps.hpp) written: each as a numbered picture
// (caption above, the colour and depth buffers side by side, the outlines drawn), a contact
// sheet and an index; and Doom's walk explained, in memory and written. Every explain picture
// is drawn here or in steps.cpp, never in an algorithm.

#include "hsr/explain.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <sstream>

#include "explain/steps.hpp"
#include "hsr/compare.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/output.hpp"
#include "doom/doom_level.hpp"

namespace hsr {
namespace {

constexpr int kGap = 8;                           // pixels between and around the panels
constexpr std::uint8_t kBack = 32;                // the dark page behind the panels
constexpr std::uint8_t kMark[3] = {235, 40, 40};  // outline colour

// An RGB8 picture, top row first.
struct Picture {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  Picture(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, kBack) {}
  std::uint8_t* at(int x, int y) { return &rgb[3 * (static_cast<std::size_t>(y) * width + x)]; }
  void blit(const std::vector<std::uint8_t>& src, int w, int h, int ox, int oy) {
    for (int y = 0; y < h; ++y)
      std::copy_n(&src[3 * static_cast<std::size_t>(y) * w], 3 * w, at(ox, oy + y));
  }
};

// A 1-pixel line from a to b (window coordinates of a panel placed at ox, oy), clipped to the
// panel.
void drawSegment(Picture& p, glm::vec2 a, glm::vec2 b, int ox, int oy, int w, int h) {
  const float len = std::max(std::abs(b.x - a.x), std::abs(b.y - a.y));
  if (!std::isfinite(len)) return;
  const int steps = static_cast<int>(std::min(std::ceil(len), 20000.0f));
  for (int k = 0; k <= steps; ++k) {
    const float t = steps == 0 ? 0.0f : static_cast<float>(k) / static_cast<float>(steps);
    const long x = std::lround(a.x + (b.x - a.x) * t), y = std::lround(a.y + (b.y - a.y) * t);
    if (x < 0 || y < 0 || x >= w || y >= h) continue;
    std::copy_n(kMark, 3, p.at(ox + static_cast<int>(x), oy + static_cast<int>(y)));
  }
}

// Words of `text` in lines of at most `columns` characters.
std::vector<std::string> wrap(const std::string& text, std::size_t columns) {
  std::vector<std::string> lines;
  std::istringstream words(text);
  std::string word, line;
  while (words >> word) {
    if (!line.empty() && line.size() + 1 + word.size() > columns) {
      lines.push_back(line);
      line.clear();
    }
    if (!line.empty()) line += ' ';
    line += word;
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

std::string fileSafe(std::string_view s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '-';
  return out;
}

// Box-filtered reduction by an integer factor.
Picture shrink(const Picture& src, int factor) {
  Picture out(std::max(1, src.width / factor), std::max(1, src.height / factor));
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < 3; ++c) {
        int sum = 0;
        for (int dy = 0; dy < factor; ++dy)
          for (int dx = 0; dx < factor; ++dx)
            sum += src.rgb[3 * (static_cast<std::size_t>(y * factor + dy) * src.width + x * factor +
                                dx) +
                           c];
        out.at(x, y)[c] = static_cast<std::uint8_t>(sum / (factor * factor));
      }
  return out;
}

// Writes each step as its picture (the header, then the colour and depth buffers side by side
// with the outlines drawn) and keeps a thumbnail of it for the contact sheet; the step's
// buffers are then let go.
class StepWriter {
 public:
  explicit StepWriter(OutputDirectory& out) : out_(out) {}

  void operator()(ExplainedStep&& s) {
    const int w = s.width, h = s.height;
    // The header: step number and name, then the caption, wrapped to the picture's width.
    const int scale = w >= 360 ? 2 : 1;
    const int char_w = 6 * scale, line_h = 10 * scale;
    const int width = 2 * w + 3 * kGap;
    const std::size_t columns = static_cast<std::size_t>(std::max(8, (width - 2 * kGap) / char_w));
    std::vector<std::string> lines = wrap(s.caption, columns);
    const int header = kGap + line_h * (2 + static_cast<int>(lines.size()));
    Picture p(width, header + h + kGap);
    char title[96];
    std::snprintf(title, sizeof title, "STEP %d: %s", s.number, s.name.c_str());
    drawLabel(p.rgb, p.width, p.height, kGap, kGap, title, scale);
    for (std::size_t i = 0; i < lines.size(); ++i)
      drawLabel(p.rgb, p.width, p.height, kGap, kGap + line_h * (2 + static_cast<int>(i)), lines[i],
                scale);
    // The colour buffer and the depth buffer side by side, what the step works on outlined.
    const int left = kGap, right = 2 * kGap + w, top = header;
    p.blit(s.color, w, h, left, top);
    p.blit(s.depth, w, h, right, top);
    for (const std::vector<glm::vec2>& o : s.outlines)
      for (std::size_t i = 0; i < o.size(); ++i)
        for (const int ox : {left, right})
          drawSegment(p, o[i], o[(i + 1) % o.size()], ox, top, w, h);
    char name[160];
    std::snprintf(name, sizeof name, "%02d-%s.png", s.number, fileSafe(s.name).c_str());
    s.picture = out_.path() / name;
    out_.write(name, {encodePng(p.width, p.height, 3, p.rgb.data())});
    // A thumbnail of the two panels for the contact sheet.
    Picture panels(2 * w + kGap, h);
    for (int y = 0; y < h; ++y)
      std::copy_n(p.at(left, top + y), 3 * (2 * w + kGap), panels.at(0, y));
    const int factor = std::max(1, (2 * w + kGap + 419) / 420);  // thumbnails about 420 px wide
    thumbs_.push_back(shrink(panels, factor));
    s.color = {};
    s.depth = {};
    steps_.push_back(std::move(s));
  }

  std::vector<ExplainedStep>& steps() { return steps_; }
  const std::vector<Picture>& thumbs() const { return thumbs_; }

 private:
  OutputDirectory& out_;
  std::vector<ExplainedStep> steps_;
  std::vector<Picture> thumbs_;
};

// The thumbnails in a grid, each under its number and step name.
Picture contactSheet(const std::vector<Picture>& thumbs, const std::vector<ExplainedStep>& steps) {
  constexpr int kColumns = 3, kLabel = 14;
  const int tw = thumbs.empty() ? 1 : thumbs[0].width, th = thumbs.empty() ? 1 : thumbs[0].height;
  const int n = static_cast<int>(thumbs.size());
  const int cols = std::min(kColumns, std::max(n, 1)), rows = (n + cols - 1) / cols;
  Picture sheet(cols * tw + (cols + 1) * kGap, rows * (th + kLabel) + (rows + 1) * kGap);
  for (int i = 0; i < n; ++i) {
    const int x = kGap + (i % cols) * (tw + kGap);
    const int y = kGap + (i / cols) * (th + kLabel + kGap);
    drawLabel(sheet.rgb, sheet.width, sheet.height, x, y + 2,
              std::to_string(steps[i].number) + " " + steps[i].name, 1);
    sheet.blit(thumbs[i].rgb, thumbs[i].width, thumbs[i].height, x, y + kLabel);
  }
  return sheet;
}

}  // namespace

namespace {

// The contact sheet and steps.md of the written steps, then the directory put in place.
void finish(OutputDirectory& files, StepWriter& writer, Explanation& out, const std::string& title,
            const std::string& source) {
  out.steps = std::move(writer.steps());
  const Picture sheet = contactSheet(writer.thumbs(), out.steps);
  out.sheet = files.path() / "sheet.png";
  files.write("sheet.png", {encodePng(sheet.width, sheet.height, 3, sheet.rgb.data())});
  // The index: every step's caption, linked to its picture.
  out.index = files.path() / "steps.md";
  std::ostringstream md;
  md << "# " << title << "\n\n"
     << "Source: " << source << ". Left: the colour buffer; right: the depth buffer "
     << "(near is light); what the step works on is outlined in red.\n\n"
     << "![contact sheet](sheet.png)\n\n";
  for (const ExplainedStep& s : out.steps)
    md << s.number << ". **" << s.name << "**: " << s.caption << " [picture]("
       << s.picture.filename().string() << ")\n";
  files.write("steps.md", {md.str()});
  files.commit();
}

constexpr const char* kDoomTitle =
    " seen as Doom's renderer sees it, the 2D BSP walked front to back";
constexpr const char* kDoomSource =
    "the notes' BSP trees and \"the first FPS\"; Doom's R_RenderBSPNode (id Software, 1993)";

// Doom's walk traced, each step handed on; the finished view.
Frame forEachDoomStep(const doom::Map& map, const doom::Nodes& nodes, const doom::Level& level,
                      const Camera& camera, const StepSink& each,
                      const ExplainOptions& explain_options) {
  Frame frame = doom::renderView(map, nodes, level, camera);
  detail::StepMaker maker(each, drawnDepthRange(frame), explain_options.pictures_per_step);
  (void)detail::renderDoomViewTraced(map, nodes, level, camera, &maker);
  return frame;
}

}  // namespace

Explanation explain(const Scene& scene, const Camera& camera, const RenderOptions& options,
                    const std::filesystem::path& dir, const ExplainOptions& explain_options) {
  const AlgorithmInfo& info = findAlgorithm(options.algorithm);
  OutputDirectory files(dir);
  StepWriter writer(files);
  Explanation out;
  out.frame = forEachExplainedStep(scene, camera, options, std::ref(writer), explain_options);
  // A fast sibling is explained by its textbook file (forEachExplainedStep): the title says so
  std::string title = std::string(info.name) + ": " + std::string(info.summary);
  if (const AlgorithmInfo* traced = explainedBy(info); traced && traced != &info)
    title += ". Its steps are those of " + std::string(traced->name) +
             ", which draws the same frame bit for bit";
  finish(files, writer, out, title, std::string(info.source));
  return out;
}

Explanation explainDoomViewSteps(const doom::Map& map, const doom::Nodes& nodes,
                                 const doom::Level& level, const Camera& camera,
                                 const ExplainOptions& explain_options) {
  Explanation out;
  out.frame = forEachDoomStep(
      map, nodes, level, camera, [&](ExplainedStep&& s) { out.steps.push_back(std::move(s)); },
      explain_options);
  return out;
}

Explanation explainDoomView(const doom::Map& map, const doom::Nodes& nodes,
                            const doom::Level& level, const Camera& camera,
                            const std::filesystem::path& dir,
                            const ExplainOptions& explain_options) {
  OutputDirectory files(dir);
  StepWriter writer(files);
  Explanation out;
  out.frame = forEachDoomStep(map, nodes, level, camera, std::ref(writer), explain_options);
  finish(files, writer, out, "bsp2d: " + map.name + kDoomTitle, kDoomSource);
  return out;
}

}  // namespace hsr
