// hsr compare: every algorithm on one scene, measured and checked against the z-buffer.

#include "hsr/compare.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <string>

#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "core/stopwatch.hpp"

namespace hsr {

std::vector<ComparisonRow> compareAlgorithms(const Scene& scene, const Camera& camera,
                                             const RenderOptions& options, int views) {
  if (views < 1 || views > kMaxCompareViews)
    throw Error("views must be 1 to " + std::to_string(kMaxCompareViews) + " (got " +
                std::to_string(views) + ")");
  std::vector<ComparisonRow> rows;
  for (const AlgorithmInfo& info : algorithms()) {
    RenderOptions o = options;
    o.algorithm = std::string(info.name);
    ComparisonRow row;
    row.algorithm = o.algorithm;
    row.not_run = unsupported(info, camera, o);
    if (!row.not_run.empty()) {
      rows.push_back(std::move(row));
      continue;
    }
    const detail::Stopwatch t0;
    row.frame = render(scene, camera, o);
    row.ms = t0.ms();
    row.state_bytes = row.frame.stats.state_bytes;
    std::uint64_t covered = 0, sum = 0;
    for (std::uint32_t c : row.frame.overdraw) {
      if (c) covered++;
      sum += c;
      row.max_overdraw = std::max(row.max_overdraw, c);
    }
    row.mean_overdraw = covered ? static_cast<double>(sum) / static_cast<double>(covered) : 0.0;
    rows.push_back(std::move(row));
  }
  // Agreement with the registry's reference row.
  const std::string_view reference = referenceAlgorithm().name;
  const auto ref_row = std::find_if(rows.begin(), rows.end(), [&](const ComparisonRow& r) {
    return r.algorithm == reference && r.not_run.empty();
  });
  if (ref_row == rows.end()) return rows;  // nothing to agree with: the reference was not run
  const FrameBuffer<PolygonId>& ref = ref_row->frame.ids;
  for (ComparisonRow& r : rows) {
    if (!r.not_run.empty()) continue;
    std::uint64_t diff = 0;
    for (std::size_t i = 0; i < ref.size(); ++i) diff += r.frame.ids[i] != ref[i];
    r.differing_pixels = diff;
    r.id_agreement =
        ref.empty() ? 1.0 : 1.0 - static_cast<double>(diff) / static_cast<double>(ref.size());
  }
  if (views == 1) return rows;

  // The orbit: every algorithm draws each further view into a frame that shares the first
  // view's kept state (a copy of a Frame shares its scratch), then is compared with the
  // reference's frame of the same view.
  std::vector<ComparisonRow*> run;
  std::vector<Frame> frames;
  std::size_t ref_index = 0;
  for (ComparisonRow& r : rows) {
    if (!r.not_run.empty()) continue;
    if (&r == &*ref_row) ref_index = run.size();
    run.push_back(&r);
    frames.push_back(r.frame);
  }
  std::uint64_t pixels = ref.size();
  for (int k = 1; k < views; ++k) {
    const Camera view = orbitView(camera, k, views);
    for (std::size_t i = 0; i < run.size(); ++i) {
      RenderOptions o = options;
      o.algorithm = run[i]->algorithm;
      const detail::Stopwatch t0;
      render(scene, view, o, frames[i]);
      run[i]->view_ms += t0.ms();
    }
    const FrameBuffer<PolygonId>& view_ref = frames[ref_index].ids;
    for (std::size_t i = 0; i < run.size(); ++i)
      for (std::size_t p = 0; p < view_ref.size(); ++p)
        run[i]->differing_pixels += frames[i].ids[p] != view_ref[p];
    pixels += view_ref.size();
  }
  for (ComparisonRow* r : run) {
    r->views = views;
    r->view_ms /= views - 1;
    r->id_agreement = 1.0 - static_cast<double>(r->differing_pixels) /
                                static_cast<double>(std::max<std::uint64_t>(pixels, 1));
  }
  return rows;
}

namespace {

// 5x7 glyphs, one byte per row (low 5 bits, MSB = leftmost column).
struct Glyph {
  char c;
  std::array<std::uint8_t, 7> rows;
};
constexpr Glyph kFont[] = {
    {'A', {14, 17, 17, 31, 17, 17, 17}}, {'B', {30, 17, 17, 30, 17, 17, 30}},
    {'C', {14, 17, 16, 16, 16, 17, 14}}, {'D', {30, 17, 17, 17, 17, 17, 30}},
    {'E', {31, 16, 16, 30, 16, 16, 31}}, {'F', {31, 16, 16, 30, 16, 16, 16}},
    {'G', {14, 17, 16, 23, 17, 17, 15}}, {'H', {17, 17, 17, 31, 17, 17, 17}},
    {'I', {14, 4, 4, 4, 4, 4, 14}},      {'J', {7, 2, 2, 2, 2, 18, 12}},
    {'K', {17, 18, 20, 24, 20, 18, 17}}, {'L', {16, 16, 16, 16, 16, 16, 31}},
    {'M', {17, 27, 21, 21, 17, 17, 17}}, {'N', {17, 17, 25, 21, 19, 17, 17}},
    {'O', {14, 17, 17, 17, 17, 17, 14}}, {'P', {30, 17, 17, 30, 16, 16, 16}},
    {'Q', {14, 17, 17, 17, 21, 18, 13}}, {'R', {30, 17, 17, 30, 20, 18, 17}},
    {'S', {15, 16, 16, 14, 1, 1, 30}},   {'T', {31, 4, 4, 4, 4, 4, 4}},
    {'U', {17, 17, 17, 17, 17, 17, 14}}, {'V', {17, 17, 17, 17, 17, 10, 4}},
    {'W', {17, 17, 17, 21, 21, 21, 10}}, {'X', {17, 17, 10, 4, 10, 17, 17}},
    {'Y', {17, 17, 10, 4, 4, 4, 4}},     {'Z', {31, 1, 2, 4, 8, 16, 31}},
    {'0', {14, 17, 19, 21, 25, 17, 14}}, {'1', {4, 12, 4, 4, 4, 4, 14}},
    {'2', {14, 17, 1, 2, 4, 8, 31}},     {'3', {31, 2, 4, 2, 1, 17, 14}},
    {'4', {2, 6, 10, 18, 31, 2, 2}},     {'5', {31, 16, 30, 1, 1, 17, 14}},
    {'6', {6, 8, 16, 30, 17, 17, 14}},   {'7', {31, 1, 2, 4, 8, 8, 8}},
    {'8', {14, 17, 17, 14, 17, 17, 14}}, {'9', {14, 17, 17, 15, 1, 2, 12}},
    {'.', {0, 0, 0, 0, 0, 12, 12}},      {'%', {24, 25, 2, 4, 8, 19, 3}},
    {'-', {0, 0, 0, 31, 0, 0, 0}},       {':', {0, 12, 12, 0, 12, 12, 0}},
    {'/', {1, 1, 2, 4, 8, 16, 16}},      {'(', {2, 4, 8, 8, 8, 4, 2}},
    {')', {8, 4, 2, 2, 2, 4, 8}},        {'=', {0, 0, 31, 0, 31, 0, 0}},
    {'_', {0, 0, 0, 0, 0, 0, 31}},       {',', {0, 0, 0, 0, 12, 4, 8}},
    {'\'', {4, 4, 8, 0, 0, 0, 0}},       {'"', {10, 10, 0, 0, 0, 0, 0}},
    {'+', {0, 4, 4, 31, 4, 4, 0}},       {'!', {4, 4, 4, 4, 4, 0, 4}},
    {'?', {14, 17, 1, 2, 4, 0, 4}},      {'<', {2, 4, 8, 16, 8, 4, 2}},
    {'>', {8, 4, 2, 1, 2, 4, 8}},        {';', {0, 12, 12, 0, 12, 4, 8}},
    {'#', {10, 10, 31, 10, 31, 10, 10}}, {'*', {0, 4, 21, 14, 21, 4, 0}},
    {'[', {14, 8, 8, 8, 8, 8, 14}},      {']', {14, 2, 2, 2, 2, 2, 14}},
    {'{', {6, 8, 8, 16, 8, 8, 6}},       {'}', {12, 2, 2, 1, 2, 2, 12}},
    {'|', {4, 4, 4, 4, 4, 4, 4}},        {'\\', {16, 16, 8, 4, 2, 1, 1}},
    {'^', {4, 10, 17, 0, 0, 0, 0}},      {'`', {8, 4, 2, 0, 0, 0, 0}},
    {'~', {0, 0, 8, 21, 2, 0, 0}},       {'@', {14, 17, 23, 21, 23, 16, 15}},
    {'$', {4, 15, 20, 14, 5, 30, 4}},    {'&', {12, 18, 20, 8, 21, 18, 13}},
};

const Glyph* findGlyph(char c) {
  if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  for (const Glyph& g : kFont)
    if (g.c == c) return &g;
  return nullptr;
}

}  // namespace

bool labelHasGlyph(char c) { return c == ' ' || findGlyph(c) != nullptr; }

void drawLabel(std::vector<std::uint8_t>& rgb, int width, int height, int x, int y,
               const std::string& text, int scale) {
  for (std::size_t n = 0; n < text.size(); ++n) {
    const Glyph* g = findGlyph(text[n]);
    if (!g) continue;  // space and unknown characters advance only
    const int gx = x + static_cast<int>(n) * 6 * scale;
    for (int r = 0; r < 7; ++r)
      for (int c = 0; c < 5; ++c) {
        if (!((g->rows[r] >> (4 - c)) & 1)) continue;
        for (int sy = 0; sy < scale; ++sy)
          for (int sx = 0; sx < scale; ++sx) {
            const int px = gx + c * scale + sx, py = y + r * scale + sy;
            if (px < 0 || py < 0 || px >= width || py >= height) continue;
            const std::size_t k = 3 * (static_cast<std::size_t>(py) * width + px);
            rgb[k] = rgb[k + 1] = rgb[k + 2] = 255;
          }
      }
  }
}

namespace {

constexpr int kLabel = 24, kGap = 8, kLegend = 48;

// The sheet as a grid of cells, one per algorithm (its colour, ids and overdraw pictures one
// above the other), as many cells a row as fit kMaxSheetWidth; a frame too wide for one cell
// is shown every `step`-th pixel. A legend row at the bottom.
struct Layout {
  int step = 1, pw = 0, ph = 0, columns = 0, rows = 0;
  long long width = 0, height = 0;
};

Layout layoutOf(int cells, int frame_width, int frame_height) {
  Layout l;
  if (cells <= 0 || frame_width <= 0 || frame_height <= 0) return l;
  l.step = std::max(1, (frame_width + kMaxSheetWidth - 2 * kGap - 1) / (kMaxSheetWidth - 2 * kGap));
  l.pw = (frame_width + l.step - 1) / l.step;
  l.ph = (frame_height + l.step - 1) / l.step;
  l.columns = std::clamp((kMaxSheetWidth - kGap) / (l.pw + kGap), 1, cells);
  l.rows = (cells + l.columns - 1) / l.columns;
  const long long cell_h = 3LL * (kLabel + l.ph) + 2LL * kGap;
  l.width = static_cast<long long>(l.columns) * l.pw + (l.columns + 1LL) * kGap;
  l.width = std::max<long long>(l.width, 2 * kGap + 300);  // room for the legend
  l.height = l.rows * cell_h + (l.rows + 1LL) * kGap + kLegend;
  return l;
}

}  // namespace

SheetSize comparisonSheetSize(int columns, int frame_width, int frame_height) {
  const Layout l = layoutOf(columns, frame_width, frame_height);
  return {l.width, l.height};
}

std::vector<std::uint8_t> comparisonSheet(const std::vector<ComparisonRow>& rows, int* width,
                                          int* height) {
  constexpr const char* kKinds[] = {"color", "ids", "overdraw"};
  std::vector<const ComparisonRow*> run;
  for (const ComparisonRow& r : rows)
    if (r.not_run.empty()) run.push_back(&r);
  const int fw = run.empty() ? 0 : run[0]->frame.width;
  const int fh = run.empty() ? 0 : run[0]->frame.height;
  const Layout l = layoutOf(static_cast<int>(run.size()), fw, fh);
  checkPngSize("comparison sheet", l.width, l.height, 3);
  *width = static_cast<int>(l.width);
  *height = static_cast<int>(l.height);
  std::vector<std::uint8_t> sheet(static_cast<std::size_t>(*width) * *height * 3, 32);
  // One overdraw scale for every cell: the most fragments any algorithm wrote to a pixel
  std::uint32_t most = 0;
  for (const ComparisonRow* r : run) most = std::max(most, r->max_overdraw);
  const int label_scale = l.pw >= 24 * 12 ? 2 : 1;
  for (std::size_t c = 0; c < run.size(); ++c) {
    const ComparisonRow& r = *run[c];
    const int ox = kGap + static_cast<int>(c % l.columns) * (l.pw + kGap);
    const int cell_y = kGap + static_cast<int>(c / l.columns) * (3 * (kLabel + l.ph) + 3 * kGap);
    for (int k = 0; k < 3; ++k) {
      const std::vector<std::uint8_t> pic =
          k == 2 ? overdrawPicture(r.frame, most) : picture(r.frame, kKinds[k]);
      const int oy = cell_y + k * (kLabel + l.ph + kGap);
      char label[128];
      if (k == 0)
        std::snprintf(label, sizeof label, "%s %.1f MS", r.algorithm.c_str(), r.ms);
      else if (k == 1)
        std::snprintf(label, sizeof label, "IDS %.3f%% = ZBUFFER", 100.0 * r.id_agreement);
      else
        std::snprintf(label, sizeof label, "OVERDRAW MEAN %.2f MAX %u", r.mean_overdraw,
                      r.max_overdraw);
      drawLabel(sheet, *width, *height, ox, oy + 4, label, label_scale);
      for (int y = 0; y < l.ph; ++y)
        for (int x = 0; x < l.pw; ++x)
          std::copy_n(&pic[3 * (static_cast<std::size_t>(y) * l.step * fw +
                                static_cast<std::size_t>(x) * l.step)],
                      3, &sheet[3 * (static_cast<std::size_t>(oy + kLabel + y) * *width + ox + x)]);
    }
  }
  // The legend: the overdraw ramp shared by every cell, and how the ids are coloured
  const int ly = *height - kLegend + 4;
  char legend[160];
  std::snprintf(legend, sizeof legend,
                "OVERDRAW, ONE SCALE FOR EVERY ALGORITHM: 1 ... %u FRAGMENTS (LOG)",
                std::max(most, 1u));
  drawLabel(sheet, *width, *height, kGap, ly, legend, 1);
  const int ramp_w = std::min(256, *width - 2 * kGap);
  for (int i = 0; i < ramp_w; ++i) {
    std::uint8_t rgb[3];
    overdrawRampColor(static_cast<float>(i) / std::max(ramp_w - 1, 1), rgb);
    for (int y = ly + 12; y < ly + 22; ++y)
      std::copy_n(rgb, 3, &sheet[3 * (static_cast<std::size_t>(y) * *width + kGap + i)]);
  }
  drawLabel(sheet, *width, *height, kGap, ly + 28, "IDS: ONE COLOUR PER POLYGON, BLACK WHERE NONE",
            1);
  if (l.step > 1) {
    std::snprintf(legend, sizeof legend, "SHOWN AT 1/%d SIZE", l.step);
    drawLabel(sheet, *width, *height, kGap + ramp_w + 16, ly + 12, legend, 1);
  }
  return sheet;
}

}  // namespace hsr
