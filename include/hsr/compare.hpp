#pragma once
// Side-by-side comparison of every registered algorithm on one scene: time, memory,
// overdraw, and agreement of each polygon-id buffer with the z-buffer's.

#include <cstdint>
#include <string>
#include <vector>

#include "hsr/render.hpp"

namespace hsr {

struct ComparisonRow {
  std::string algorithm;
  double ms = 0.0;                // wall time of render()
  std::uint64_t state_bytes = 0;  // memory held by the algorithm
  double mean_overdraw = 0.0;     // fragments written per covered pixel
  std::uint32_t max_overdraw = 0;
  double id_agreement = 1.0;  // fraction of pixels whose id equals the z-buffer's
  std::uint64_t differing_pixels = 0;
  std::string not_run;   // why it was not run (it cannot do what the options ask)
  int views = 1;         // views rendered: the camera's, then an orbit (orbitView)
  double view_ms = 0.0;  // mean wall time of the views after the first
  Frame frame;           // the first view
};

// The most views compareAlgorithms takes.
inline constexpr int kMaxCompareViews = 360;

// Every algorithm of the registry; one that cannot do what the options ask is listed with
// not_run set and no frame (the sheet leaves it out). With views > 1, each algorithm then
// draws views 1 .. views - 1 of an orbit around the target into the frame it drew the first
// view in, keeping what it keeps between frames (an octree, its buffers), and id agreement
// counts every view's pixels.
std::vector<ComparisonRow> compareAlgorithms(const Scene& scene, const Camera& camera,
                                             const RenderOptions& options, int views = 1);

// A labelled contact sheet: a grid of cells no wider than kMaxSheetWidth, one per algorithm
// (its colour, ids and overdraw pictures one above the other; a frame wider than a cell shown
// every few pixels), the overdraw pictures on one scale for every algorithm, and a legend.
// Returns RGB8 top row first and sets width and height.
inline constexpr int kMaxSheetWidth = 4096;
std::vector<std::uint8_t> comparisonSheet(const std::vector<ComparisonRow>& rows, int* width,
                                          int* height);
// The sheet's size for `columns` algorithms (cells) at frame_width x frame_height (known before any
// rendering, so that a sheet too large to write is refused at once).
struct SheetSize {
  long long width, height;
};
SheetSize comparisonSheetSize(int columns, int frame_width, int frame_height);

// Whether the label font draws `c`: every printable ASCII character does (lower case as upper
// case); other bytes only advance.
bool labelHasGlyph(char c);
// Draws text with a built-in 5x7 pixel font into an RGB8 image (for labels).
void drawLabel(std::vector<std::uint8_t>& rgb, int width, int height, int x, int y,
               const std::string& text, int scale = 2);

}  // namespace hsr
