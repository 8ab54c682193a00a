// The A-buffer, as the notes teach it (Carpenter 1984, "The A-buffer, an antialiased hidden
// surface method"; the notes' "A-buffer").
//
// The z-buffer keeps one surface per pixel, so its edges are jagged (a pixel is all one polygon
// or all another) and a see-through polygon must be drawn after everything behind it. The
// A-buffer keeps, per pixel, a list of fragments: for each polygon that reaches the pixel,
// which of the pixel's sub-pixel samples it covers (a bit mask), its depth, its colour and
// opacity. Nothing is decided while polygons are drawn; when all are in, each pixel's list is
// resolved:
//
//     for all polygons P, in any order:
//       for all pixels (i, j) P reaches:
//         add to list[i, j]: (P's id, mask of the samples P covers, depth, colour, alpha)
//     for all pixels (i, j):
//       for each sample s:  the fragments covering s, nearest first; an opaque one hides
//                           everything behind it; the see-through ones in front of it are
//                           laid over it, farthest first
//       Image[i, j] = the mean of its samples' colours
//
// So edges are antialiased (a pixel half covered by a red polygon over white comes out pink)
// and transparency is right whatever order the polygons come in. hsr's fragments:
//   - coverage: the shared exact edge setup and fill rule evaluated at each sample
//     (raster/samples.hpp: Direct3D's 4x pattern and its kin), so polygons that share an edge
//     cover each of its samples exactly once;
//   - depth: THE depth definition (raster/depth.hpp) at the pixel centre, and at each sample
//     where the resolve compares two fragments there;
//   - one fragment per polygon and pixel: the triangles the pipeline cut a polygon into add
//     their masks to the polygon's fragment.
// Ids and depth are the nearest opaque fragment covering the pixel centre (ties to the
// polygon drawn first, as the z-buffer's LESS), so they equal the z-buffer's whatever the
// samples; with one sample (the centre) and opaque polygons the colour does too.
//
// This file is that loop on one core, one list per pixel of the whole frame, to be read beside
// the notes. The renderer registered as "abuffer" (abuffer_fast.cpp) is the same in tiles on
// all cores, never listing a fragment that cannot show; tests/cross/textbook_test.cpp proves
// the two equal bit for bit.
//
// Cost: O(triangles + pixels reached + fragments x samples); memory 24 bytes a fragment and 4 a
// pixel. A frame whose fragments would exceed RenderOptions::fragment_memory is refused.
//
// Tests: tests/visibility/abuffer_test.cpp and every suite of the registry its capabilities join.

#include <bit>
#include <cstdio>
#include <string>
#include <vector>

#include "core/frame.hpp"
#include "core/stopwatch.hpp"
#include "hsr/error.hpp"
#include "raster/edge.hpp"
#include "raster/fragment.hpp"
#include "raster/samples.hpp"
#include "visibility/abuffer_lists.hpp"
#include "visibility/algorithm.hpp"

namespace hsr::detail {
namespace {

// Step names: what `hsr explain abuffer-textbook` (and `hsr explain abuffer`) shows.
constexpr std::string_view kStepPolygon = "add polygon";
constexpr std::string_view kStepPixel = "one pixel's list";
constexpr std::string_view kStepMagnified = "one pixel magnified";
constexpr std::string_view kStepDone = "done";

// The lists of every pixel: each pixel's first fragment, the fragments linked through `next`.
struct Lists {
  std::vector<std::uint32_t> head;
  std::vector<Fragment> pool;
  std::vector<const Fragment*> of(std::size_t pixel) const {
    std::vector<const Fragment*> out;
    for (std::uint32_t f = head[pixel]; f != kEndOfList; f = pool[f].next) out.push_back(&pool[f]);
    return out;
  }
};

}  // namespace

void drawABufferTextbook(const AlgorithmInput& in, Frame& frame) {
  detail::Stopwatch t0;
  const ScreenTriangles& tris = in.prepared.triangles;
  const SamplePattern& pattern =
      samplePattern(in.options.samples == 0 ? kABufferDefaultSamples : in.options.samples);
  const std::uint64_t fragment_limit = in.options.fragment_memory / sizeof(Fragment);
  const FrameView fb(frame);
  std::vector<std::uint32_t> polygon_of;  // each triangle's polygon: its first triangle
  const std::uint64_t polygons = numberPolygons(tris, polygon_of);
  Lists lists;
  lists.head.assign(frame.color.size(), kEndOfList);
  FragmentCounts counts;

  // For all polygons P (their triangles, one after another), for all pixels P reaches: add P's
  // fragment to the pixel's list, or its samples to the fragment P already has there.
  std::uint64_t polygon = 0;
  for (std::size_t first = 0; first < tris.size();) {
    std::size_t last = first + 1;
    while (last < tris.size() && polygon_of[last] == polygon_of[first]) ++last;
    const std::uint64_t before = lists.pool.size();
    for (std::size_t i = first; i < last; ++i) {
      const ScreenTriangle& t = tris[i];
      TriangleSetup s = setupTriangle(t, t.y0);
      SampleEdges samples;
      setupSampleEdges(s, pattern, &samples);
      // The pixels of a row it may reach: inside every edge moved out by the farthest sample
      TriangleSetup reach = s;
      for (int j = 0; j < 3; ++j)
        reach.edge[j].row += std::max<std::int64_t>(samples.highest[j], 0);
      for (int y = t.y0; y <= t.y1; ++y, nextRow(s), nextRow(reach)) {
        int lo = t.x0, hi = t.x1;
        if (!spanOfRow(reach, &lo, &hi)) continue;
        counts.tested += static_cast<std::uint64_t>(hi - lo + 1);
        for (int x = lo; x <= hi; ++x) {
          // The samples it covers (the edge functions at each), and whether it covers the centre
          std::int64_t e[3];
          for (int j = 0; j < 3; ++j) e[j] = s.edge[j].row + s.edge[j].step_x * x;
          const bool centre = (e[0] | e[1] | e[2]) >= 0;
          const std::uint64_t mask = sampleMask(samples, e);
          if (mask == 0 && !centre) continue;
          std::uint32_t& head = lists.head[fb.index(x, y)];
          if (head != kEndOfList && lists.pool[head].polygon == polygon_of[first]) {
            Fragment& f = lists.pool[head];  // another triangle of P was here: the same fragment
            f.mask |= mask;
            f.centre = f.centre || centre;
            continue;
          }
          if (lists.pool.size() >= fragment_limit)
            throw Error(fragmentBudgetMessage(fragment_limit));
          lists.pool.push_back({mask, -INFINITY, polygon_of[first], head, centre});
          head = static_cast<std::uint32_t>(lists.pool.size() - 1);
          counts.written++;
        }
      }
    }
    if (in.trace && in.trace->wants(kStepPolygon, polygon, polygons)) {
      std::vector<TraceOutline> outlines;
      for (std::size_t i = first; i < last; ++i) {
        TraceOutline o;
        for (int k = 0; k < 3; ++k)
          o.emplace_back(tris[i].x[k] / float(kSubpixelOne), tris[i].y[k] / float(kSubpixelOne));
        outlines.push_back(std::move(o));
      }
      in.trace->record({kStepPolygon,
                        "Polygon " + std::to_string(polygon + 1) + " of " +
                            std::to_string(polygons) + " (id " + std::to_string(tris[first].id) +
                            "): a fragment added to the list of each of the " +
                            std::to_string(lists.pool.size() - before) +
                            " pixels it reaches (which of the " + std::to_string(pattern.count) +
                            " samples it covers, its depth, colour and opacity). Nothing is "
                            "decided yet: the picture stays as it was cleared.",
                        &frame, std::move(outlines)});
    }
    ++polygon;
    first = last;
  }
  frame.stats.addStage("fill lists", t0.lap());

  // The pixel with the longest list, for the teaching view, before the resolve paints over it
  std::size_t longest = 0, longest_n = 0;
  if (in.trace)
    for (std::size_t k = 0; k < lists.head.size(); ++k)
      if (const std::size_t n = lists.of(k).size(); n > longest_n) longest = k, longest_n = n;
  const int lx = static_cast<int>(longest % frame.width),
            ly = static_cast<int>(longest / frame.width);
  const std::uint32_t longest_background = fb.rgba[longest];

  // For all pixels: the list resolved. Id and depth: the nearest opaque fragment covering the
  // centre; coverage: the samples opaque fragments cover; colour: the mean of the samples'.
  frame.coverage.assign(frame.color.size(), 0.0f);
  for (int y = 0; y < frame.height; ++y)
    for (int x = 0; x < frame.width; ++x) {
      const std::size_t k = fb.index(x, y);
      const std::vector<const Fragment*> list = lists.of(k);
      fb.overdraw[k] = static_cast<std::uint32_t>(list.size());
      if (list.empty()) continue;  // the background: render() has cleared it
      float z = 0;
      if (const Fragment* f = nearestAtCentre(tris, list, x, y, &z)) {
        fb.depth[k] = z;
        fb.ids[k] = tris[f->polygon].id;
      }
      std::uint64_t opaque_mask = 0;
      for (const Fragment* f : list)
        if (!tris[f->polygon].transparent()) opaque_mask |= f->mask;
      frame.coverage[k] =
          static_cast<float>(std::popcount(opaque_mask)) / static_cast<float>(pattern.count);
      std::uint32_t sum[3] = {0, 0, 0};
      for (int s = 0; s < pattern.count; ++s) {
        const std::uint32_t c = resolveSample(tris, pattern, list, x, y, s, fb.rgba[k]).colour;
        for (int ch = 0; ch < 3; ++ch) sum[ch] += (c >> (8 * ch)) & 0xFFu;
      }
      fb.rgba[k] = meanOfSamples(sum, pattern.count);
    }
  frame.stats.addStage("resolve", t0.lap());

  if (in.trace && longest_n > 0) {
    const std::vector<const Fragment*> list = lists.of(longest);
    if (in.trace->wants(kStepPixel, 0, 1))
      in.trace->record({kStepPixel,
                        describeList(tris, pattern, list, lx, ly),
                        &frame,
                        {pixelBoxOutline(PixelBox{lx - 3, ly - 3, lx + 3, ly + 3})}});
    if (in.trace->wants(kStepMagnified, 0, 1)) {
      TracePixel close;
      const std::uint32_t mean =
          closeUp(tris, polygon_of, pattern, list, lx, ly, longest_background, close);
      char hex[8];
      std::snprintf(hex, sizeof hex, "#%02x%02x%02x", mean & 0xFFu, (mean >> 8) & 0xFFu,
                    (mean >> 16) & 0xFFu);
      in.trace->record(
          {kStepMagnified,
           "Pixel (" + std::to_string(lx) + ", " + std::to_string(ly) +
               ") magnified: the lines are the true edges of the triangles of the " +
               std::to_string(list.size()) + " polygons listed there, the squares its " +
               std::to_string(pattern.count) +
               " samples; each point shows what the sample nearest it resolves to (the nearest "
               "opaque fragment covering it, see-through ones laid over it) and that fragment's "
               "depth. The pixel's colour is the mean of its samples: " +
               hex + ".",
           &frame,
           {},
           nullptr,
           &close});
    }
  }
  if (in.trace && in.trace->wants(kStepDone, 0, 1))
    in.trace->record(
        {kStepDone,
         "Done: every pixel's list resolved. Edges antialiased (a pixel an edge crosses shows the "
         "mean of its samples), see-through polygons blended in depth order whatever order they "
         "came in; ids and depth are the nearest opaque polygon at each pixel centre, as the "
         "z-buffer's.",
         &frame,
         {}});

  frame.stats.fragments_tested += counts.tested;
  frame.stats.fragments_written += counts.written;
  frame.stats.addCounter("abuffer: fragments stored", lists.pool.size());
  frame.stats.addCounter("abuffer: samples", static_cast<std::uint64_t>(pattern.count));
  frame.stats.state_bytes += frameBufferBytes(frame) + lists.pool.capacity() * sizeof(Fragment) +
                             lists.head.capacity() * 4 + polygon_of.capacity() * 4;
}

}  // namespace hsr::detail
