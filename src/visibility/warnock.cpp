// Warnock's area subdivision (Warnock 1969; the notes' "area subdivision").
//
// Look at an area of the screen, at first the whole viewport, and at how each polygon stands
// to it:
//   surrounding  - the polygon covers the whole area;
//   overlapping  - it covers part of the area and reaches outside it;
//   inside       - it lies within the area;
//   outside      - it covers nothing of the area.
// If what the area shows is simple, draw it:
//   1. every polygon is outside: the area shows the background;
//   2. one polygon alone is not outside: draw it within the area;
//   3. a surrounding polygon is in front of every other polygon in the whole area (its
//      plane is nearer at the area's four corners): draw it on the whole area;
//   4. the area is a single pixel: show the polygon nearest at the pixel's centre.
// Otherwise cut the area into four quadrants and look at each in turn, handing down only the
// polygons that are not outside (a surrounding polygon surrounds every quadrant too).
//
// The polygons are the pipeline's: each arrives as triangles snapped to the sub-pixel grid,
// which share its plane. Relations are decided per triangle, bounding boxes first, then
// exactly: a triangle's three edge functions (the shared edge setup, raster/edge.hpp) are
// linear in the pixel, so their least and greatest values over an area lie at its corners;
// an edge negative at every corner leaves every centre of the area outside, three edges
// non-negative at every corner cover them all. "One polygon alone" asks whether every
// triangle left belongs to one polygon. Drawing uses the shared fill rule and fragment depth
// and the z-buffer's tie rule at a pixel (the polygon submitted first wins), so the picture
// equals the z-buffer's bit for bit. See-through polygons are then blended over the finished
// picture as the z-buffer blends them.
//
// Cost: O(areas x polygons handed down); areas are few where the picture is simple and reach
// pixel size along visible edges. Memory O(polygons x depth). Quadrants near the top are
// visited in parallel; the picture and every count are the same at any thread count.
//
// Tests: tests/visibility/warnock_test.cpp and every suite of the registry its capabilities join.

#include "visibility/warnock.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <string>
#include <vector>

#include "core/check.hpp"
#include "core/frame.hpp"
#include "core/parallel.hpp"
#include "core/stopwatch.hpp"
#include "raster/edge.hpp"
#include "raster/fragment.hpp"
#include "raster/lines.hpp"
#include "raster/triangle.hpp"

namespace hsr::detail {
namespace {

// Step names: what `hsr explain warnock` shows.
constexpr std::string_view kStepLevel = "level";
constexpr std::string_view kStepDone = "done";

// Levels whose quadrants are visited in parallel (4^3 = 64 tasks), each with its own lists.
constexpr int kParallelLevels = 3;

enum class Relation : std::uint8_t { kOutside, kOverlapping, kInside, kSurrounding };

// A polygon's triangle handed down to an area, with its relation to the area.
struct Item {
  std::uint32_t triangle;
  Relation relation;
};

// How triangle t stands to `area`.
Relation relationOf(const ScreenTriangle& t, const PixelBox& area) {
  // Bounding boxes first.
  if (t.x1 < area.x0 || t.x0 > area.x1 || t.y1 < area.y0 || t.y0 > area.y1)
    return Relation::kOutside;
  // Then exactly: each edge function E(i, j) = step_x i + step_y j + E(0, 0) at the corners.
  const TriangleSetup s = setupTriangle(t, 0);
  bool covers_all = true;
  for (const EdgeSetup& e : s.edge) {
    const std::int64_t least = e.row + e.step_x * (e.step_x > 0 ? area.x0 : area.x1) +
                               e.step_y * (e.step_y > 0 ? area.y0 : area.y1);
    const std::int64_t most = e.row + e.step_x * (e.step_x > 0 ? area.x1 : area.x0) +
                              e.step_y * (e.step_y > 0 ? area.y1 : area.y0);
    if (most < 0) return Relation::kOutside;  // every centre of the area is outside this edge
    covers_all = covers_all && least >= 0;
  }
  if (covers_all) return Relation::kSurrounding;
  if (t.x0 >= area.x0 && t.x1 <= area.x1 && t.y0 >= area.y0 && t.y1 <= area.y1)
    return Relation::kInside;
  return Relation::kOverlapping;
}

bool coversCentre(const ScreenTriangle& t, int x, int y) {
  const TriangleSetup s = setupTriangle(t, 0);
  for (const EdgeSetup& e : s.edge)
    if (e.row + e.step_x * x + e.step_y * y < 0) return false;
  return true;
}

// The plane's depth at the area's four corners; false where it cannot be trusted to decide.
bool cornerDepths(const DepthPlane& p, const PixelBox& a, std::array<double, 4>& d) {
  const int xs[2] = {a.x0, a.x1}, ys[2] = {a.y0, a.y1};
  for (int k = 0; k < 4; ++k) {
    const int x = xs[k & 1], y = ys[k >> 1];
    if (!planeDepthIsSafe(p, x, y)) return false;
    d[k] = planeDepth(p, x, y);
  }
  return true;
}

struct Counts {
  std::array<std::uint64_t, 16> areas{};             // visited, per level
  std::array<std::uint64_t, kWarnockStops> stops{};  // leaves, by why they stopped
  std::uint64_t handed_down = 0;                     // triangles handed to areas, in all
  std::uint64_t list_bytes = 0;                      // the lists' memory, all workers'
  int deepest = 0;
  FragmentCounts fragments;
  void add(const Counts& o) {
    for (std::size_t k = 0; k < areas.size(); ++k) areas[k] += o.areas[k];
    for (std::size_t k = 0; k < stops.size(); ++k) stops[k] += o.stops[k];
    handed_down += o.handed_down;
    list_bytes += o.list_bytes;
    deepest = std::max(deepest, o.deepest);
    fragments += o.fragments;
  }
};

// A leaf, kept when explaining.
struct Leaf {
  PixelBox area;
  int level;
  WarnockStop why;
};

struct Shared {
  const ScreenTriangles& tris;
  const std::vector<std::uint32_t>& polygon_of;
  const FrameView& fb;
  RasterPath path;
  WarnockObserver* observer;
  std::vector<Leaf>* leaves;  // non-null when explaining
  int deepest_allowed;
};

// One worker's subdivision: the lists of all open areas live in one array, each area's list
// appended after its parent's and dropped when the area is done.
class Subdivision {
 public:
  explicit Subdivision(const Shared& sh) : sh_(sh) {}

  std::vector<Item> lists;
  Counts counts;

  // The viewport with the given polygons.
  void start(const PixelBox& viewport, const std::vector<Item>& all) {
    handDown(all, 0, all.size(), viewport, lists);
    visit(viewport, 0, 0, lists.size());
    counts.list_bytes += lists.capacity() * sizeof(Item);
  }

  void visit(const PixelBox& area, int level, std::size_t first, std::size_t count) {
    HSR_CHECK_LE(level, sh_.deepest_allowed);
    counts.areas[static_cast<std::size_t>(level)]++;
    counts.deepest = std::max(counts.deepest, level);
    counts.handed_down += count;

    // 1. Every polygon outside: the background shows.
    if (count == 0) return stop(area, level, WarnockStop::kNothing);

    // 2. One polygon alone: draw it within the area.
    const std::uint32_t polygon = sh_.polygon_of[lists[first].triangle];
    bool one = true;
    for (std::size_t k = first + 1; k < first + count && one; ++k)
      one = sh_.polygon_of[lists[k].triangle] == polygon;
    if (one) {
      for (std::size_t k = first; k < first + count; ++k) draw(lists[k].triangle, area);
      return stop(area, level, WarnockStop::kOnePolygon);
    }

    // 3. A surrounding polygon in front of every other in the whole area.
    const std::uint32_t front = surrounderInFront(area, first, count);
    if (front != kNone) {
      draw(front, area);
      return stop(area, level, WarnockStop::kSurrounderInFront);
    }

    // 4. A single pixel: the polygon nearest at its centre.
    if (area.x0 == area.x1 && area.y0 == area.y1) {
      nearestAtCentre(area.x0, area.y0, first, count);
      return stop(area, level, WarnockStop::kPixel);
    }

    // Otherwise: the quadrants, each with the polygons not outside it.
    const int xm = area.x0 + (area.x1 - area.x0 + 1 + 1) / 2 - 1;  // left half: ceil(w / 2)
    const int ym = area.y0 + (area.y1 - area.y0 + 1 + 1) / 2 - 1;
    PixelBox quads[4];
    int n = 0;
    for (const auto& [ya, yb] : {std::pair{area.y0, ym}, std::pair{ym + 1, area.y1}})
      for (const auto& [xa, xb] : {std::pair{area.x0, xm}, std::pair{xm + 1, area.x1}})
        if (xa <= xb && ya <= yb) quads[n++] = {xa, ya, xb, yb};
    if (level < kParallelLevels && sh_.observer == nullptr && sh_.leaves == nullptr) {
      std::vector<Subdivision> parts(static_cast<std::size_t>(n), Subdivision(sh_));
      tbb::parallel_for(0, n, [&](int q) {
        Subdivision& part = parts[static_cast<std::size_t>(q)];
        handDown(lists, first, count, quads[q], part.lists);
        part.visit(quads[q], level + 1, 0, part.lists.size());
        part.counts.list_bytes += part.lists.capacity() * sizeof(Item);
      });
      for (const Subdivision& part : parts) counts.add(part.counts);
      return;
    }
    for (int q = 0; q < n; ++q) {
      const std::size_t start = lists.size();
      handDown(lists, first, count, quads[q], lists);
      visit(quads[q], level + 1, start, lists.size() - start);
      lists.resize(start);
    }
  }

 private:
  static constexpr std::uint32_t kNone = ~0u;

  // The items of from[first, first + count) not outside `area`, appended to `to` (which may
  // be `from` itself: the source is read by index).
  void handDown(const std::vector<Item>& from, std::size_t first, std::size_t count,
                const PixelBox& area, std::vector<Item>& to) {
    for (std::size_t k = first; k < first + count; ++k) {
      const Item it = from[k];
      const Relation r = it.relation == Relation::kSurrounding
                             ? Relation::kSurrounding
                             : relationOf(sh_.tris[it.triangle], area);
      if (r != Relation::kOutside) to.push_back({it.triangle, r});
    }
  }

  void stop(const PixelBox& area, int level, WarnockStop why) {
    counts.stops[static_cast<std::size_t>(why)]++;
    if (sh_.observer) sh_.observer->leaf(area, level, why);
    if (sh_.leaves) sh_.leaves->push_back({area, level, why});
  }

  // Triangle `tri`'s fragments within the area, each tested only against the cleared depth
  // (one at the far plane or beyond is not drawn, as under the z-buffer's LESS).
  void draw(std::uint32_t tri, const PixelBox& area) {
    rasterTriangle<DepthFunc::Less>(sh_.tris[tri], area, sh_.fb, true, sh_.path, counts.fragments);
  }

  // The surrounding triangle whose plane is nearest at the area's first corner, if it is in
  // front of every other polygon's at all four corners (the only one that can be).
  std::uint32_t surrounderInFront(const PixelBox& area, std::size_t first, std::size_t count) {
    std::uint32_t best = kNone;
    double best_z = 0.0;
    for (std::size_t k = first; k < first + count; ++k) {
      if (lists[k].relation != Relation::kSurrounding) continue;
      const std::uint32_t tri = lists[k].triangle;
      const double z = planeDepth(sh_.tris[tri].depth, area.x0, area.y0);
      if (best == kNone || z < best_z) best = tri, best_z = z;
    }
    if (best == kNone) return kNone;
    std::array<double, 4> s, o;
    if (!cornerDepths(sh_.tris[best].depth, area, s)) return kNone;
    for (const double z : s)
      if (!(z >= 0.0 && z <= 1.0)) return kNone;
    for (std::size_t k = first; k < first + count; ++k) {
      const std::uint32_t tri = lists[k].triangle;
      // The surrounder's own polygon shares its plane and covers no centre it covers.
      if (sh_.polygon_of[tri] == sh_.polygon_of[best]) continue;
      if (!cornerDepths(sh_.tris[tri].depth, area, o)) return kNone;
      for (int c = 0; c < 4; ++c)
        if (!(s[c] + kSafeDepthGap <= o[c])) return kNone;
    }
    return best;
  }

  // The polygon nearest at the centre of pixel (x, y); of equal depths the one submitted
  // first (the lists keep submission order), as the z-buffer under LESS.
  void nearestAtCentre(int x, int y, std::size_t first, std::size_t count) {
    std::uint32_t best = kNone;
    float best_z = 0.0f;
    for (std::size_t k = first; k < first + count; ++k) {
      const ScreenTriangle& t = sh_.tris[lists[k].triangle];
      if (!coversCentre(t, x, y)) continue;
      const float z = fragmentDepth(t.depth, x, y);
      counts.fragments.tested++;
      if (best == kNone || z < best_z) best = lists[k].triangle, best_z = z;
    }
    const std::size_t idx = sh_.fb.index(x, y);
    if (best == kNone || !(best_z < sh_.fb.depth[idx])) return;
    const ScreenTriangle& t = sh_.tris[best];
    counts.fragments.written++;
    sh_.fb.overdraw[idx]++;
    sh_.fb.depth[idx] = best_z;
    sh_.fb.ids[idx] = t.id;
    sh_.fb.rgba[idx] = t.rgba;
  }

  const Shared& sh_;
};

const char* stopName(WarnockStop why) {
  switch (why) {
    case WarnockStop::kNothing:
      return "nothing there";
    case WarnockStop::kOnePolygon:
      return "one polygon";
    case WarnockStop::kSurrounderInFront:
      return "surrounder in front";
    case WarnockStop::kPixel:
      return "pixel";
  }
  return "?";
}

// The teaching view: level by level, the areas decided so far tinted by why they stopped
// (grey: nothing there, green: one polygon, blue: a surrounder in front, red: pixel), the
// areas still to subdivide dark, and the areas that stopped at this level outlined.
void traceLevels(const AlgorithmInput& in, const Frame& frame, const std::vector<Leaf>& leaves,
                 const Counts& c) {
  static constexpr std::uint32_t kTint[kWarnockStops] = {0xFF808080u, 0xFF40C040u, 0xFFE08030u,
                                                         0xFF3030E0u};
  const int levels = c.deepest + 1;
  for (int level = 0; level < levels; ++level) {
    if (!in.trace->wants(kStepLevel, static_cast<std::uint64_t>(level),
                         static_cast<std::uint64_t>(levels)))
      continue;
    Frame pic = frame;
    std::fill(pic.color.begin(), pic.color.end(), 0xFF303030u);
    std::fill(pic.depth.begin(), pic.depth.end(), 1.0f);
    std::vector<TraceOutline> outlines;
    std::uint64_t at_level[kWarnockStops] = {};
    for (const Leaf& l : leaves) {
      if (l.level > level) continue;
      if (l.level == level) {
        at_level[static_cast<int>(l.why)]++;
        if (outlines.size() < 4000 && (l.area.x1 > l.area.x0 || l.area.y1 > l.area.y0))
          outlines.push_back({{l.area.x0 - 0.5f, l.area.y0 - 0.5f},
                              {l.area.x1 + 0.5f, l.area.y0 - 0.5f},
                              {l.area.x1 + 0.5f, l.area.y1 + 0.5f},
                              {l.area.x0 - 0.5f, l.area.y1 + 0.5f}});
      }
      const std::uint32_t tint = kTint[static_cast<int>(l.why)];
      for (int y = l.area.y0; y <= l.area.y1; ++y)
        for (int x = l.area.x0; x <= l.area.x1; ++x) {
          const std::size_t k = static_cast<std::size_t>(y) * frame.width + x;
          pic.color[k] = blendOver((tint & 0x00FFFFFFu) | 0x70000000u, frame.color[k]);
          pic.depth[k] = frame.depth[k];
        }
    }
    in.trace->record(
        {kStepLevel,
         "Level " + std::to_string(level) + ": " + std::to_string(c.areas[level]) +
             " areas looked at; " + std::to_string(at_level[0]) + " show nothing (grey), " +
             std::to_string(at_level[1]) + " one polygon alone (green), " +
             std::to_string(at_level[2]) + " a surrounding polygon in front of all (blue), " +
             std::to_string(at_level[3]) +
             " are single pixels (red). The dark rest is cut into quadrants for the next "
             "level.",
         &pic, std::move(outlines)});
  }
}

}  // namespace

int warnockDeepestLevel(int width, int height) {
  const unsigned n = static_cast<unsigned>(std::max({width, height, 1}));
  return static_cast<int>(std::bit_width(n - 1));  // ceil(log2(n))
}

void drawWarnockObserved(const AlgorithmInput& in, Frame& frame, WarnockObserver* observer) {
  const detail::Stopwatch t0;
  const ScreenTriangles& tris = in.prepared.triangles;
  const FrameView fb(frame);
  std::vector<std::uint32_t> polygon_of;
  const std::uint64_t polygons = numberPolygons(tris, polygon_of);
  std::vector<Leaf> leaves;
  const Shared sh{tris,
                  polygon_of,
                  fb,
                  rasterPath(DepthFunc::Less),
                  observer,
                  in.trace ? &leaves : nullptr,
                  warnockDeepestLevel(frame.width, frame.height)};
  HSR_CHECK_LT(sh.deepest_allowed, 16);

  // The whole viewport, with every opaque polygon (see-through ones are blended afterwards).
  const PixelBox viewport{0, 0, frame.width - 1, frame.height - 1};
  std::vector<Item> all;
  all.reserve(tris.size());
  for (std::uint32_t i = 0; i < tris.size(); ++i)
    if (!tris[i].transparent()) all.push_back({i, Relation::kOverlapping});
  Subdivision root(sh);
  root.start(viewport, all);
  Counts c = root.counts;
  c.list_bytes += all.capacity() * sizeof(Item);

  // See-through polygons over the finished picture, in submission order, as the z-buffer.
  const RasterPath path = rasterPath(DepthFunc::Less);
  for (const ScreenTriangle& t : tris)
    if (t.transparent()) rasterTriangle<DepthFunc::Less>(t, viewport, fb, true, path, c.fragments);
  for (const ScreenLine& o : in.prepared.outline) drawOutlinePen(o, viewport, fb);

  if (in.trace) {
    traceLevels(in, frame, leaves, c);
    if (in.trace->wants(kStepDone, 0, 1))
      in.trace->record(
          {kStepDone,
           "Done: " + std::to_string(c.stops[0] + c.stops[1] + c.stops[2] + c.stops[3]) +
               " areas needed no further cut: " + std::to_string(c.stops[0]) + " nothing there, " +
               std::to_string(c.stops[1]) + " one polygon, " + std::to_string(c.stops[2]) +
               " a surrounder in front, " + std::to_string(c.stops[3]) + " single pixels; " +
               std::to_string(c.deepest + 1) + " levels (at most " +
               std::to_string(sh.deepest_allowed + 1) + " for this viewport).",
           &frame,
           {}});
  }

  frame.stats.state_bytes += c.list_bytes + polygon_of.capacity() * 4;
  frame.stats.fragments_tested += c.fragments.tested;
  frame.stats.fragments_written += c.fragments.written;
  frame.stats.addCounter("warnock: polygons", polygons);
  for (int level = 0; level <= c.deepest; ++level)
    frame.stats.addCounter("warnock: areas at level " + std::to_string(level), c.areas[level]);
  for (int k = 0; k < kWarnockStops; ++k)
    frame.stats.addCounter(std::string("warnock: stop, ") + stopName(static_cast<WarnockStop>(k)),
                           c.stops[k]);
  frame.stats.addCounter("warnock: triangles handed down", c.handed_down);
  frame.stats.addStage("subdivide", t0.ms());
}

void drawWarnock(const AlgorithmInput& in, Frame& frame) {
  drawWarnockObserved(in, frame, nullptr);
}

}  // namespace hsr::detail
