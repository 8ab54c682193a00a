// Building a Doom map's 2D BSP tree (its nodes), as the notes give BSP and as Doom's node
// builders do it:
//
//   1. Segs: every linedef side with a sidedef is a seg, running v1 -> v2 for the front side
//      and v2 -> v1 for the back, so that the sector it faces is always on its right.
//   2. If the segs are convex (every seg lies in front of or on every other seg's line), they
//      enclose one convex region: a subsector, the leaf.
//   3. Otherwise choose a partition line among the segs' lines (the heuristic below) and
//      classify every seg against it: in front (right of the line), behind, on it (it joins the
//      side it faces: the front when it runs the line's way), or spanning it. A spanning seg is
//      split where the line crosses it, the point rounded to whole map units as the vanilla
//      format stores it.
//   4. Build the front and the back subtree from the two lists, the same way; the node keeps
//      the line and the bounding box of each child's segs (Doom culls with them).
//
// The heuristic (BuildOptions): every distinct line through the node's segs is a candidate,
// and the one of least  split_cost * splits + |front - back|  wins, where front and back count
// the segs that would go to each side (a split seg counts on both). Splits are what the
// vanilla format pays for (every split is one more seg, and a vertex rounded off its line);
// the imbalance term keeps the tree shallow where splits are equal. ZDBSP weighs the same two
// things but looks at 64 candidates a node by default; looking at every line is what finds the
// lines that split nothing. To keep that affordable: collinear segs are one candidate, the
// count for a candidate stops as soon as its splits alone cost more than the best so far, and
// the node's segs are grouped in blocks of 16 with a bounding box, so a block the line passes
// clear of is counted in one step (the node keeps its parent's seg order, which stays close in
// space: the segs come in linedef order and every partition keeps the order on each side).
//
// Exact: vertices are integers (map units), so the sides of a line, twice the signed area
// dx (y - py) - dy (x - px), are exact in double (|values| < 2^35 < 2^53).
// Cost: O(candidates x (blocks + segs in the blocks the line crosses)) a node: 0.5-0.6 s for a
// whole Freedoom WAD (32 or 36 maps) on one core; memory: O(segs).
// Tests: tests/doom/doom_test.cpp (every map of both Freedoom WADs: checkNodes finds nothing,
// the tree's sectors agree with the linedefs', written back and read again it is the same).

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include <fmt/core.h>

#include "hsr/doom.hpp"
#include "hsr/error.hpp"
#include "core/stopwatch.hpp"

namespace hsr::doom {

namespace {

constexpr int kBlock = 16;
constexpr std::size_t kMaxTreeDepth = 1024;  // Freedoom's deepest: 105 (the recursion's bound)

// A seg while the tree is built: its (rounded, integer) endpoints and what it came from.
struct BuildSeg {
  double x1, y1, x2, y2;
  std::uint32_t v1, v2;
  std::uint32_t line;  // its linedef's line among the map's distinct lines
  std::uint16_t linedef;
  std::uint16_t side;
  std::uint16_t sector;
};

// A directed line through integer points: the partition, and which of the map's lines it is.
struct Line {
  double x, y, dx, dy;
  std::uint32_t id;
  // Twice the signed area of the triangle (line start, line end, point): < 0 right (front).
  double side(double px, double py) const { return dx * (py - y) - dy * (px - x); }
};

enum class Side { kFront, kBack, kSpanning };

// Where a seg lies against a line: on the line itself -> the side it faces; both ends on the
// right or on the line -> front; both on the left or on it -> back; else spanning. A seg of the
// line's own linedefs is on it even where a rounded split point left its end a little off.
Side classify(const BuildSeg& s, const Line& l, double& c1, double& c2) {
  c1 = l.side(s.x1, s.y1);
  c2 = l.side(s.x2, s.y2);
  if (s.line == l.id || (c1 == 0 && c2 == 0))
    return (s.x2 - s.x1) * l.dx + (s.y2 - s.y1) * l.dy > 0 ? Side::kFront : Side::kBack;
  if (c1 <= 0 && c2 <= 0) return Side::kFront;
  if (c1 >= 0 && c2 >= 0) return Side::kBack;
  return Side::kSpanning;
}

struct Box {
  double top = -1e300, bottom = 1e300, left = 1e300, right = -1e300;
  void extend(double x, double y) {
    top = std::max(top, y), bottom = std::min(bottom, y);
    left = std::min(left, x), right = std::max(right, x);
  }
  void extend(const Box& b) {
    top = std::max(top, b.top), bottom = std::min(bottom, b.bottom);
    left = std::min(left, b.left), right = std::max(right, b.right);
  }
  std::array<std::int16_t, 4> vanilla() const {
    return {static_cast<std::int16_t>(top), static_cast<std::int16_t>(bottom),
            static_cast<std::int16_t>(left), static_cast<std::int16_t>(right)};
  }
};

// What a candidate line would do to the node's segs.
struct Count {
  std::uint32_t front = 0, back = 0, splits = 0;
  bool gave_up = false;  // stopped once its splits cost more than the best
};

class Builder {
 public:
  Builder(const Map& map, const BuildOptions& options) : map_(map), options_(options) {
    nodes_.vertices = map.vertices;
    for (std::size_t i = 0; i < map.vertices.size(); ++i)
      vertex_index_.emplace(key(map.vertices[i].x, map.vertices[i].y),
                            static_cast<std::uint32_t>(i));
  }

  Nodes build(BuildStats& stats) {
    std::vector<BuildSeg> segs = initialSegs(stats);
    if (segs.empty()) throw Error(fmt::format("map {}: no linedef of nonzero length", map_.name));
    Box box;
    buildNode(std::move(segs), 0, box);
    if (nodes_.segs.size() > 65535 || nodes_.vertices.size() > 65535 ||
        nodes_.nodes.size() > 32767 || nodes_.subsectors.size() > 32767)
      throw Error(
          fmt::format("map {}: the tree passes the vanilla limits ({} segs, {} vertices, {} nodes)",
                      map_.name, nodes_.segs.size(), nodes_.vertices.size(), nodes_.nodes.size()));
    return std::move(nodes_);
  }

 private:
  static std::uint64_t key(std::int64_t x, std::int64_t y) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(x)) << 32) |
           static_cast<std::uint32_t>(y);
  }

  // Step 1: a seg for every linedef side with a sidedef; collinear linedefs share a line.
  std::vector<BuildSeg> initialSegs(BuildStats& stats) {
    std::unordered_map<std::string, std::uint32_t> lines;
    std::vector<BuildSeg> segs;
    for (std::size_t i = 0; i < map_.linedefs.size(); ++i) {
      const Linedef& l = map_.linedefs[i];
      const Vertex a = map_.vertices[l.v1], b = map_.vertices[l.v2];
      if (a.x == b.x && a.y == b.y) continue;
      // The line as A x + B y = C with gcd 1 and A > 0 (or A = 0, B > 0): one key per line.
      std::int64_t A = std::int64_t(b.y) - a.y, B = std::int64_t(a.x) - b.x;
      std::int64_t C = A * a.x + B * a.y;
      const std::int64_t g = std::gcd(std::gcd(A, B), C);
      A /= g, B /= g, C /= g;
      if (A < 0 || (A == 0 && B < 0)) A = -A, B = -B, C = -C;
      const auto [it, fresh] =
          lines.emplace(fmt::format("{},{},{}", A, B, C), static_cast<std::uint32_t>(lines.size()));
      (void)fresh;
      for (std::uint16_t side = 0; side < 2; ++side) {
        if (l.side[side] == kNoSide) continue;
        BuildSeg s{};
        const Vertex& from = side == 0 ? a : b;
        const Vertex& to = side == 0 ? b : a;
        s.x1 = from.x, s.y1 = from.y, s.x2 = to.x, s.y2 = to.y;
        s.v1 = side == 0 ? l.v1 : l.v2;
        s.v2 = side == 0 ? l.v2 : l.v1;
        s.line = it->second;
        s.linedef = static_cast<std::uint16_t>(i);
        s.side = side;
        s.sector = map_.sidedefs[l.side[side]].sector;
        segs.push_back(s);
      }
    }
    line_count_ = lines.size();
    stats.sides = segs.size();
    return segs;
  }

  // The partition along a seg: its linedef's own line (exact integers), in the seg's direction.
  Line lineOf(const BuildSeg& s) const {
    const Linedef& l = map_.linedefs[s.linedef];
    const Vertex a = map_.vertices[s.side == 0 ? l.v1 : l.v2],
                 b = map_.vertices[s.side == 0 ? l.v2 : l.v1];
    return {double(a.x), double(a.y), double(b.x) - a.x, double(b.y) - a.y, s.line};
  }

  // The node's segs in blocks of kBlock, each with its bounding box.
  struct Blocks {
    std::vector<Box> boxes;
    void make(const std::vector<BuildSeg>& segs) {
      boxes.assign((segs.size() + kBlock - 1) / kBlock, Box{});
      for (std::size_t i = 0; i < segs.size(); ++i) {
        boxes[i / kBlock].extend(segs[i].x1, segs[i].y1);
        boxes[i / kBlock].extend(segs[i].x2, segs[i].y2);
      }
    }
  };

  // Step 3's count for one candidate, stopping when split_cost * splits reaches `best`.
  Count count(const std::vector<BuildSeg>& segs, const Blocks& blocks, const Line& l,
              double best) const {
    Count c;
    const double limit = best / options_.split_cost;
    for (std::size_t b = 0; b < blocks.boxes.size(); ++b) {
      const Box& box = blocks.boxes[b];
      const std::size_t first = b * kBlock, last = std::min(segs.size(), first + kBlock);
      // The extremes of the side function over the box: it is linear in x and y.
      const double hi = l.dx * ((l.dx > 0 ? box.top : box.bottom) - l.y) -
                        l.dy * ((l.dy > 0 ? box.left : box.right) - l.x);
      const double lo = l.dx * ((l.dx > 0 ? box.bottom : box.top) - l.y) -
                        l.dy * ((l.dy > 0 ? box.right : box.left) - l.x);
      if (hi < 0) {
        c.front += static_cast<std::uint32_t>(last - first);
        continue;
      }
      if (lo > 0) {
        c.back += static_cast<std::uint32_t>(last - first);
        continue;
      }
      for (std::size_t i = first; i < last; ++i) {
        double c1, c2;
        switch (classify(segs[i], l, c1, c2)) {
          case Side::kFront:
            ++c.front;
            break;
          case Side::kBack:
            ++c.back;
            break;
          case Side::kSpanning:
            ++c.front, ++c.back, ++c.splits;
            if (c.splits >= limit) {
              c.gave_up = true;
              return c;
            }
        }
      }
    }
    return c;
  }

  // Step 3's choice: the candidate of least cost; -1 when no line leaves segs on its back (the
  // segs are convex: a subsector).
  std::ptrdiff_t choose(const std::vector<BuildSeg>& segs, const std::vector<char>& refused) {
    blocks_.make(segs);
    seen_.assign(line_count_, 0);
    double best = 1e300;
    std::ptrdiff_t chosen = -1;
    for (std::size_t i = 0; i < segs.size(); ++i) {
      if (seen_[segs[i].line] || refused[i]) continue;
      seen_[segs[i].line] = 1;
      const Count c = count(segs, blocks_, lineOf(segs[i]), best);
      if (c.gave_up || (c.back == 0 && c.splits == 0)) continue;
      const double cost =
          double(options_.split_cost) * c.splits + std::abs(double(c.front) - double(c.back));
      if (cost < best) best = cost, chosen = static_cast<std::ptrdiff_t>(i);
    }
    return chosen;
  }

  std::uint32_t vertexAt(double x, double y) {
    const auto [it, fresh] = vertex_index_.emplace(
        key(std::int64_t(x), std::int64_t(y)), static_cast<std::uint32_t>(nodes_.vertices.size()));
    if (fresh)
      nodes_.vertices.push_back({static_cast<std::int16_t>(x), static_cast<std::int16_t>(y)});
    return it->second;
  }

  // Step 3's split: every seg to its side; a spanning one cut at the line, the point rounded.
  // A cut that rounds onto an end of the seg leaves it whole, on the side of its other end.
  void partition(const std::vector<BuildSeg>& segs, const Line& l, std::vector<BuildSeg>& front,
                 std::vector<BuildSeg>& back) {
    for (const BuildSeg& s : segs) {
      double c1, c2;
      const Side side = classify(s, l, c1, c2);
      if (side == Side::kFront) {
        front.push_back(s);
        continue;
      }
      if (side == Side::kBack) {
        back.push_back(s);
        continue;
      }
      // The crossing on the seg's linedef itself (exact integers), not on the piece that earlier
      // rounding may have moved: every split point stays within half a unit of its linedef.
      const Line own = lineOf(s);
      const double along = l.dx * own.dy - l.dy * own.dx;
      const double u = along != 0 ? -l.side(own.x, own.y) / along : 0;
      const double t = c1 / (c1 - c2);
      const double x = std::nearbyint(along != 0 ? own.x + u * own.dx : s.x1 + t * (s.x2 - s.x1));
      const double y = std::nearbyint(along != 0 ? own.y + u * own.dy : s.y1 + t * (s.y2 - s.y1));
      if ((x == s.x1 && y == s.y1) || (x == s.x2 && y == s.y2)) {
        const double other = (x == s.x1 && y == s.y1) ? c2 : c1;
        (other < 0 ? front : back).push_back(s);
        continue;
      }
      const std::uint32_t v = vertexAt(x, y);
      BuildSeg a = s, b = s;
      a.x2 = x, a.y2 = y, a.v2 = v;
      b.x1 = x, b.y1 = y, b.v1 = v;
      (c1 < 0 ? front : back).push_back(a);
      (c2 < 0 ? front : back).push_back(b);
    }
  }

  // Steps 2 to 4 for one node; returns its child number (kSubsectorBit for a subsector).
  std::uint16_t buildNode(std::vector<BuildSeg> segs, std::uint64_t level, Box& box) {
    if (level >= kMaxTreeDepth)
      throw Error(fmt::format("map {}: the tree passes {} levels", map_.name, kMaxTreeDepth));
    std::vector<char> refused(segs.size(), 0);
    for (;;) {
      const std::ptrdiff_t chosen = choose(segs, refused);
      if (chosen < 0) return leaf(segs, box);
      const Line l = lineOf(segs[std::size_t(chosen)]);
      std::vector<BuildSeg> front, back;
      partition(segs, l, front, back);
      if (front.empty() || back.empty()) {  // every cut rounded onto one side: try another line
        for (std::size_t i = 0; i < segs.size(); ++i)
          if (segs[i].line == segs[std::size_t(chosen)].line) refused[i] = 1;
        continue;
      }
      segs.clear();
      segs.shrink_to_fit();
      Node node;
      node.x = static_cast<std::int16_t>(l.x), node.y = static_cast<std::int16_t>(l.y);
      if (l.dx < -32768 || l.dx > 32767 || l.dy < -32768 || l.dy > 32767)
        throw Error(
            fmt::format("map {}: a linedef too long for a vanilla node's partition", map_.name));
      node.dx = static_cast<std::int16_t>(l.dx), node.dy = static_cast<std::int16_t>(l.dy);
      Box front_box, back_box;
      node.child[0] = buildNode(std::move(front), level + 1, front_box);
      node.child[1] = buildNode(std::move(back), level + 1, back_box);
      node.box[0] = front_box.vanilla();
      node.box[1] = back_box.vanilla();
      box = front_box;
      box.extend(back_box);
      nodes_.nodes.push_back(node);
      return static_cast<std::uint16_t>(std::min<std::size_t>(nodes_.nodes.size() - 1, 0x7FFF));
    }
  }

  std::uint16_t leaf(const std::vector<BuildSeg>& segs, Box& box) {
    Subsector ss;
    ss.first = static_cast<std::uint16_t>(nodes_.segs.size());
    ss.count = static_cast<std::uint16_t>(segs.size());
    for (const BuildSeg& s : segs) {
      box.extend(s.x1, s.y1);
      box.extend(s.x2, s.y2);
      Seg out;
      out.v1 = static_cast<std::uint16_t>(s.v1);
      out.v2 = static_cast<std::uint16_t>(s.v2);
      out.linedef = s.linedef;
      out.side = static_cast<std::int16_t>(s.side);
      const double angle = std::atan2(s.y2 - s.y1, s.x2 - s.x1);  // radians, -pi..pi
      out.angle = static_cast<std::int16_t>(static_cast<std::uint16_t>(
          static_cast<std::int64_t>(std::nearbyint(angle / (2 * M_PI) * 65536.0)) & 0xFFFF));
      const Linedef& l = map_.linedefs[s.linedef];
      const Vertex start = map_.vertices[s.side == 0 ? l.v1 : l.v2];
      const double offset = std::nearbyint(std::hypot(s.x1 - start.x, s.y1 - start.y));
      if (offset > 32767)
        throw Error(fmt::format("map {}: linedef {} is too long for a vanilla seg's offset",
                                map_.name, s.linedef));
      out.offset = static_cast<std::int16_t>(offset);
      nodes_.segs.push_back(out);
    }
    nodes_.subsectors.push_back(ss);
    return static_cast<std::uint16_t>(kSubsectorBit |
                                      std::min<std::size_t>(nodes_.subsectors.size() - 1, 0x7FFF));
  }

  const Map& map_;
  BuildOptions options_;
  Nodes nodes_;
  std::unordered_map<std::uint64_t, std::uint32_t> vertex_index_;
  std::size_t line_count_ = 0;
  Blocks blocks_;
  std::vector<char> seen_;
};

}  // namespace

Nodes buildNodes(const Map& map, const BuildOptions& options, BuildStats* stats) {
  if (options.split_cost < 1 || options.split_cost > 1 << 16)
    throw Error(fmt::format("split cost {} is outside 1..65536", options.split_cost));
  const detail::Stopwatch start;
  BuildStats sides;
  Nodes nodes = Builder(map, options).build(sides);
  BuildStats s = nodeStats(map, nodes);  // the figures of the tree as it is
  s.build_ms = start.ms();
  if (stats) *stats = s;
  return nodes;
}

}  // namespace hsr::doom
