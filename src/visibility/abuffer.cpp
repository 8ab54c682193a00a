// The A-buffer (Carpenter 1984, "The A-buffer, an antialiased hidden surface method"; the
// notes' "A-buffer").
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
// A fragment wholly behind an opaque polygon that already covers the whole pixel can never
// show: it is not stored, and one that such a polygon comes to cover leaves the list. As in
// Carpenter's paper, a pixel that one opaque polygon covers wholly, in front of all else that
// reached it, holds that polygon itself and needs no list (most pixels of a solid scene).
//
// The screen is cut into 64x64 tiles done one after another per core (bin the triangles, fill
// the tile's lists, resolve them), so fragment memory is one tile's lists per core. Cost:
// O(triangles + pixels reached + fragments x samples); memory 24 bytes a fragment in a list (a
// pixel's own polygon costs nothing more). A frame whose listed fragments would exceed
// RenderOptions::fragment_memory is refused.
//
// Tests: tests/visibility/abuffer_test.cpp and every suite of the registry its capabilities join.

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdio>
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
#include "visibility/algorithm.hpp"

namespace hsr::detail {
namespace {

// Step names: what `hsr explain abuffer` shows.
constexpr std::string_view kStepBin = "bin";
constexpr std::string_view kStepTile = "fill and resolve tile";
constexpr std::string_view kStepPixel = "one pixel's list";
constexpr std::string_view kStepMagnified = "one pixel magnified";
constexpr std::string_view kStepDone = "done";

inline constexpr int kDefaultSamples = 4;
inline constexpr std::uint32_t kEndOfList = 0xFFFFFFFFu;
inline constexpr std::uint32_t kNoneHeld = 0xFFFFFFFFu;

// One polygon's share of one pixel. Its depth at the centre and at each sample comes from its
// polygon's plane (THE depth definition) when the list is resolved.
struct Fragment {
  std::uint64_t mask;     // the samples it covers
  float nearest;          // no nearer than this anywhere in the pixel (-infinity: not known)
  std::uint32_t polygon;  // its first triangle: plane, colour, alpha and id
  std::uint32_t next;     // the next fragment of the pixel's list, or kEndOfList
  bool centre;            // covers the pixel centre (by the fill rule, as the z-buffer)
};
static_assert(sizeof(Fragment) == 24, "24 bytes a fragment");

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
  if (total > job.fragment_limit)
    throw Error("abuffer: the frame needs more than " + std::to_string(job.fragment_limit) +
                " fragments (" + std::to_string(job.fragment_limit * sizeof(Fragment) >> 20) +
                " MiB of fragment memory at 24 bytes each); raise the fragment memory limit "
                "(--fragment-memory MIB) or draw fewer overlapping polygons");
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

// A fragment's depth at sample s of pixel (x, y).
float depthAtSample(const FrameJob& job, const Fragment& f, int x, int y, int s) {
  return sampleDepth(job.tris[f.polygon].depth, x, y, job.pattern.x[s], job.pattern.y[s]);
}

// Whether opaque fragment a hides b at a sample where they lie at depths za and zb: nearer, or
// as near and drawn first (the z-buffer's LESS keeps the first of equals).
bool inFront(float za, const Fragment& a, float zb, const Fragment& b) {
  return za < zb || (za == zb && a.polygon < b.polygon);
}

// What one sample of a pixel shows: its colour, and the depth of the nearest opaque fragment
// covering it (NaN where none does).
struct SampleResult {
  std::uint32_t colour;
  float depth;
  PolygonId id;  // the nearest opaque fragment's polygon (kNoPolygon where none)
};

// Step 2, for one sample of pixel (x, y) whose fragments are `list`.
SampleResult resolveSample(const FrameJob& job, const std::vector<const Fragment*>& list, int x,
                           int y, int s, std::uint32_t background) {
  auto opaque = [&](const Fragment* f) { return !job.tris[f->polygon].transparent(); };
  auto colour = [&](const Fragment* f) { return job.tris[f->polygon].rgba; };
  const std::uint64_t bit = std::uint64_t(1) << s;
  // The nearest opaque fragment covering the sample hides everything behind it
  const Fragment* nearest = nullptr;
  float nearest_z = 0;
  for (const Fragment* f : list) {
    if (!(f->mask & bit) || !opaque(f)) continue;
    const float z = depthAtSample(job, *f, x, y, s);
    if (!nearest || inFront(z, *f, nearest_z, *nearest)) nearest = f, nearest_z = z;
  }
  std::uint32_t c = nearest ? colour(nearest) : background;
  // The see-through ones nearer than it, laid over it farthest first (of equals, the one drawn
  // first goes under, as the z-buffer blends them)
  thread_local std::vector<std::pair<float, const Fragment*>> in_front;
  in_front.clear();
  for (const Fragment* f : list) {
    if (!(f->mask & bit) || opaque(f)) continue;
    const float z = depthAtSample(job, *f, x, y, s);
    if (!nearest || z < nearest_z) in_front.push_back({z, f});
  }
  std::sort(in_front.begin(), in_front.end(), [](const auto& a, const auto& b) {
    return a.first > b.first || (a.first == b.first && a.second->polygon < b.second->polygon);
  });
  for (const auto& [z, f] : in_front) c = blendOver(colour(f), c);
  return {c, nearest ? nearest_z : NAN, nearest ? job.tris[nearest->polygon].id : kNoPolygon};
}

// The mean of a pixel's samples from their channel sums, rounded to nearest (opaque). The sample
// counts are powers of two, so it divides by shifting.
std::uint32_t meanOfSamples(const std::uint32_t sum[3], int count) {
  const int shift = std::countr_zero(static_cast<unsigned>(count));
  std::uint32_t out = 0xFF000000u;
  for (int ch = 0; ch < 3; ++ch)
    out |= ((sum[ch] + static_cast<std::uint32_t>(count) / 2) >> shift) << (8 * ch);
  return out;
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
    for (int s = 0; s < p.count; ++s) add(resolveSample(job, list, x, y, s, background).colour, 1);
  }
  // The mean of the samples, rounded to nearest
  job.fb.rgba[idx] = meanOfSamples(sum, p.count);
}

// ---- the teaching view

// The pixel of a tile with the most fragments, and how many.
std::pair<std::size_t, int> longestList(const TileLists& l, std::uint64_t all) {
  std::pair<std::size_t, int> best{0, 0};
  std::vector<const Fragment*> list;
  Fragment whole;
  for (std::size_t at = 0; at < l.head.size(); ++at) {
    gatherPixel(l, at, all, whole, list);
    if (static_cast<int>(list.size()) > best.second) best = {at, static_cast<int>(list.size())};
  }
  return best;
}

// A pixel's fragments in words, before they are resolved: each one's polygon, opacity, samples
// covered (sample 0 first) and depth at the centre, nearest first.
std::string describeList(const FrameJob& job, const TileLists& l, std::size_t at, int x, int y) {
  std::vector<const Fragment*> fragments;
  Fragment whole;
  gatherPixel(l, at, allSamples(job.pattern.count), whole, fragments);
  std::vector<std::pair<float, const Fragment*>> list;
  for (const Fragment* f : fragments)
    list.push_back({fragmentDepth(job.tris[f->polygon].depth, x, y), f});
  std::sort(list.begin(), list.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::string s = "Pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") holds " +
                  std::to_string(list.size()) +
                  " fragments, one per polygon that reaches it, nearest first:";
  for (const auto& [z, f] : list) {
    const ScreenTriangle& t = job.tris[f->polygon];
    std::string bits;
    for (int i = 0; i < job.pattern.count; ++i) bits += (f->mask >> i) & 1 ? '1' : '0';
    char depth[32];
    std::snprintf(depth, sizeof depth, "%.6f", static_cast<double>(z));
    s += " polygon " + std::to_string(t.id) + " (" +
         (t.transparent() ? "alpha " + std::to_string(t.rgba >> 24) + "/255"
                          : std::string("opaque")) +
         "), samples " + bits + (f->centre ? " and the centre" : "") + ", depth " + depth +
         " at the centre" +
         (f == &whole ? " (covering the pixel in front of all that came before it, so held by the "
                        "pixel itself, "
                        "not listed)"
                      : "") +
         ";";
  }
  s += " Resolve: each sample takes the nearest opaque fragment covering it (or the background) "
       "with the "
       "see-through ones in front of it laid over it, farthest first; the pixel is the mean of "
       "its " +
       std::to_string(job.pattern.count) +
       " samples, its id and depth the nearest opaque fragment at the centre.";
  return s;
}

// The pixel with the longest list, kept for the magnified view: its fragments, and the
// background behind them.
struct KeptPixel {
  int x = 0, y = 0;
  std::uint32_t background = 0;
  std::vector<Fragment> fragments;
};

// The kept pixel close up, for the magnified view (src/explain/ draws it): what each sample
// resolves to, and the true edges of the triangles of every polygon listed there. Returns the
// pixel's colour, the mean of its samples.
std::uint32_t closeUp(const FrameJob& job, const KeptPixel& k, TracePixel& out) {
  const SamplePattern& p = job.pattern;
  std::vector<const Fragment*> list;
  for (const Fragment& f : k.fragments) list.push_back(&f);
  out = {k.x, k.y, {}, {}};
  std::uint32_t sum[3] = {0, 0, 0};
  for (int s = 0; s < p.count; ++s) {
    const SampleResult r = resolveSample(job, list, k.x, k.y, s, k.background);
    out.samples.push_back(
        {{p.x[s] / static_cast<double>(kSubpixelOne), p.y[s] / static_cast<double>(kSubpixelOne)},
         r.colour,
         r.depth,
         r.id});
    for (int ch = 0; ch < 3; ++ch) sum[ch] += (r.colour >> (8 * ch)) & 0xFFu;
  }
  const auto window = [](std::int32_t x, std::int32_t y) {
    return glm::dvec2(x / static_cast<double>(kSubpixelOne), y / static_cast<double>(kSubpixelOne));
  };
  for (const Fragment& f : k.fragments)
    for (std::uint32_t i = f.polygon; i < job.tris.size() && job.polygon_of[i] == f.polygon; ++i) {
      const ScreenTriangle& t = job.tris[i];
      for (int e = 0; e < 3; ++e)
        out.edges.push_back({window(t.x[e], t.y[e]), window(t.x[(e + 1) % 3], t.y[(e + 1) % 3])});
    }
  return meanOfSamples(sum, p.count);
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
      samplePattern(in.options.samples == 0 ? kDefaultSamples : in.options.samples);

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
  if (!in.trace) {
    tbb::parallel_for(std::size_t(0), tiles, [&](std::size_t tile) {
      const PixelBox box = scratch.bins.tileBox(tile, frame.width, frame.height);
      TileLists& lists = scratch.lists.local();
      fillLists(job, tile, box, lists, counts.local());
      resolveTile(job, box, lists);
    });
  } else {
    // Explained: the tiles one after another, and the longest list of all described
    if (in.trace->wants(kStepBin, 0, 1))
      in.trace->record(
          {kStepBin,
           "Bin: the screen is cut into " + std::to_string(tiles) +
               " tiles of 64x64 pixels; each of the " + std::to_string(tris.size()) +
               " triangles is listed in every tile it reaches. Each tile is filled and resolved "
               "on its own, so only one tile's fragment lists exist at a time.",
           &frame,
           {}});
    std::string longest;
    int longest_n = 0, px = 0, py = 0;
    KeptPixel kept;
    for (std::size_t tile = 0; tile < tiles; ++tile) {
      const PixelBox box = scratch.bins.tileBox(tile, frame.width, frame.height);
      TileLists& lists = scratch.lists.local();
      FragmentCounts c;
      fillLists(job, tile, box, lists, c);
      const auto [at, n] = longestList(lists, allSamples(pattern.count));
      if (n > longest_n) {
        const int tile_w = box.x1 - box.x0 + 1;
        px = box.x0 + static_cast<int>(at % tile_w), py = box.y0 + static_cast<int>(at / tile_w);
        longest_n = n;
        longest = describeList(job, lists, at, px, py);
        std::vector<const Fragment*> list;
        Fragment whole;
        gatherPixel(lists, at, allSamples(pattern.count), whole, list);
        kept = {px, py, fb.rgba[fb.index(px, py)], {}};
        for (const Fragment* f : list) kept.fragments.push_back(*f);
      }
      resolveTile(job, box, lists);
      counts.local() += c;
      if (in.trace->wants(kStepTile, tile, tiles))
        in.trace->record(
            {kStepTile,
             "Tile " + std::to_string(tile + 1) + " of " + std::to_string(tiles) + ": " +
                 std::to_string(scratch.bins.start[tile + 1] - scratch.bins.start[tile]) +
                 " triangles gave " + std::to_string(c.written) +
                 " fragments (a coverage mask of " + std::to_string(pattern.count) +
                 " samples each, those hidden behind a polygon covering the whole pixel left out); "
                 "each pixel's list resolved sample by sample.",
             &frame,
             {pixelBoxOutline(box)}});
    }
    if (longest_n > 0 && in.trace->wants(kStepPixel, 0, 1))
      in.trace->record({kStepPixel,
                        longest,
                        &frame,
                        {pixelBoxOutline(PixelBox{px - 3, py - 3, px + 3, py + 3})}});
    if (longest_n > 0 && in.trace->wants(kStepMagnified, 0, 1)) {
      TracePixel close;
      const std::uint32_t mean = closeUp(job, kept, close);
      char hex[8];
      std::snprintf(hex, sizeof hex, "#%02x%02x%02x", mean & 0xFFu, (mean >> 8) & 0xFFu,
                    (mean >> 16) & 0xFFu);
      in.trace->record(
          {kStepMagnified,
           "Pixel (" + std::to_string(px) + ", " + std::to_string(py) +
               ") magnified: the lines are the true edges of the triangles of the " +
               std::to_string(kept.fragments.size()) + " polygons listed there, the squares its " +
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
    if (in.trace->wants(kStepDone, 0, 1))
      in.trace->record(
          {kStepDone,
           "Done: edges antialiased (a pixel an edge crosses shows the mean of its samples), "
           "see-through polygons blended in depth order whatever order they came in; ids and "
           "depth are the nearest opaque polygon at each pixel centre, as the z-buffer's.",
           &frame,
           {}});
  }
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
