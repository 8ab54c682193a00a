// Hidden-line drawings (hsr/line_drawing.hpp): the exact visible parts of the lines, then pen
// strokes. The default engine (LineEngine::kEdges) finds the lines first and then what hides
// them (visibility/line_visibility.cpp, the same rules as step 2 below), then step 3. The
// reference engine (kRoberts):
//   1. Visible and hidden parts of every edge: Roberts' algorithm on the pipeline's polygons
//      (roberts.cpp), with the hidden parts kept.
//   2. Which edges are lines. Each segment knows its polygon and the polygon across its edge.
//      An outline: no polygon across (an open border, or the other one culled or clipped),
//      or the two fold over each other in the picture (both lie on one side of the edge: a
//      silhouette, whatever the windings say). A crease: the two meet at more than the crease
//      angle, their normals turned towards the eye. A junction line: an intersection line.
//      Where a non-planar polygon's pieces meet, and where two polygons meet within the
//      crease angle, there is no line.
//   3. Strokes (lines/strokes.hpp): merged, chained and ordered, the visible layer winning
//      where a line is both.
// With a time limit that step 1 would pass, and the raster fallback asked for:
//   4. Lines from the z-buffer's ids: between two pixels showing different polygons, a unit
//      segment along their shared pixel edge where a line belongs (background beside a polygon,
//      polygons of different objects or sharing no corner, or neighbours whose normals turned
//      towards the eye part by more than the crease angle), then step 3.

#include "hsr/line_drawing.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <tuple>
#include <unordered_map>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "core/parallel.hpp"
#include "core/stopwatch.hpp"
#include "geometry/polygon.hpp"
#include "lines/strokes.hpp"
#include "core/deadline.hpp"
#include "hsr/error.hpp"
#include "hsr/roberts.hpp"
#include "orchestrator.hpp"
#include "pipeline/pipeline.hpp"
#include "lines/line_visibility.hpp"
#include "visibility/algorithm.hpp"
#include "visibility/roberts.hpp"

namespace hsr {

const char* lineKindName(LineKind kind) {
  switch (kind) {
    case LineKind::kOutline:
      return "outline";
    case LineKind::kCrease:
      return "crease";
    case LineKind::kIntersection:
      return "intersection";
  }
  return "?";
}

namespace {

using glm::dvec2;
using glm::dvec3;

// Strokes merge ends this close (pixels): far below what any pen shows, far above the
// rounding of Roberts' junction lines.
constexpr double kStrokeTolerance = 1e-6;
// Roberts' pieces shorter than its grid unit (1/256 pixel) are left out: where a face's
// sections meet, rounding leaves gaps of 1e-8 pixel between hidden stretches, and stretches
// as short at their ends.
constexpr double kShortest = 1.0 / 256;

// Step 2 for each segment, from the polygons' pieces in the window and their eye-space planes.
class Classifier {
 public:
  Classifier(const std::vector<detail::WindowPolygon>& polygons, bool ortho,
             double crease_angle_deg)
      : ortho_(ortho), cos_crease_(std::cos(crease_angle_deg * 3.14159265358979323846 / 180.0)) {
    for (const detail::WindowPolygon& w : polygons) by_id_[w.id].push_back(&w);
  }

  // The line a segment is part of, or none (-1).
  int kindOf(const RobertsSegment& s) const {
    if (s.junction) return static_cast<int>(LineKind::kIntersection);
    if (s.neighbour == kNoPolygon) return static_cast<int>(LineKind::kOutline);
    if (s.neighbour == s.face) return -1;  // inside a non-planar polygon
    const auto f = by_id_.find(s.face), g = by_id_.find(s.neighbour);
    if (f == by_id_.end() || g == by_id_.end()) return static_cast<int>(LineKind::kOutline);
    // A fold: both polygons on one side of the edge in the picture
    const dvec2 a(s.x0, s.y0), b(s.x1, s.y1);
    const int side_f = sideOf(f->second, a, b), side_g = sideOf(g->second, a, b);
    if (side_f != 0 && side_f == side_g) return static_cast<int>(LineKind::kOutline);
    // A crease: normals turned towards the eye, at more than the crease angle
    const dvec3 nf = towardsEye(*f->second.front()), ng = towardsEye(*g->second.front());
    const double lf = glm::length(nf), lg = glm::length(ng);
    if (!(lf > 0) || !(lg > 0)) return static_cast<int>(LineKind::kOutline);
    return glm::dot(nf, ng) / (lf * lg) < cos_crease_ ? static_cast<int>(LineKind::kCrease) : -1;
  }

 private:
  // Which side of the line through a and b the polygon lies on: the sign of its vertex
  // farthest from it (0 when it lies on the line).
  static int sideOf(const std::vector<const detail::WindowPolygon*>& pieces, dvec2 a, dvec2 b) {
    const dvec2 d = b - a;
    double best = 0;
    for (const detail::WindowPolygon* w : pieces)
      for (const dvec3& q : w->vertices) {
        const double c = d.x * (q.y - a.y) - d.y * (q.x - a.x);
        if (std::abs(c) > std::abs(best)) best = c;
      }
    return best > 0 ? 1 : best < 0 ? -1 : 0;
  }
  // The polygon's eye-space normal on the side the eye is (in perspective the eye is the
  // origin; in parallel it is far towards +z).
  dvec3 towardsEye(const detail::WindowPolygon& w) const {
    const dvec3 n(w.eye_plane);
    const double at_eye = ortho_ ? n.z : w.eye_plane.w;
    return at_eye < 0 ? -n : n;
  }

  bool ortho_;
  double cos_crease_;
  std::unordered_map<PolygonId, std::vector<const detail::WindowPolygon*>> by_id_;
};

LineLayerStats layerStats(const detail::StrokeStats& s) {
  return {s.segments, s.strokes, s.length, s.pen_up, s.pen_up_unordered};
}

void addCount(LineDrawing& out, int kind) {
  (kind == 0   ? out.outline_segments
   : kind == 1 ? out.crease_segments
               : out.intersection_segments)++;
}

// ---- 4. Lines from the z-buffer's ids
std::vector<detail::StrokeSegment> rasterLines(const Scene& scene, const Camera& camera,
                                               const RenderOptions& options,
                                               const LineDrawingOptions& lines, LineDrawing& out) {
  const double crease_angle_deg = lines.crease_angle_deg;
  const bool wanted[3] = {lines.outlines, lines.creases, lines.intersections};
  RenderOptions zo = options;
  zo.algorithm = "zbuffer";
  zo.outline = false;
  const Frame z = render(scene, camera, zo);
  const double cos_crease = std::cos(crease_angle_deg * 3.14159265358979323846 / 180.0);
  // The polygons shown: their corners (object and position) and normals turned towards the eye
  struct Shown {
    std::vector<std::tuple<std::uint32_t, float, float, float>> corners;  // sorted
    dvec3 normal{0.0};
  };
  std::unordered_map<PolygonId, Shown> shown;
  const dvec3 eye(camera.eye), towards_eye = -glm::normalize(dvec3(camera.target) - eye);
  for (const PolygonId id : z.ids) {
    if (id == kNoPolygon || shown.count(id)) continue;
    Shown& sh = shown[id];
    const auto v = scene.polygon(id);
    sh.normal =
        detail::newellNormal(v.size(), [&](std::size_t i) { return dvec3(scene.position(v[i])); });
    for (const std::uint32_t vi : v) {
      const glm::vec3 q = scene.position(vi);
      sh.corners.emplace_back(scene.object(id), q.x, q.y, q.z);
    }
    std::sort(sh.corners.begin(), sh.corners.end());
    const dvec3 at_eye = camera.ortho ? towards_eye : eye - dvec3(scene.position(v[0]));
    if (glm::dot(sh.normal, at_eye) < 0) sh.normal = -sh.normal;
  }
  std::unordered_map<std::uint64_t, int> kinds;  // by pair of ids
  auto kindOf = [&](PolygonId a, PolygonId b) {
    if (a == kNoPolygon || b == kNoPolygon) return lines.outlines ? 0 : -1;
    const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
    if (const auto it = kinds.find(key); it != kinds.end()) return it->second;
    const Shown &sa = shown.at(a), &sb = shown.at(b);
    std::vector<std::tuple<std::uint32_t, float, float, float>> common;
    std::set_intersection(sa.corners.begin(), sa.corners.end(), sb.corners.begin(),
                          sb.corners.end(), std::back_inserter(common));
    const double la = glm::length(sa.normal), lb = glm::length(sb.normal);
    int kind = static_cast<int>(LineKind::kOutline);  // another object, or no corner shared
    if (!common.empty() && la > 0 && lb > 0)
      kind = glm::dot(sa.normal, sb.normal) / (la * lb) < cos_crease
                 ? static_cast<int>(LineKind::kCrease)
                 : -1;
    if (kind >= 0 && !wanted[kind]) kind = -1;
    return kinds[key] = kind;
  };
  std::vector<detail::StrokeSegment> segments;
  for (int y = 0; y < z.height; ++y)
    for (int x = 0; x < z.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * z.width + x;
      if (x + 1 < z.width && z.ids[i] != z.ids[i + 1])
        if (const int k = kindOf(z.ids[i], z.ids[i + 1]); k >= 0)
          segments.push_back(
              {{x + 0.5, y - 0.5}, {x + 0.5, y + 0.5}, static_cast<std::uint8_t>(k)}),
              addCount(out, k);
      if (y + 1 < z.height && z.ids[i] != z.ids[i + z.width])
        if (const int k = kindOf(z.ids[i], z.ids[i + z.width]); k >= 0)
          segments.push_back(
              {{x - 0.5, y + 0.5}, {x + 0.5, y + 0.5}, static_cast<std::uint8_t>(k)}),
              addCount(out, k);
    }
  out.width = z.width, out.height = z.height;
  return segments;
}

}  // namespace

LineDrawing lineDrawing(const Scene& scene, const Camera& camera, const RenderOptions& options,
                        const LineDrawingOptions& lines) {
  if (!std::isfinite(lines.crease_angle_deg) || lines.crease_angle_deg < 0 ||
      lines.crease_angle_deg > 180)
    throw Error("line drawing: the crease angle must be between 0 and 180 degrees, not " +
                std::to_string(lines.crease_angle_deg));
  if (options.polygon_mode != PolygonMode::Fill)
    throw Error("line drawing: the polygon mode must be fill");
  if (!(lines.time_limit_s >= 0) || !std::isfinite(lines.time_limit_s))
    throw Error("line drawing: the time limit must be a number of seconds, 0 for none");
  const detail::Stopwatch t0;
  detail::Deadline deadline;
  if (lines.time_limit_s > 0)
    deadline.at = std::chrono::steady_clock::now() +
                  std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                      std::chrono::duration<double>(lines.time_limit_s));
  LineDrawing out;
  out.engine = lines.engine;
  const bool edges = lines.engine == LineEngine::kEdges;
  const int threads = detail::workerThreads(options.threads);
  // ---- 1. Visible and hidden parts of every edge
  detail::PreparedScene ps;
  RobertsDrawing r;
  detail::LineVisibility lv;
  try {
    detail::runWithThreads(threads, [&] {
      ps = detail::prepare(scene, camera, options, {.window_polygons = true, .triangles = !edges});
      const detail::Stopwatch tp;
      out.stage_ms.emplace_back("pipeline", t0.ms());
      if (edges)
        lv = detail::lineVisibility(scene, ps.polygons, ps.width, ps.height,
                                    {.ortho = camera.ortho,
                                     .crease_angle_deg = lines.crease_angle_deg,
                                     .outlines = lines.outlines,
                                     .creases = lines.creases,
                                     .intersections = lines.intersections,
                                     .hidden = lines.hidden,
                                     .deadline = lines.time_limit_s > 0 ? &deadline : nullptr});
      else
        r = detail::robertsDrawingOf(scene, ps.polygons, ps.width, ps.height, nullptr, nullptr,
                                     lines.hidden, lines.time_limit_s > 0 ? &deadline : nullptr);
      if (edges)
        for (const auto& [stage, ms] : lv.stages) out.stage_ms.emplace_back(stage, ms);
      else
        out.stage_ms.emplace_back("roberts", tp.ms());
    });
  } catch (const detail::DeadlinePassed&) {
    if (!lines.raster_fallback)
      throw Error(fmt::format(
          "line drawing: the exact drawing did not finish within the time limit of {} s "
          "({} polygons in view); the raster fallback draws lines from the z-buffer's ids",
          lines.time_limit_s, ps.polygons.size()));
    // ---- 4. Lines from the z-buffer's ids, then 3.
    out.exact = false;
    const std::vector<detail::StrokeSegment> segments =
        rasterLines(scene, camera, options, lines, out);
    out.visibility_ms = t0.ms();
    const detail::Stopwatch t1;
    std::vector<detail::Stroke> vs, hs;
    detail::StrokeStats vstats, hstats;
    detail::mergeStrokes(segments, {}, kStrokeTolerance, &vs, &hs, &vstats, &hstats);
    for (detail::Stroke& s : vs)
      out.visible.push_back({std::move(s.points), static_cast<LineKind>(s.kind)});
    out.visible_stats = layerStats(vstats);
    out.strokes_ms = t1.ms();
    return out;
  }
  out.width = ps.width, out.height = ps.height;
  out.visibility_ms = t0.ms();
  const detail::Stopwatch t1;
  std::vector<detail::StrokeSegment> visible, hidden;
  if (edges) {
    visible = std::move(lv.visible), hidden = std::move(lv.hidden);
    out.outline_segments = lv.pieces[0], out.crease_segments = lv.pieces[1];
    out.intersection_segments = lv.pieces[2], out.smooth_segments = lv.smooth_edges;
  } else {
    // ---- 2. Which edges are lines
    const Classifier classify(ps.polygons, camera.ortho, lines.crease_angle_deg);
    const bool wanted[3] = {lines.outlines, lines.creases, lines.intersections};
    auto tiny = [](const RobertsSegment& s) {
      return std::hypot(s.x1 - s.x0, s.y1 - s.y0) < kShortest;
    };
    for (const RobertsSegment& s : r.segments) {
      if (tiny(s)) continue;
      const int kind = classify.kindOf(s);
      if (kind < 0) {
        out.smooth_segments++;
        continue;
      }
      if (!wanted[kind]) continue;
      addCount(out, kind);
      visible.push_back({{s.x0, s.y0}, {s.x1, s.y1}, static_cast<std::uint8_t>(kind)});
    }
    for (const RobertsSegment& s : r.hidden)
      if (const int kind = classify.kindOf(s); kind >= 0 && wanted[kind] && !tiny(s))
        hidden.push_back({{s.x0, s.y0}, {s.x1, s.y1}, static_cast<std::uint8_t>(kind)});
  }
  // ---- 3. Strokes
  std::vector<detail::Stroke> vs, hs;
  detail::StrokeStats vstats, hstats;
  detail::mergeStrokes(visible, hidden, kStrokeTolerance, &vs, &hs, &vstats, &hstats);
  for (auto [from, to] : {std::pair{&vs, &out.visible}, std::pair{&hs, &out.hidden}})
    for (detail::Stroke& s : *from)
      to->push_back({std::move(s.points), static_cast<LineKind>(s.kind)});
  out.visible_stats = layerStats(vstats);
  out.hidden_stats = layerStats(hstats);
  out.strokes_ms = t1.ms();
  return out;
}

}  // namespace hsr
