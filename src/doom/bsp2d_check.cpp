// Checking a Doom map's node tree, and the two ways of asking which sector holds a point: down
// the tree, as Doom's renderer does (R_PointInSubsector), and from the linedefs alone. A tree is
// right when both give the same sector everywhere inside the map (tests/doom/doom_test.cpp asks
// at many random points); checkNodes looks at the tree's own structure.

#include <algorithm>
#include <cmath>
#include <functional>

#include <fmt/core.h>

#include "hsr/doom.hpp"
#include "hsr/error.hpp"

namespace hsr::doom {

namespace {

bool hasLength(const Map& map, const Linedef& l) {
  const Vertex a = map.vertices[l.v1], b = map.vertices[l.v2];
  return a.x != b.x || a.y != b.y;
}

}  // namespace

BuildStats nodeStats(const Map& map, const Nodes& nodes) {
  BuildStats s;
  for (const Linedef& l : map.linedefs)
    if (hasLength(map, l)) s.sides += (l.side[0] != kNoSide) + (l.side[1] != kNoSide);
  s.segs = nodes.segs.size();
  s.splits = s.segs > s.sides ? s.segs - s.sides : 0;
  s.nodes = nodes.nodes.size();
  s.subsectors = nodes.subsectors.size();
  for (const Subsector& ss : nodes.subsectors) {
    const auto sector = [&](std::size_t i) {
      const Seg& seg = nodes.segs[i];
      return map.sidedefs[map.linedefs[seg.linedef].side[std::size_t(seg.side) & 1]].sector;
    };
    if (ss.count == 0 || std::size_t(ss.first) + ss.count > nodes.segs.size()) continue;
    for (std::size_t i = ss.first + 1u; i < std::size_t(ss.first) + ss.count; ++i)
      if (sector(i) != sector(ss.first)) {
        ++s.mixed_subsectors;
        break;
      }
  }
  // The longest root-to-subsector path, walked with a stack (a corrupt tree is not trusted here:
  // checkNodes says what is wrong; a child index out of range ends its path).
  std::vector<std::pair<std::uint16_t, std::uint64_t>> stack;
  if (!nodes.nodes.empty())
    stack.push_back({static_cast<std::uint16_t>(nodes.nodes.size() - 1), 1});
  std::uint64_t visits = 0;
  while (!stack.empty() && ++visits <= 4 * nodes.nodes.size() + 4) {
    const auto [n, level] = stack.back();
    stack.pop_back();
    s.depth = std::max(s.depth, level);
    for (std::uint16_t c : nodes.nodes[n].child)
      if (!(c & kSubsectorBit) && c < nodes.nodes.size()) stack.push_back({c, level + 1});
  }
  return s;
}

std::uint16_t subsectorAt(const Nodes& nodes, double x, double y) {
  if (nodes.nodes.empty()) return 0;
  std::uint16_t n = static_cast<std::uint16_t>(nodes.nodes.size() - 1);
  for (std::size_t steps = 0; steps <= nodes.nodes.size(); ++steps) {
    const Node& node = nodes.nodes[n];
    // Doom's R_PointOnSide: the right of the line (and nothing else) is the front.
    const double side = double(node.dx) * (y - node.y) - double(node.dy) * (x - node.x);
    const std::uint16_t c = node.child[side < 0 ? 0 : 1];
    if (c & kSubsectorBit) return static_cast<std::uint16_t>(c & ~kSubsectorBit);
    if (c >= nodes.nodes.size()) break;
    n = c;
  }
  throw Error("a node tree that does not end in a subsector");
}

std::uint16_t sectorByTree(const Map& map, const Nodes& nodes, double x, double y) {
  const Subsector& ss = nodes.subsectors.at(subsectorAt(nodes, x, y));
  const Seg& seg = nodes.segs.at(ss.first);
  return map.sidedefs.at(map.linedefs.at(seg.linedef).side.at(std::size_t(seg.side))).sector;
}

std::optional<std::uint16_t> sectorByLinedefs(const Map& map, double x, double y) {
  // A ray in a direction no linedef of integer vertices runs along, to the nearest linedef.
  const double rx = std::cos(0.3141), ry = std::sin(0.3141);
  double nearest = INFINITY;
  std::optional<std::uint16_t> sector;
  for (const Linedef& l : map.linedefs) {
    const Vertex a = map.vertices[l.v1], b = map.vertices[l.v2];
    const double ex = double(b.x) - a.x, ey = double(b.y) - a.y;
    const double denom = rx * ey - ry * ex;
    if (denom == 0) continue;
    const double wx = double(a.x) - x, wy = double(a.y) - y;
    const double t = (wx * ey - wy * ex) / denom;  // along the ray
    const double u = (wx * ry - wy * rx) / denom;  // along the linedef
    if (t <= 0 || u < 0 || u > 1 || t >= nearest) continue;
    nearest = t;
    const double side = ex * (y - a.y) - ey * (x - a.x);  // < 0: the point is on the right (front)
    const std::uint16_t sd = l.side[side < 0 ? 0 : 1];
    sector = sd == kNoSide ? std::nullopt : std::optional<std::uint16_t>(map.sidedefs[sd].sector);
  }
  return sector;
}

std::vector<std::string> checkNodes(const Map& map, const Nodes& n, double tolerance) {
  std::vector<std::string> problems;
  std::size_t more = 0;
  const auto problem = [&](std::string line) {
    if (problems.size() < 20)
      problems.push_back(std::move(line));
    else
      ++more;
  };
  const auto finish = [&] {
    if (more) problems.push_back(fmt::format("... and {} more", more));
    return problems;
  };
  // Indices.
  if (n.vertices.size() < map.vertices.size()) problem("fewer vertices than the linedefs use");
  for (std::size_t i = 0; i < map.vertices.size() && i < n.vertices.size(); ++i)
    if (n.vertices[i].x != map.vertices[i].x || n.vertices[i].y != map.vertices[i].y)
      problem(fmt::format("vertex {} moved", i));
  for (std::size_t i = 0; i < n.segs.size(); ++i) {
    const Seg& s = n.segs[i];
    if (s.v1 >= n.vertices.size() || s.v2 >= n.vertices.size() ||
        s.linedef >= map.linedefs.size() || (s.side != 0 && s.side != 1) ||
        map.linedefs[s.linedef].side[std::size_t(s.side)] == kNoSide)
      problem(fmt::format("seg {}: an index out of range", i));
  }
  for (std::size_t i = 0; i < n.subsectors.size(); ++i)
    if (n.subsectors[i].count == 0 ||
        std::size_t(n.subsectors[i].first) + n.subsectors[i].count > n.segs.size())
      problem(fmt::format("subsector {}: segs out of range", i));
  if (n.subsectors.empty()) problem("no subsector");
  if (!problems.empty()) return finish();

  // Every node reached once, every subsector once, and nothing else reached.
  std::vector<int> node_seen(n.nodes.size()), ss_seen(n.subsectors.size());
  if (n.nodes.empty()) {
    ss_seen.at(0) = 1;
  } else {
    std::vector<std::uint16_t> stack{static_cast<std::uint16_t>(n.nodes.size() - 1)};
    while (!stack.empty()) {
      const std::uint16_t id = stack.back();
      stack.pop_back();
      if (node_seen[id]++) {
        problem(fmt::format("node {} reached twice", id));
        return finish();
      }
      for (std::uint16_t c : n.nodes[id].child) {
        const std::uint16_t i = c & ~kSubsectorBit;
        if (c & kSubsectorBit) {
          if (i >= n.subsectors.size())
            problem(fmt::format("node {}: subsector {} out of range", id, i));
          else
            ++ss_seen[i];
        } else if (c >= n.nodes.size()) {
          problem(fmt::format("node {}: child {} out of range", id, c));
        } else {
          stack.push_back(c);
        }
      }
    }
  }
  for (std::size_t i = 0; i < node_seen.size(); ++i)
    if (node_seen[i] != 1) problem(fmt::format("node {} reached {} times", i, node_seen[i]));
  for (std::size_t i = 0; i < ss_seen.size(); ++i)
    if (ss_seen[i] != 1) problem(fmt::format("subsector {} reached {} times", i, ss_seen[i]));

  const auto at = [&](std::uint16_t v) { return n.vertices[v]; };
  // Each subsector convex.
  for (std::size_t i = 0; i < n.subsectors.size(); ++i) {
    const Subsector& ss = n.subsectors[i];
    for (std::size_t a = ss.first; a < std::size_t(ss.first) + ss.count; ++a) {
      const Seg& sa = n.segs[a];
      const Linedef& l = map.linedefs[sa.linedef];
      const Vertex p = map.vertices[sa.side == 0 ? l.v1 : l.v2],
                   q = map.vertices[sa.side == 0 ? l.v2 : l.v1];
      const double dx = double(q.x) - p.x, dy = double(q.y) - p.y, len = std::hypot(dx, dy);
      for (std::size_t b = ss.first; b < std::size_t(ss.first) + ss.count; ++b) {
        if (b == a) continue;
        for (std::uint16_t v : {n.segs[b].v1, n.segs[b].v2}) {
          const double d = (dx * (at(v).y - p.y) - dy * (at(v).x - p.x)) / len;  // > 0: behind
          if (d > tolerance)
            problem(fmt::format(
                "subsector {}: not convex (seg {} has an end {:.2f} units behind seg {})", i, b, d,
                a));
        }
      }
    }
  }

  // Each seg on its linedef at its offset; each linedef side covered once from end to end.
  std::vector<std::vector<std::pair<double, double>>> cover(map.linedefs.size() * 2);
  for (std::size_t i = 0; i < n.segs.size(); ++i) {
    const Seg& s = n.segs[i];
    const Linedef& l = map.linedefs[s.linedef];
    const Vertex p = map.vertices[s.side == 0 ? l.v1 : l.v2],
                 q = map.vertices[s.side == 0 ? l.v2 : l.v1];
    const double dx = double(q.x) - p.x, dy = double(q.y) - p.y, len = std::hypot(dx, dy);
    if (len == 0) {
      problem(fmt::format("seg {}: on a linedef of zero length", i));
      continue;
    }
    double t[2];
    int k = 0;
    for (std::uint16_t v : {s.v1, s.v2}) {
      const double off = std::abs(dx * (at(v).y - p.y) - dy * (at(v).x - p.x)) / len;
      if (off > tolerance)
        problem(fmt::format("seg {}: an end {:.2f} units off linedef {}", i, off, s.linedef));
      t[k++] = (dx * (at(v).x - p.x) + dy * (at(v).y - p.y)) / len;
    }
    if (!(t[1] > t[0]))
      problem(fmt::format("seg {}: runs against its linedef side or has no length", i));
    if (std::abs(t[0] - s.offset) > tolerance + 0.5)
      problem(fmt::format("seg {}: offset {} where its start is {:.2f} along the linedef", i,
                          s.offset, t[0]));
    cover[std::size_t(s.linedef) * 2 + std::size_t(s.side)].push_back({t[0], t[1]});
  }
  for (std::size_t i = 0; i < map.linedefs.size(); ++i) {
    const Linedef& l = map.linedefs[i];
    if (!hasLength(map, l)) continue;
    const Vertex p = map.vertices[l.v1], q = map.vertices[l.v2];
    const double len = std::hypot(double(q.x) - p.x, double(q.y) - p.y);
    for (int side = 0; side < 2; ++side) {
      auto& c = cover[i * 2 + std::size_t(side)];
      if (l.side[std::size_t(side)] == kNoSide) continue;
      if (c.empty()) {
        problem(fmt::format("linedef {} side {}: no seg", i, side));
        continue;
      }
      std::sort(c.begin(), c.end());
      double reached = 0;
      for (const auto& [t0, t1] : c) {
        if (std::abs(t0 - reached) > tolerance)
          problem(fmt::format("linedef {} side {}: {} at {:.2f} to {:.2f}", i, side,
                              t0 > reached ? "a gap" : "an overlap", std::min(t0, reached),
                              std::max(t0, reached)));
        reached = t1;
      }
      if (std::abs(reached - len) > tolerance)
        problem(
            fmt::format("linedef {} side {}: covered to {:.2f} of {:.2f}", i, side, reached, len));
    }
  }
  return finish();
}

}  // namespace hsr::doom
