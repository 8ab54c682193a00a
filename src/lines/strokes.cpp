// Segments into pen strokes (lines/strokes.hpp), in three steps:
//   1. Lines. Segments on one line (their direction and offset within the tolerance) are
//      taken together: along the line, each stretch is drawn once, in the first layer where
//      any segment covers it, with the lowest kind of those there.
//   2. Chains. Pieces that meet end to end are followed into polylines while the meeting
//      point joins exactly two pieces of one kind; closed loops come out as loops.
//   3. Order. From the page's corner, the pen goes each time to the nearest free end of a
//      stroke (drawing the stroke backwards when that end is its last point).

#include "lines/strokes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <glm/geometric.hpp>

namespace hsr::detail {

namespace {

using glm::dvec2;

constexpr int kLayers = 2;

struct Piece {
  dvec2 a, b;
  std::uint8_t layer, kind;
};

// A segment on its line: the line's direction (x > 0, or x = 0 and y > 0), the angle of that
// direction, the offset of the line from the origin, and where along it the ends lie.
struct OnLine {
  double angle, offset, s0, s1;
  dvec2 a, b;  // a before b along the direction
  std::uint8_t layer, kind;
};

// ---- 1. Lines
void linesToPieces(std::vector<OnLine>& on, double tolerance, double extent,
                   std::vector<Piece>& pieces) {
  // Directions that differ by less than this stay within the tolerance across the drawing
  const double angle_tolerance = tolerance / std::max(extent, 1.0);
  std::sort(on.begin(), on.end(),
            [](const OnLine& l, const OnLine& r) { return l.angle < r.angle; });
  struct Break {
    double s;
    dvec2 p;
  };
  std::vector<Break> breaks;
  for (std::size_t i = 0; i < on.size();) {
    // Consecutive directions within the tolerance: one family of parallel lines
    std::size_t j = i + 1;
    while (j < on.size() && on[j].angle - on[j - 1].angle <= angle_tolerance) ++j;
    std::vector<OnLine*> family;
    for (std::size_t k = i; k < j; ++k) family.push_back(&on[k]);
    std::sort(family.begin(), family.end(),
              [](const OnLine* l, const OnLine* r) { return l->offset < r->offset; });
    for (std::size_t k = 0; k < family.size();) {
      std::size_t m = k + 1;
      while (m < family.size() && family[m]->offset - family[m - 1]->offset <= tolerance) ++m;
      // family[k, m): one line. Where along it each stretch begins and ends, snapped together
      // when within the tolerance, each kept with a point of the input that lies there.
      const dvec2 origin = family[k]->a;
      const dvec2 dir = glm::normalize(family[k]->b - family[k]->a);
      breaks.clear();
      for (std::size_t q = k; q < m; ++q) {
        family[q]->s0 = glm::dot(family[q]->a - origin, dir);
        family[q]->s1 = glm::dot(family[q]->b - origin, dir);
        if (family[q]->s1 < family[q]->s0)
          std::swap(family[q]->s0, family[q]->s1), std::swap(family[q]->a, family[q]->b);
        breaks.push_back({family[q]->s0, family[q]->a});
        breaks.push_back({family[q]->s1, family[q]->b});
      }
      std::sort(breaks.begin(), breaks.end(),
                [](const Break& l, const Break& r) { return l.s < r.s; });
      std::vector<Break> at;  // the snapped breaks, apart by more than the tolerance
      for (const Break& br : breaks)
        if (at.empty() || br.s - at.back().s > tolerance) at.push_back(br);
      auto index = [&](double s) {  // the snapped break a value belongs to
        auto it = std::upper_bound(at.begin(), at.end(), s,
                                   [](double v, const Break& br) { return v < br.s; });
        std::size_t idx = static_cast<std::size_t>(it - at.begin()) - 1;
        return idx;
      };
      // Coverage of each stretch between breaks, per layer and kind
      const std::size_t n = at.size();
      std::vector<std::array<std::uint8_t, kLayers>> best(n, {255, 255});
      std::vector<std::array<bool, kLayers>> covered(n, {false, false});
      for (std::size_t q = k; q < m; ++q) {
        const std::size_t b0 = index(family[q]->s0), b1 = index(family[q]->s1);
        for (std::size_t x = b0; x < b1; ++x) {
          auto& c = covered[x][family[q]->layer];
          auto& kd = best[x][family[q]->layer];
          c = true;
          kd = std::min(kd, family[q]->kind);
        }
      }
      // Runs of stretches with the same layer and kind become one piece
      for (std::size_t x = 0; x + 1 < n;) {
        const int layer = covered[x][0] ? 0 : covered[x][1] ? 1 : -1;
        if (layer < 0) {
          ++x;
          continue;
        }
        const std::uint8_t kind = best[x][layer];
        std::size_t y = x + 1;
        while (y + 1 < n) {
          const int l2 = covered[y][0] ? 0 : covered[y][1] ? 1 : -1;
          if (l2 != layer || best[y][layer] != kind) break;
          ++y;
        }
        pieces.push_back({at[x].p, at[y].p, static_cast<std::uint8_t>(layer), kind});
        x = y;
      }
      k = m;
    }
    i = j;
  }
}

// ---- 2. Chains: ends within the tolerance are one point (a grid of cells of that size)
struct Points {
  double cell;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  std::vector<dvec2> at;
  std::uint64_t key(std::int64_t x, std::int64_t y) const {
    return (static_cast<std::uint64_t>(x) << 32) ^ static_cast<std::uint64_t>(y & 0xFFFFFFFF);
  }
  std::uint32_t of(dvec2 p) {
    const std::int64_t cx = static_cast<std::int64_t>(std::floor(p.x / cell));
    const std::int64_t cy = static_cast<std::int64_t>(std::floor(p.y / cell));
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        if (auto it = grid.find(key(cx + dx, cy + dy)); it != grid.end())
          for (std::uint32_t i : it->second)
            if (glm::length(at[i] - p) <= cell) return i;
    const auto i = static_cast<std::uint32_t>(at.size());
    at.push_back(p);
    grid[key(cx, cy)].push_back(i);
    return i;
  }
};

void chain(const std::vector<Piece>& pieces, int layer, double tolerance,
           std::vector<Stroke>& out) {
  Points points{tolerance, {}, {}};
  struct Edge {
    std::uint32_t u, v;
    std::uint8_t kind;
    bool used = false;
  };
  std::vector<Edge> edges;
  for (const Piece& p : pieces) {
    if (p.layer != layer) continue;
    const std::uint32_t u = points.of(p.a), v = points.of(p.b);
    if (u != v) edges.push_back({u, v, p.kind});
  }
  std::vector<std::vector<std::uint32_t>> at(points.at.size());
  for (std::uint32_t e = 0; e < edges.size(); ++e)
    at[edges[e].u].push_back(e), at[edges[e].v].push_back(e);
  // From `start` along edge e, on through points that join exactly two pieces of one kind
  auto follow = [&](std::uint32_t start, std::uint32_t e) {
    Stroke s;
    s.kind = edges[e].kind;
    s.points.push_back(points.at[start]);
    std::uint32_t here = start;
    for (;;) {
      edges[e].used = true;
      here = edges[e].u == here ? edges[e].v : edges[e].u;
      s.points.push_back(points.at[here]);
      if (at[here].size() != 2) break;
      const std::uint32_t next = at[here][0] == e ? at[here][1] : at[here][0];
      if (edges[next].used || edges[next].kind != s.kind) break;
      e = next;
    }
    // Straight runs as one piece: a point on the line through its neighbours goes
    std::vector<dvec2> kept;
    for (const dvec2& q : s.points) {
      if (kept.size() >= 2) {
        const dvec2 d = q - kept[kept.size() - 2];
        const dvec2 w = kept.back() - kept[kept.size() - 2];
        const double len = glm::length(d);
        if (len > 0 && std::abs(d.x * w.y - d.y * w.x) / len <= tolerance * 1e-3 &&
            glm::dot(w, d) > 0 && glm::dot(w, d) < len * len)
          kept.back() = q;
        else
          kept.push_back(q);
      } else {
        kept.push_back(q);
      }
    }
    s.points = std::move(kept);
    out.push_back(std::move(s));
  };
  // Open chains from their ends (points not joining exactly two pieces, or where kinds change)
  for (std::uint32_t p = 0; p < at.size(); ++p) {
    const bool end = at[p].size() != 2 || edges[at[p][0]].kind != edges[at[p][1]].kind;
    if (!end) continue;
    for (std::uint32_t e : at[p])
      if (!edges[e].used) follow(p, e);
  }
  // What is left are loops
  for (std::uint32_t e = 0; e < edges.size(); ++e)
    if (!edges[e].used) follow(edges[e].u, e);
}

// ---- 3. Order: the nearest free end each time, through a grid of the free strokes' ends
// (made again, finer, each time half of them have been drawn, so the search stays short).
void order(std::vector<Stroke>& strokes) {
  if (strokes.size() < 2) return;
  std::vector<std::uint8_t> done(strokes.size(), 0);
  int n = 0;
  dvec2 lo(0.0), size(1.0);
  std::vector<std::vector<std::uint32_t>> cells;  // 2 stroke + end
  // Clamped before the conversion: the pen may stand far outside the ends left, and with them
  // all on one line `size` is tiny, so the quotient can pass any int
  auto cellOf = [&](dvec2 q) {
    const double top = static_cast<double>(n - 1);
    const int cx = static_cast<int>(std::clamp(std::floor((q.x - lo.x) / size.x * n), 0.0, top));
    const int cy = static_cast<int>(std::clamp(std::floor((q.y - lo.y) / size.y * n), 0.0, top));
    return std::pair{cx, cy};
  };
  std::size_t built_for = 0;
  auto build = [&](std::size_t left) {
    built_for = left;
    lo = dvec2(std::numeric_limits<double>::infinity());
    dvec2 hi(-std::numeric_limits<double>::infinity());
    for (std::uint32_t i = 0; i < strokes.size(); ++i)
      if (!done[i])
        for (const dvec2& q : {strokes[i].points.front(), strokes[i].points.back()})
          lo = glm::min(lo, q), hi = glm::max(hi, q);
    n = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(left)))));
    size = glm::max(hi - lo, dvec2(1e-9));
    cells.assign(static_cast<std::size_t>(n) * n, {});
    for (std::uint32_t i = 0; i < strokes.size(); ++i)
      if (!done[i])
        for (std::uint32_t end = 0; end < 2; ++end) {
          const auto [cx, cy] = cellOf(end ? strokes[i].points.back() : strokes[i].points.front());
          cells[static_cast<std::size_t>(cy) * n + cx].push_back(2 * i + end);
        }
  };
  std::vector<Stroke> out;
  out.reserve(strokes.size());
  build(strokes.size());
  dvec2 pen = lo;  // the drawing's corner nearest the origin
  for (std::size_t count = 0; count < strokes.size(); ++count) {
    const std::size_t left = strokes.size() - count;
    if (left * 2 < built_for) build(left);
    const auto [px, py] = cellOf(pen);
    const double cell = std::min(size.x, size.y) / n;
    std::uint32_t best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (int r = 0; r <= n; ++r) {
      if (r > 1 && (r - 1) * cell > best_d) break;  // ring r lies at least r - 1 cells away
      for (int cy = std::max(py - r, 0); cy <= std::min(py + r, n - 1); ++cy)
        for (int cx = std::max(px - r, 0); cx <= std::min(px + r, n - 1); ++cx) {
          if (std::max(std::abs(cx - px), std::abs(cy - py)) != r) continue;
          for (std::uint32_t e : cells[static_cast<std::size_t>(cy) * n + cx]) {
            if (done[e / 2]) continue;
            const Stroke& s = strokes[e / 2];
            const double d = glm::length((e & 1 ? s.points.back() : s.points.front()) - pen);
            if (d < best_d || (d == best_d && e < best)) best_d = d, best = e;
          }
        }
    }
    done[best / 2] = 1;
    Stroke s = std::move(strokes[best / 2]);
    if (best & 1) std::reverse(s.points.begin(), s.points.end());
    pen = s.points.back();
    out.push_back(std::move(s));
  }
  strokes = std::move(out);
}

void statsOf(const std::vector<Stroke>& strokes, StrokeStats* stats) {
  stats->strokes = strokes.size();
  stats->length = 0;
  for (const Stroke& s : strokes)
    for (std::size_t i = 1; i < s.points.size(); ++i)
      stats->length += glm::length(s.points[i] - s.points[i - 1]);
}

}  // namespace

double penUpTravel(const std::vector<Stroke>& strokes) {
  double travel = 0;
  for (std::size_t i = 1; i < strokes.size(); ++i)
    travel += glm::length(strokes[i].points.front() - strokes[i - 1].points.back());
  return travel;
}

void mergeStrokes(const std::vector<StrokeSegment>& first, const std::vector<StrokeSegment>& second,
                  double tolerance, std::vector<Stroke>* first_out, std::vector<Stroke>* second_out,
                  StrokeStats* first_stats, StrokeStats* second_stats) {
  auto drawn = [&](const StrokeSegment& sg) {
    const double len = glm::length(sg.b - sg.a);
    return len > tolerance && std::isfinite(len);  // else nothing to draw
  };
  dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (int layer = 0; layer < kLayers; ++layer)
    for (const StrokeSegment& sg : layer == 0 ? first : second)
      if (drawn(sg))
        lo = glm::min(lo, glm::min(sg.a, sg.b)), hi = glm::max(hi, glm::max(sg.a, sg.b));
  const double extent = lo.x <= hi.x ? glm::length(hi - lo) : 1.0;
  const double kHalfTurn = 3.14159265358979323846;
  std::vector<OnLine> on;
  for (int layer = 0; layer < kLayers; ++layer)
    for (const StrokeSegment& sg : layer == 0 ? first : second) {
      if (!drawn(sg)) continue;
      dvec2 a = sg.a, b = sg.b;
      dvec2 dir = glm::normalize(b - a);
      if (dir.x < 0 || (dir.x == 0 && dir.y < 0)) dir = -dir, std::swap(a, b);
      double angle = std::atan2(dir.y, dir.x);  // in (-pi/2, pi/2]
      // A line's direction turns round at the vertical: those just short of it are taken the
      // other way, beside those just past it
      if (angle > kHalfTurn / 2 - tolerance / std::max(extent, 1.0))
        angle -= kHalfTurn, dir = -dir, std::swap(a, b);
      const double offset = a.x * -dir.y + a.y * dir.x;
      on.push_back({angle, offset, 0, 0, a, b, static_cast<std::uint8_t>(layer), sg.kind});
    }
  std::vector<Piece> pieces;
  linesToPieces(on, tolerance, extent, pieces);
  std::vector<Stroke>* outs[kLayers] = {first_out, second_out};
  StrokeStats* stats[kLayers] = {first_stats, second_stats};
  for (int layer = 0; layer < kLayers; ++layer) {
    outs[layer]->clear();
    chain(pieces, layer, tolerance, *outs[layer]);
    stats[layer]->segments = layer == 0 ? first.size() : second.size();
    stats[layer]->pen_up_unordered = penUpTravel(*outs[layer]);
    order(*outs[layer]);
    stats[layer]->pen_up = penUpTravel(*outs[layer]);
    statsOf(*outs[layer], stats[layer]);
  }
}

}  // namespace hsr::detail
