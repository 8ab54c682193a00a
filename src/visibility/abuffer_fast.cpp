// The A-buffer reorganised for cores: the same frame as abuffer.cpp (Carpenter 1984; the notes'
// loop, one list per pixel of the whole frame on one core), bit for bit in colour, coverage, ids
// and depth, made faster and smaller in three ways:
//   - tiles: the screen is cut into 64x64 tiles done one after another per core (bin the
//     triangles, fill the tile's lists, resolve them), so fragment memory is one tile's lists
//     per core;
//   - hidden fragments never listed: a fragment wholly behind an opaque polygon that already
//     covers the whole pixel can never show: it is not stored, and one that such a polygon comes
//     to cover leaves the list. As in Carpenter's paper, a pixel that one opaque polygon covers
//     wholly, in front of all else that reached it, holds that polygon itself and needs no list
//     (most pixels of a solid scene);
//   - pixels resolved at once where their samples cannot differ: fragments that share no sample
//     (an edge between neighbours), or whose depth ranges over the pixel lie apart, give each
//     sample what the sample-by-sample resolve (abuffer_lists.hpp) would.
// The overdraw buffer counts the fragments a pixel's list kept, so it is smaller here where
// hidden fragments were never listed.
//
// Guarantee: the colour, coverage, id and depth buffers equal abuffer-textbook's bit for bit
// (tests/cross/textbook_test.cpp), and so at any thread count. `hsr explain abuffer` walks
// abuffer.cpp. Cost: O(triangles + pixels reached + fragments x samples); memory 24 bytes a
// fragment in a list (a pixel's own polygon costs nothing more). A frame whose listed fragments
// would exceed RenderOptions::fragment_memory is refused.
//
// Tests: tests/visibility/abuffer_test.cpp and every suite of the registry its capabilities join.

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "core/frame.hpp"
#include "core/parallel.hpp"
#include "hsr/error.hpp"
#include "core/stopwatch.hpp"
#include "raster/bins.hpp"
#include "raster/edge.hpp"
#include "raster/fragment.hpp"
#include "raster/samples.hpp"
#include "visibility/abuffer_lists.hpp"
#include "visibility/algorithm.hpp"

namespace hsr::detail {
namespace {

inline constexpr std::uint32_t kNoneHeld = 0xFFFFFFFFu;

// One core's lists for the tile it is on.
struct TileLists {
  std::vector<std::uint32_t> head;  // per pixel of the tile, its list's first fragment
  // Per pixel: the opaque polygon that covers it wholly and lies in front of everything else
  // that reached it when it came (kNoneHeld if none), and its nearest depth in the pixel. It
  // is the pixel's fragment without a list; polygons that come later and lie in front of it
  // in part are listed beside it
  std::vector<std::uint32_t> whole;
  std::vector<float> whole_nearest;
  // Per pixel: the far end of the depth range of the nearest opaque fragment that covers the
  // whole pixel (every sample and the centre), +infinity while there is none: whatever lies
  // wholly behind it never shows
  std::vector<double> covered_to;
  std::vector<Fragment> pool;
  std::vector<std::uint32_t> free;  // pool entries dropped from their lists, to be reused
};

// A polygon's depth over a pixel square, as doubles (empty, lo > hi, where not known).
struct DepthRange {
  double lo, hi;
};
// Whether a fragment that lies no nearer than `nearest` anywhere in a pixel is wholly behind
// the opaque polygon that covers the pixel up to `covered_to`: at every sample and at the
// centre that the fragment covers, the polygon's float depth is smaller. (Where the fragment
// covers a sample its depth is at most 1, as the pipeline clips at the far plane; so the
// covering polygon's is below 1 there by the gap, and clamping cannot make them tie.)
bool behind(double nearest, double covered_to) { return covered_to + kSafeDepthGap < nearest; }
// A range's near end as a float no larger (-infinity for an empty range: never behind).
float nearestOf(const DepthRange& r) {
  if (!(r.lo <= r.hi)) return -INFINITY;
  // Within [-1, 1] a float is within 2^-25 of the double, so 2^-22 less is surely no larger
  if (std::abs(r.lo) < 1.0) return static_cast<float>(r.lo - 0x1p-22);
  const float f = static_cast<float>(r.lo);
  return static_cast<double>(f) > r.lo ? std::nextafter(f, -INFINITY) : f;
}

struct Scratch {
  Bins bins;
  std::vector<std::size_t> counts;
  std::vector<std::uint32_t> polygon_of;
  tbb::enumerable_thread_specific<TileLists> lists;
};

// What the whole frame shares while its tiles are drawn.
struct FrameJob {
  const ScreenTriangles& tris;
  const std::vector<std::uint32_t>& polygon_of;
  const Bins& bins;
  const SamplePattern& pattern;
  const FrameView& fb;
  float* coverage;
  std::uint64_t fragment_limit;           // fragments the memory budget allows
  std::atomic<std::uint64_t>& fragments;  // fragments made so far, all tiles
};

// Counts fragments against the budget every so often (the total, and so the verdict, does not
// depend on how tiles were shared between cores).
constexpr std::uint64_t kCountEvery = 4096;

void countFragments(const FrameJob& job, std::uint64_t n) {
  const std::uint64_t total = job.fragments.fetch_add(n) + n;
  if (total > job.fragment_limit) throw Error(fragmentBudgetMessage(job.fragment_limit));
}

// Takes out of the list that starts at `link` every fragment wholly behind depth `covered_to` at
// pixel (x, y); returns one of them for the caller to reuse (the others go to the free list),
// or kEndOfList.
std::uint32_t dropBehind(TileLists& l, std::uint32_t& link, double covered_to) {
  std::uint32_t kept = kEndOfList;
  for (std::uint32_t* next = &link; *next != kEndOfList;) {
    const std::uint32_t g = *next;
    if (!behind(l.pool[g].nearest, covered_to)) {
      next = &l.pool[g].next;
      continue;
    }
    *next = l.pool[g].next;
    if (kept == kEndOfList)
      kept = g;
    else
      l.free.push_back(g);
  }
  return kept;
}

// A triangle's depth over the pixel squares of a box: its plane's value at each centre, less and
// plus half its change across a pixel. Empty (lo > hi) where the plane is too steep or too far
// for planeDepth to be trusted to the gap (raster/depth.hpp); the terms are largest at the box's
// corners, so those are checked once.
struct DepthRanges {
  const DepthPlane& plane;
  double half;
  bool safe;
  DepthRanges(const DepthPlane& p, int x0, int y0, int x1, int y1)
      : plane(p),
        half(0.5 * (std::abs(p.dzdx) + std::abs(p.dzdy))),
        safe(planeDepthIsSafe(p, x0, y0) && planeDepthIsSafe(p, x1, y0) &&
             planeDepthIsSafe(p, x0, y1) && planeDepthIsSafe(p, x1, y1)) {}
  DepthRange at(double row_start, int x) const {
    if (!safe) return {1.0, 0.0};
    const double centre = row_start + plane.dzdx * static_cast<double>(x);
    return {centre - half, centre + half};
  }
};

// Rows of fewer pixels than this are tested pixel by pixel throughout.
constexpr int kShortRow = 8;

// From pixel x to at most x_end of a row (the tile's pixels from row_at on), inside every
// sample of an opaque polygon whose depth ranges are safe: while a pixel holds no list and no
// polygon (or one wholly behind), it comes to hold this polygon whole. Returns the first pixel
// it stopped at (x_end + 1 when none).
int holdWhole(TileLists& l, const DepthRanges& ranges, double row_start, std::size_t row_at, int x0,
              std::uint32_t polygon, int x, int x_end, std::uint64_t& written) {
  const std::uint32_t* head = l.head.data() + row_at;
  std::uint32_t* whole = l.whole.data() + row_at;
  float* whole_nearest = l.whole_nearest.data() + row_at;
  double* covered_to = l.covered_to.data() + row_at;
  const int first = x;
  for (; x <= x_end; ++x) {
    const int p = x - x0;  // in the tile's row
    if (head[p] != kEndOfList || whole[p] == polygon) break;
    const DepthRange r = ranges.at(row_start, x);
    if (!(r.hi < covered_to[p]) || (whole[p] != kNoneHeld && !behind(whole_nearest[p], r.hi)))
      break;
    covered_to[p] = r.hi;
    whole[p] = polygon;
    whole_nearest[p] = nearestOf(r);
  }
  written += static_cast<std::uint64_t>(x - first);
  return x;
}

// Step 1, for one tile: every polygon's fragments, pixel by pixel.
void fillLists(const FrameJob& job, std::size_t tile, const PixelBox& box, TileLists& l,
               FragmentCounts& counts) {
  const int tile_w = box.x1 - box.x0 + 1;
  const std::size_t tile_pixels = static_cast<std::size_t>(tile_w) * (box.y1 - box.y0 + 1);
  l.head.assign(tile_pixels, kEndOfList);
  l.whole.assign(tile_pixels, kNoneHeld);
  l.whole_nearest.resize(tile_pixels);
  l.covered_to.assign(tile_pixels, INFINITY);
  l.pool.clear();
  l.free.clear();
  const std::uint64_t all = allSamples(job.pattern.count);
  std::uint64_t uncounted = 0, tested = 0, written = 0;
  SampleEdges samples;
  for (std::size_t k = job.bins.start[tile]; k < job.bins.start[tile + 1]; ++k) {
    const std::uint32_t i = job.bins.items[k];
    const ScreenTriangle& t = job.tris[i];
    const std::uint32_t polygon = job.polygon_of[i];
    const bool opaque = !t.transparent();
    const int y0 = std::max(box.y0, static_cast<int>(t.y0)),
              y1 = std::min(box.y1, static_cast<int>(t.y1));
    const int x0 = std::max(box.x0, static_cast<int>(t.x0)),
              x1 = std::min(box.x1, static_cast<int>(t.x1));
    if (y0 > y1 || x0 > x1) continue;
    TriangleSetup s = setupTriangle(t, y0);
    setupSampleEdges(s, job.pattern, &samples);
    // The pixels of a row it may reach: inside every edge moved out by the farthest sample (or
    // the centre), found per row exactly as a span is (a sliver across the screen reaches few)
    TriangleSetup reach = s;
    for (int j = 0; j < 3; ++j) reach.edge[j].row += std::max<std::int64_t>(samples.highest[j], 0);
    // And where every sample and the centre are inside: the edges moved in by the nearest sample
    TriangleSetup inner = s;
    for (int j = 0; j < 3; ++j) inner.edge[j].row += std::min<std::int64_t>(samples.lowest[j], 0);
    const DepthRanges ranges(t.depth, x0, y0, x1, y1);
    const bool quick = opaque && ranges.safe;
    for (int y = y0; y <= y1; ++y, nextRow(s), nextRow(reach), nextRow(inner)) {
      int lo = x0, hi = x1;
      if (!spanOfRow(reach, &lo, &hi)) continue;
      tested += static_cast<std::uint64_t>(hi - lo + 1);
      const double row_start = depthRowStart(t.depth, y);
      // the row's first pixel in the tile
      const std::size_t row_at = static_cast<std::size_t>(y - box.y0) * tile_w;

      // Where every sample and the centre are inside (a row of a few pixels is not worth
      // finding it for)
      int in_lo = lo, in_hi = hi;
      if (hi - lo < kShortRow || !spanOfRow(inner, &in_lo, &in_hi)) in_lo = hi + 1, in_hi = hi;
      // The edge functions at pixel x's centre
      auto edgesAt = [&](int x, std::int64_t e[3]) {
        for (int j = 0; j < 3; ++j) e[j] = s.edge[j].row + s.edge[j].step_x * x;
      };
      for (int x = lo; x <= hi; ++x) {
        // The common case, inside an opaque polygon: a run of pixels it covers whole, in front
        // of all that reached them before, each holding it (as the steps below would decide)
        if (quick && x >= in_lo && x <= in_hi) {
          x = holdWhole(l, ranges, row_start, row_at, box.x0, polygon, x, in_hi, written);
          if (x > in_hi) {
            x = in_hi;
            continue;
          }
        }
        const std::size_t at = row_at + static_cast<std::size_t>(x - box.x0);
        std::uint32_t& head = l.head[at];
        // The samples it covers, and whether it covers the centre
        const bool inside = x >= in_lo && x <= in_hi;
        std::int64_t e[3];
        edgesAt(x, e);
        const bool centre = inside || (e[0] | e[1] | e[2]) >= 0;
        const std::uint64_t mask = inside ? all : sampleMask(samples, e);
        if (mask == 0 && !centre) continue;
        // The polygon the pixel holds wholly: these samples are its already
        if (l.whole[at] == polygon) continue;
        // Another triangle of the polygon already listed here (its triangles come one after
        // another): its fragment takes these samples too, and may now cover the whole pixel
        if (head != kEndOfList && l.pool[head].polygon == polygon) {
          Fragment& h = l.pool[head];
          h.mask |= mask;
          h.centre = h.centre || centre;
          if (opaque && h.mask == all && h.centre) {
            const DepthRange r = ranges.at(row_start, x);
            if (r.lo <= r.hi && r.hi < l.covered_to[at]) {
              l.covered_to[at] = r.hi;
              const std::uint32_t dropped = dropBehind(l, h.next, r.hi);
              if (dropped != kEndOfList) l.free.push_back(dropped);
              if (l.whole[at] != kNoneHeld && behind(l.whole_nearest[at], r.hi))
                l.whole[at] = kNoneHeld;
            }
          }
          continue;
        }
        // Hidden wherever it lies: behind a polygon drawn before that covers the whole pixel
        const DepthRange r = ranges.at(row_start, x);
        if (r.lo <= r.hi && behind(r.lo, l.covered_to[at])) continue;
        // Opaque over the whole pixel: what lies wholly behind it leaves the pixel first (and
        // the new fragment takes the place of one of those); in front of all of it, the pixel
        // holds the polygon itself
        std::uint32_t f = kEndOfList;
        if (opaque && mask == all && centre && r.lo <= r.hi && r.hi < l.covered_to[at]) {
          l.covered_to[at] = r.hi;
          if (l.whole[at] != kNoneHeld && behind(l.whole_nearest[at], r.hi))
            l.whole[at] = kNoneHeld;
          if (head != kEndOfList) f = dropBehind(l, head, r.hi);
          if (head == kEndOfList && l.whole[at] == kNoneHeld) {
            l.whole[at] = polygon;
            l.whole_nearest[at] = nearestOf(r);
            if (f != kEndOfList) l.free.push_back(f);
            ++written;
            continue;
          }
        }
        if (f == kEndOfList && !l.free.empty()) {
          f = l.free.back();
          l.free.pop_back();
        } else if (f == kEndOfList) {
          f = static_cast<std::uint32_t>(l.pool.size());
          l.pool.emplace_back();
          if (++uncounted == kCountEvery) countFragments(job, uncounted), uncounted = 0;
        }
        l.pool[f] = {mask, nearestOf(r), polygon, head, centre};
        head = f;
        ++written;
      }
    }
  }
  countFragments(job, uncounted);
  counts.tested += tested;
  counts.written += written;
}

// A pixel's fragments: its list's, then the polygon it holds wholly (made a fragment over every
// sample in `whole`).
void gatherPixel(const TileLists& l, std::size_t at, std::uint64_t all, Fragment& whole,
                 std::vector<const Fragment*>& out) {
  out.clear();
  for (std::uint32_t f = l.head[at]; f != kEndOfList; f = l.pool[f].next) out.push_back(&l.pool[f]);
  whole = {all, l.whole_nearest[at], l.whole[at], kEndOfList, true};
  if (whole.polygon != kNoneHeld) out.push_back(&whole);
}

// Every sample of pixel (x, y) resolves alike when each fragment covers them all and their depth
// ranges over the pixel are apart (each wholly behind the next by the safe gap): they lie in the
// same order at every sample (see-through layers over a pixel, say). Then the one colour they
// all resolve to is the nearest opaque fragment's (or the background) with the see-through ones
// in front of it laid over it, farthest first, as resolveSample() would find at each; returns
// false when they do not resolve alike.
bool resolveAlike(const FrameJob& job, const std::vector<const Fragment*>& list, int x, int y,
                  std::uint32_t background, std::uint32_t* colour) {
  const std::uint64_t all = allSamples(job.pattern.count);
  thread_local std::vector<std::pair<DepthRange, const Fragment*>> order;
  order.clear();
  for (const Fragment* f : list) {
    if (f->mask != all) return false;
    const DepthPlane& plane = job.tris[f->polygon].depth;
    const DepthRange r = DepthRanges(plane, x, y, x, y).at(depthRowStart(plane, y), x);
    if (!(r.lo <= r.hi)) return false;
    order.push_back({r, f});
  }
  std::sort(order.begin(), order.end(),
            [](const auto& a, const auto& b) { return a.first.lo < b.first.lo; });
  for (std::size_t i = 1; i < order.size(); ++i)
    if (!behind(order[i].first.lo, order[i - 1].first.hi)) return false;
  // Nearest first: up to the first opaque one, then back out over the see-through ones
  std::size_t opaque = 0;
  while (opaque < order.size() && job.tris[order[opaque].second->polygon].transparent()) ++opaque;
  std::uint32_t c =
      opaque < order.size() ? job.tris[order[opaque].second->polygon].rgba : background;
  for (std::size_t i = opaque; i-- > 0;) c = blendOver(job.tris[order[i].second->polygon].rgba, c);
  *colour = c;
  return true;
}

// Step 2, for one pixel: its list resolved into colour (the mean of its samples), and the
// nearest opaque fragment at the centre into id and depth.
void resolvePixel(const FrameJob& job, const TileLists& l, std::size_t at, int x, int y) {
  const std::size_t idx = job.fb.index(x, y);
  const SamplePattern& p = job.pattern;
  const std::uint64_t all = allSamples(p.count);
  // Gather the list (it is short: the polygons that reach this pixel), with the polygon the
  // pixel holds wholly
  thread_local std::vector<const Fragment*> list;
  Fragment whole;
  gatherPixel(l, at, all, whole, list);
  job.fb.overdraw[idx] = static_cast<std::uint32_t>(list.size());
  if (list.empty()) return;
  auto opaque = [&](const Fragment* f) { return !job.tris[f->polygon].transparent(); };
  auto colour = [&](const Fragment* f) { return job.tris[f->polygon].rgba; };

  // Id and depth: the nearest opaque fragment covering the centre
  const Fragment* at_centre = nullptr;
  float centre_z = 0;
  std::uint64_t opaque_mask = 0;
  for (const Fragment* f : list) {
    if (!opaque(f)) continue;
    opaque_mask |= f->mask;
    if (!f->centre) continue;
    const float z = fragmentDepth(job.tris[f->polygon].depth, x, y);
    if (!at_centre || inFront(z, *f, centre_z, *at_centre)) at_centre = f, centre_z = z;
  }
  if (at_centre) {
    job.fb.depth[idx] = centre_z;
    job.fb.ids[idx] = job.tris[at_centre->polygon].id;
  }
  if (job.coverage)
    job.coverage[idx] =
        static_cast<float>(std::popcount(opaque_mask)) / static_cast<float>(p.count);

  // Colour, sample by sample
  const std::uint32_t background = job.fb.rgba[idx];
  if (list.size() == 1 && opaque(list[0]) &&
      list[0]->mask == all) {  // one polygon over all samples
    job.fb.rgba[idx] = colour(list[0]);
    return;
  }
  std::uint32_t sum[3] = {0, 0, 0};
  auto add = [&](std::uint32_t c, std::uint32_t samples) {
    for (int ch = 0; ch < 3; ++ch) sum[ch] += ((c >> (8 * ch)) & 0xFFu) * samples;
  };
  // Opaque fragments that share no sample (a pixel that an edge between neighbours crosses):
  // each sample is the colour of the one that covers it, or the background
  std::uint64_t covered = 0;
  bool shared = false;
  for (const Fragment* f : list) {
    shared = shared || !opaque(f) || (f->mask & covered) != 0;
    covered |= f->mask;
  }
  if (!shared) {
    for (const Fragment* f : list)
      add(colour(f), static_cast<std::uint32_t>(std::popcount(f->mask)));
    add(background, static_cast<std::uint32_t>(p.count - std::popcount(covered)));
  } else if (std::uint32_t c; resolveAlike(job, list, x, y, background, &c)) {
    add(c, static_cast<std::uint32_t>(p.count));
  } else {
    for (int s = 0; s < p.count; ++s)
      add(resolveSample(job.tris, job.pattern, list, x, y, s, background).colour, 1);
  }
  // The mean of the samples, rounded to nearest
  job.fb.rgba[idx] = meanOfSamples(sum, p.count);
}

void resolveTile(const FrameJob& job, const PixelBox& box, const TileLists& l) {
  const int tile_w = box.x1 - box.x0 + 1;
  for (int y = box.y0; y <= box.y1; ++y)
    for (int x = box.x0; x <= box.x1; ++x) {
      const std::size_t at = static_cast<std::size_t>(y - box.y0) * tile_w + (x - box.x0);
      if (l.head[at] != kEndOfList) {
        resolvePixel(job, l, at, x, y);
        continue;
      }
      // A pixel that nothing reached, or that holds one polygon and no list: that polygon's
      const std::size_t idx = job.fb.index(x, y);
      job.fb.overdraw[idx] = l.whole[at] == kNoneHeld ? 0 : 1;
      if (l.whole[at] == kNoneHeld) continue;
      const ScreenTriangle& t = job.tris[l.whole[at]];
      job.fb.depth[idx] = fragmentDepth(t.depth, x, y);
      job.fb.ids[idx] = t.id;
      job.fb.rgba[idx] = t.rgba;
      if (job.coverage) job.coverage[idx] = 1.0f;
    }
}

}  // namespace

void drawABuffer(const AlgorithmInput& in, Frame& frame) {
  detail::Stopwatch t0;
  auto lap = [&](const char* stage) { frame.stats.addStage(stage, t0.lap()); };
  std::unique_ptr<Scratch> own;
  Scratch& scratch = algorithmScratch(in, own);
  const ScreenTriangles& tris = in.prepared.triangles;
  const SamplePattern& pattern =
      samplePattern(in.options.samples == 0 ? kABufferDefaultSamples : in.options.samples);

  // Bin: each triangle listed in every tile it reaches (its box reaches every sample)
  numberPolygons(tris, scratch.polygon_of);
  binPrimitives(std::span<const ScreenTriangle>(tris.data(), tris.size()), frame.width,
                frame.height, scratch.bins, scratch.counts);
  lap("bin");

  // Fill and resolve each tile's lists, tiles in parallel
  frame.coverage.assign(frame.color.size(), 0.0f);
  const FrameView fb(frame);
  std::atomic<std::uint64_t> fragments{0};
  const FrameJob job{tris,
                     scratch.polygon_of,
                     scratch.bins,
                     pattern,
                     fb,
                     frame.coverage.data(),
                     in.options.fragment_memory / sizeof(Fragment),
                     fragments};
  tbb::enumerable_thread_specific<FragmentCounts> counts;
  const std::size_t tiles = scratch.bins.tiles();
  tbb::parallel_for(std::size_t(0), tiles, [&](std::size_t tile) {
    const PixelBox box = scratch.bins.tileBox(tile, frame.width, frame.height);
    TileLists& lists = scratch.lists.local();
    fillLists(job, tile, box, lists, counts.local());
    resolveTile(job, box, lists);
  });
  lap("fill and resolve");

  FragmentCounts total;
  for (const FragmentCounts& c : counts) total += c;
  frame.stats.fragments_tested += total.tested;
  frame.stats.fragments_written += total.written;
  // What the memory budget counts: fragments stored (a dropped fragment's place is reused)
  frame.stats.addCounter("abuffer: fragments stored", fragments.load());
  frame.stats.addCounter("abuffer: samples", static_cast<std::uint64_t>(pattern.count));
  std::uint64_t pools = 0;
  for (const TileLists& l : scratch.lists)
    pools += l.pool.capacity() * sizeof(Fragment) + l.head.capacity() * 4 + l.whole.capacity() * 4 +
             l.whole_nearest.capacity() * 4 + l.covered_to.capacity() * 8;
  frame.stats.state_bytes += frameBufferBytes(frame) + tris.capacity() * sizeof(ScreenTriangle) +
                             scratch.bins.bytes() + scratch.polygon_of.capacity() * 4 + pools;
}

}  // namespace hsr::detail
