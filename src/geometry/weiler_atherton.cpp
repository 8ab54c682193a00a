// Weiler-Atherton clipping (Weiler & Atherton 1977; Weiler 1980, "Polygon comparison using a
// graph representation"): the boundaries of A and B are cut where they meet, each piece of
// boundary is labelled inside or outside the other polygon, the pieces an operation keeps are
// chosen, and the result is walked: follow A's vertex list, and where it meets B switch to B's
// list (and back), until the walk comes home. The notes' four operations differ only in which
// pieces they keep:
//   A∩B: pieces of A inside B, and of B inside A;
//   A∪B: pieces of A outside B, and of B outside A;
//   A−B: pieces of A outside B, and of B inside A walked backwards; B−A the other way round.
//
// Exactness (the guarantee of this file): every edge lies on a line through two grid points,
// a x + b y + c = 0 with integer a, b, c; every vertex is an input vertex or the crossing of
// two such lines, (X / D, Y / D) in integers. With |coordinates| <= 2^28, a, b < 2^30,
// c < 2^59, D < 2^60, X and Y < 2^89, and the side of a line a vertex lies on,
// a X + b Y + c D, stays below 2^120: every test is an exact integer sign in __int128. Only
// comparing two vertices' coordinates needs 192 bits (compareFractions).

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "geometry/predicates.hpp"
#include "hsr/clipping.hpp"

namespace hsr {
namespace {

using i128 = __int128;
using u128 = unsigned __int128;

int sign(i128 v) { return (v > 0) - (v < 0); }

// A line a x + b y + c = 0 through p in direction (dx, dy) = (-b, a): positive on its left.
struct Line {
  std::int64_t a = 0, b = 0, c = 0;
};

Line lineThrough(GridPoint p, std::int64_t dx, std::int64_t dy) {
  return {-dy, dx, dy * p.x - dx * p.y};
}

// Exact vertex (X / D, Y / D), D > 0.
struct Vertex {
  i128 x = 0, y = 0;
  std::int64_t d = 1;
};

Vertex crossing(const Line& l, const Line& m) {
  i128 d = i128{l.a} * m.b - i128{m.a} * l.b;
  i128 x = i128{l.b} * m.c - i128{m.b} * l.c, y = i128{m.a} * l.c - i128{l.a} * m.c;
  if (d < 0) d = -d, x = -x, y = -y;
  return {x, y, static_cast<std::int64_t>(d)};
}

// Which side of line l the vertex lies on: +1 left, -1 right, 0 on it.
int side(const Line& l, const Vertex& v) {
  return sign(i128{l.a} * v.x + i128{l.b} * v.y + i128{l.c} * v.d);
}

// sign(p / q - r / s) for q, s > 0, |p|, |r| < 2^127: the products need 192 bits.
struct U192 {
  std::uint64_t w[3];
};
U192 multiply(u128 a, std::uint64_t b) {
  const u128 lo = static_cast<u128>(static_cast<std::uint64_t>(a)) * b;
  const u128 hi = static_cast<u128>(static_cast<std::uint64_t>(a >> 64)) * b;
  const u128 mid = (lo >> 64) + static_cast<std::uint64_t>(hi);
  return {{static_cast<std::uint64_t>(lo), static_cast<std::uint64_t>(mid),
           static_cast<std::uint64_t>(hi >> 64) + static_cast<std::uint64_t>(mid >> 64)}};
}
int compareFractions(i128 p, std::int64_t q, i128 r, std::int64_t s) {
  if (q == s) return sign(p - r);  // (grid points: both 1)
  const int sp = sign(p), sr = sign(r);
  if (sp != sr) return sp > sr ? 1 : -1;
  if (sp == 0) return 0;
  const U192 left = multiply(static_cast<u128>(sp > 0 ? p : -p), static_cast<std::uint64_t>(s));
  const U192 right = multiply(static_cast<u128>(sr > 0 ? r : -r), static_cast<std::uint64_t>(q));
  for (int k = 2; k >= 0; --k)
    if (left.w[k] != right.w[k]) return (left.w[k] > right.w[k] ? 1 : -1) * sp;
  return 0;
}

// Directions: integer vectors of edges. cross > 0: b turns left of a.
i128 cross(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by) {
  return i128{ax} * by - i128{ay} * bx;
}
i128 dot(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by) {
  return i128{ax} * bx + i128{ay} * by;
}

struct Direction {
  std::int64_t x = 0, y = 0;
  Direction reversed() const { return {-x, -y}; }
};

// Turning counter-clockwise from `from`, is `a` met before `b`? (angles in [0, 360), `from`
// itself at 0).
bool metBefore(Direction from, Direction a, Direction b) {
  auto half = [&](Direction v) {
    const i128 c = cross(from.x, from.y, v.x, v.y);
    return c < 0 || (c == 0 && dot(from.x, from.y, v.x, v.y) < 0) ? 1 : 0;
  };
  const int ha = half(a), hb = half(b);
  if (ha != hb) return ha < hb;
  return cross(a.x, a.y, b.x, b.y) > 0;
}
bool sameDirection(Direction a, Direction b) {
  return cross(a.x, a.y, b.x, b.y) == 0 && dot(a.x, a.y, b.x, b.y) > 0;
}

// The region left of a boundary that comes into a point along `in` and leaves along `out`:
// does direction u point into it? (strictly: not along the boundary itself)
bool pointsInto(Direction in, Direction out, Direction u) {
  if (sameDirection(u, out) || sameDirection(u, in.reversed())) return false;
  return metBefore(out, u, in.reversed());
}

i128 twiceSignedArea(const GridRing& r) {
  i128 s = 0;
  for (std::size_t i = 0, n = r.size(); i < n; ++i)
    s += cross(r[i].x, r[i].y, r[(i + 1) % n].x, r[(i + 1) % n].y);
  return s;
}

// ------------------------------------------------------------------------------------------
// The graph of both boundaries

enum Owner : std::uint8_t { kA = 0, kB = 1 };

// Where a vertex lies along a line walked in direction d: (v · d) / v.d, compared exactly.
struct Param {
  i128 num;
  std::int64_t den;
};
Param along(const Vertex& v, Direction d) { return {v.x * d.x + v.y * d.y, v.d}; }
int compare(Param l, Param r) { return compareFractions(l.num, l.den, r.num, r.den); }

std::int64_t floorDiv(i128 x, std::int64_t d) {
  if (d == 1) return static_cast<std::int64_t>(x);
  i128 q = x / d;
  if (q * d > x) --q;
  return static_cast<std::int64_t>(q);
}
std::int64_t ceilDiv(i128 x, std::int64_t d) {
  return d == 1 ? static_cast<std::int64_t>(x) : -floorDiv(-x, d);
}

struct Edge {
  Vertex v0, v1;     // its ends
  Direction d;       // along its line, from v0 to v1
  Line line;         // positive on its left
  Param t0, t1;      // its ends along d (t0 < t1)
  int node0, node1;  // graph nodes of the two ends
  int ring;          // ring index (over both regions)
  Owner owner;
  std::int64_t x0, x1, y0, y1;  // a box around it, on the grid
};

// A point inside an edge, at parameter t along it.
struct Hit {
  int edge;
  Param t;
  int node;
};

// A piece of boundary between two consecutive points on an edge.
struct Piece {
  int from, to, edge;
};

enum class Label : std::uint8_t { Outside, Inside, SharedSame, SharedOpposite };

struct Ring {
  Owner owner;
  int first_edge, edge_count;
  int first_piece = 0, piece_count = 0;
};

Direction directionOf(const Line& l) { return {l.b, -l.a}; }

class Graph {
 public:
  std::vector<Vertex> nodes;
  std::vector<Edge> edges;
  std::vector<Ring> rings;
  std::vector<Hit> hits;
  std::vector<Piece> pieces;
  std::vector<Label> labels;
  std::vector<int> parent;  // union-find over nodes that turn out to be one point

  // Empty again, keeping the memory: one Graph per thread serves every call (small clips are
  // otherwise half allocation).
  void reset() {
    nodes.clear(), edges.clear(), rings.clear(), hits.clear(), pieces.clear(), labels.clear(),
        parent.clear();
  }

  int find(int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  }
  void unite(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }

  void addRing(const ExactRing& r, bool counter_clockwise, Owner owner) {
    const int n = static_cast<int>(r.size()), base = static_cast<int>(nodes.size());
    const int ring = static_cast<int>(rings.size());
    rings.push_back({owner, static_cast<int>(edges.size()), n});
    auto vertex = [](const ExactPoint& p) { return Vertex{p.x, p.y, p.d}; };
    auto line = [](const ExactPoint& p) { return Line{p.a, p.b, p.c}; };
    // Which way round it runs: the turn at its lowest (then leftmost) vertex
    int low = 0;
    for (int i = 1; i < n; ++i) {
      const int cy = compareFractions(r[i].y, r[i].d, r[low].y, r[low].d);
      if (cy < 0 || (cy == 0 && compareFractions(r[i].x, r[i].d, r[low].x, r[low].d) < 0)) low = i;
    }
    const Direction in = directionOf(line(r[(low + n - 1) % n])), out = directionOf(line(r[low]));
    const bool as_given = (cross(in.x, in.y, out.x, out.y) > 0) == counter_clockwise;
    // Vertex i and the line of the edge leaving it, walked the chosen way round
    auto at = [&](int i) { return vertex(as_given ? r[i] : r[n - 1 - i]); };
    auto lineFrom = [&](int i) {
      if (as_given) return line(r[i]);
      const Line l = line(r[(2 * n - 2 - i) % n]);  // the edge from n-1-i back to n-2-i, turned
      return Line{-l.a, -l.b, -l.c};
    };
    for (int i = 0; i < n; ++i) nodes.push_back(at(i));
    for (int i = 0; i < n; ++i) {
      const Vertex p = at(i), q = at((i + 1) % n);
      const Line l = lineFrom(i);
      const Direction d = directionOf(l);
      edges.push_back({p, q, d, l, along(p, d), along(q, d), base + i, base + (i + 1) % n, ring,
                       owner, std::min(floorDiv(p.x, p.d), floorDiv(q.x, q.d)),
                       std::max(ceilDiv(p.x, p.d), ceilDiv(q.x, q.d)),
                       std::min(floorDiv(p.y, p.d), floorDiv(q.y, q.d)),
                       std::max(ceilDiv(p.y, p.d), ceilDiv(q.y, q.d))});
    }
  }
  void addRegion(const ExactRegion& region, Owner owner) {
    for (const ExactPolygon& poly : region) {
      addRing(poly.outer, true, owner);
      for (const ExactRing& h : poly.holes) addRing(h, false, owner);
    }
  }

  // Vertex v (node `node`) lies inside edge e: a hit there.
  void hitAt(int e, const Vertex& v, int node) { hits.push_back({e, along(v, edges[e].d), node}); }

  // 1. Find where the boundaries meet, and insert those points into both vertex lists.
  void intersect(int ea, int eb) {
    const Edge &A = edges[ea], &B = edges[eb];
    const int s0 = side(B.line, A.v0), s1 = side(B.line, A.v1);
    if (s0 * s1 > 0) return;
    const int r0 = side(A.line, B.v0), r1 = side(A.line, B.v1);
    if (r0 * r1 > 0) return;
    if (s0 == 0 && s1 == 0) {
      // Collinear: each end that lies inside the other edge is a point of both boundaries;
      // ends that coincide are one node.
      auto place = [&](int on, const Vertex& v, int node) {
        const Edge& E = edges[on];
        const Param t = along(v, E.d);
        const int from = compare(t, E.t0), to = compare(t, E.t1);
        if (from < 0 || to > 0) return;
        if (from == 0)
          unite(node, E.node0);
        else if (to == 0)
          unite(node, E.node1);
        else
          hitAt(on, v, node);
      };
      place(ea, B.v0, B.node0);
      place(ea, B.v1, B.node1);
      place(eb, A.v0, A.node0);
      place(eb, A.v1, A.node1);
      return;
    }
    // The lines cross at one point, and it lies on both edges.
    if (s0 == 0 || s1 == 0) {  // at an end of A's edge
      const int node = s0 == 0 ? A.node0 : A.node1;
      if (r0 == 0)
        unite(node, B.node0);
      else if (r1 == 0)
        unite(node, B.node1);
      else
        hitAt(eb, s0 == 0 ? A.v0 : A.v1, node);
    } else if (r0 == 0 || r1 == 0) {  // at an end of B's edge, inside A's
      hitAt(ea, r0 == 0 ? B.v0 : B.v1, r0 == 0 ? B.node0 : B.node1);
    } else {  // a proper crossing: a new vertex on both lists
      const int node = static_cast<int>(nodes.size());
      const Vertex v = crossing(A.line, B.line);
      nodes.push_back(v);
      parent.push_back(node);
      hitAt(ea, v, node);
      hitAt(eb, v, node);
    }
  }

  void build(const ExactRegion& a, const ExactRegion& b) {
    addRegion(a, kA);
    const int first_b = static_cast<int>(edges.size());
    addRegion(b, kB);
    parent.resize(nodes.size());
    std::iota(parent.begin(), parent.end(), 0);
    // Every pair of an edge of A and an edge of B whose boxes overlap. B's edges sorted by
    // their left end, so that each edge of A looks only at those that start within the widest
    // of B's edges before it, and before it ends.
    const int edge_count = static_cast<int>(edges.size());
    auto pairs = [&](int first0, int end0, int first1, int end1, bool other_ring_only) {
      std::vector<int> by_x(static_cast<std::size_t>(end1 - first1));
      std::iota(by_x.begin(), by_x.end(), first1);
      // Ties by number: every sort here is a total order, so that every standard library (the
      // native build's and the web page's) puts them in the same order
      std::sort(by_x.begin(), by_x.end(), [&](int l, int r) {
        return edges[l].x0 != edges[r].x0 ? edges[l].x0 < edges[r].x0 : l < r;
      });
      std::int64_t widest = 0;
      for (int e : by_x) widest = std::max(widest, edges[e].x1 - edges[e].x0);
      for (int ea = first0; ea < end0; ++ea) {
        const Edge& A = edges[ea];
        const auto from = std::partition_point(by_x.begin(), by_x.end(),
                                               [&](int e) { return edges[e].x0 < A.x0 - widest; });
        for (auto it = from; it != by_x.end(); ++it) {
          const int eb = *it;
          const Edge& B = edges[eb];
          if (B.x0 > A.x1) break;
          if (B.x1 < A.x0 || B.y1 < A.y0 || B.y0 > A.y1) continue;
          if (other_ring_only && B.ring <= A.ring) continue;
          intersect(ea, eb);
        }
      }
    };
    pairs(0, first_b, first_b, edge_count, false);
    // Rings of one region may touch at points: find those too, so that a point where two rings
    // of one region meet is one node (needed only where a region has several rings)
    if (first_b > 0 && edges[first_b - 1].ring > edges[0].ring) pairs(0, first_b, 0, first_b, true);
    if (first_b < edge_count && edges[edge_count - 1].ring > edges[first_b].ring)
      pairs(first_b, edge_count, first_b, edge_count, true);
    // Sort the points inside each edge along it; points at the same place are one node.
    std::sort(hits.begin(), hits.end(), [](const Hit& l, const Hit& r) {
      if (l.edge != r.edge) return l.edge < r.edge;
      const int c = compare(l.t, r.t);
      return c != 0 ? c < 0 : l.node < r.node;
    });
    for (std::size_t i = 1; i < hits.size(); ++i)
      if (hits[i].edge == hits[i - 1].edge && compare(hits[i].t, hits[i - 1].t) == 0)
        unite(hits[i].node, hits[i - 1].node);
    // The pieces, ring by ring in boundary order: from each edge's start, through the points
    // found inside it (never at its ends), to its end
    std::size_t h = 0;
    for (Ring& r : rings) {
      r.first_piece = static_cast<int>(pieces.size());
      for (int e = r.first_edge; e < r.first_edge + r.edge_count; ++e) {
        int last = find(edges[e].node0);
        for (; h < hits.size() && hits[h].edge == e; ++h) {
          const int node = find(hits[h].node);
          if (node != last) pieces.push_back({last, node, e});
          last = node;
        }
        const int end = find(edges[e].node1);
        if (end != last) pieces.push_back({last, end, e});
      }
      r.piece_count = static_cast<int>(pieces.size()) - r.first_piece;
    }
  }

  int nextInRing(int p) const {
    const Ring& r = rings[edges[pieces[p].edge].ring];
    return p + 1 < r.first_piece + r.piece_count ? p + 1 : r.first_piece;
  }
  Direction direction(int p) const { return edges[pieces[p].edge].d; }
  Owner owner(int p) const { return edges[pieces[p].edge].owner; }
};

// For each node, the passages of each region's boundary through it: (piece in, piece out).
struct Passages {
  std::vector<int> start;  // per node + 1
  std::vector<std::pair<int, int>> items;
  std::vector<int> fill;  // (working memory)
  void build(const Graph& g, Owner owner) {
    start.assign(g.nodes.size() + 1, 0);
    for (std::size_t p = 0; p < g.pieces.size(); ++p)
      if (g.owner(static_cast<int>(p)) == owner) ++start[g.pieces[p].to + 1];
    for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
    items.resize(start.back());
    fill.assign(start.begin(), start.end() - 1);
    for (std::size_t p = 0; p < g.pieces.size(); ++p)
      if (g.owner(static_cast<int>(p)) == owner)
        items[fill[g.pieces[p].to]++] = {static_cast<int>(p), g.nextInRing(static_cast<int>(p))};
  }
  bool touches(int node) const { return start[node] != start[node + 1]; }
};

// Crossing-number test of a vertex that is on no edge of `owner`'s boundary: is it inside?
// (A horizontal ray to the right of it, counted against that boundary's edges.)
bool insideBoundary(const Graph& g, const Vertex& p, Owner owner) {
  bool inside = false;
  for (const Edge& e : g.edges) {
    if (e.owner != owner) continue;
    const bool a_above = compareFractions(e.v0.y, e.v0.d, p.y, p.d) > 0,
               b_above = compareFractions(e.v1.y, e.v1.d, p.y, p.d) > 0;
    if (a_above == b_above) continue;
    // The edge crosses the horizontal through p; it crosses right of p when p lies left of
    // the edge walked upwards.
    const int s = side(e.line, p);
    if (b_above ? s > 0 : s < 0) inside = !inside;
  }
  return inside;
}

// 2. Label each piece: inside or outside the other region, or shared with its boundary (the
// same way round or the opposite way). A piece that starts where the other boundary passes
// is labelled by the angle it leaves at; one that starts elsewhere inherits the label of the
// piece before it (its status can change only where the boundaries meet); a ring that never
// meets the other boundary is inside or outside as a whole (a crossing-number test).
void label(Graph& g) {
  g.labels.assign(g.pieces.size(), Label::Outside);
  thread_local Passages passages[2];
  passages[kA].build(g, kA);
  passages[kB].build(g, kB);
  // Shared pieces: the same two nodes on both boundaries
  thread_local std::vector<std::pair<std::pair<int, int>, int>> keys;
  keys.clear();
  for (std::size_t p = 0; p < g.pieces.size(); ++p)
    if (g.owner(static_cast<int>(p)) == kB)
      keys.push_back(
          {{std::min(g.pieces[p].from, g.pieces[p].to), std::max(g.pieces[p].from, g.pieces[p].to)},
           static_cast<int>(p)});
  std::sort(keys.begin(), keys.end());
  thread_local std::vector<std::int8_t> shared;  // +1 same way, -1 opposite
  shared.assign(g.pieces.size(), 0);
  for (std::size_t p = 0; p < g.pieces.size(); ++p) {
    const Piece& P = g.pieces[p];
    if (g.owner(static_cast<int>(p)) != kA) continue;
    const std::pair<int, int> key{std::min(P.from, P.to), std::max(P.from, P.to)};
    const auto it =
        std::lower_bound(keys.begin(), keys.end(), std::pair<std::pair<int, int>, int>{key, -1});
    if (it == keys.end() || it->first != key) continue;
    const int q = it->second;
    const std::int8_t way = g.pieces[q].from == P.from ? 1 : -1;
    shared[p] = shared[q] = way;
  }

  for (const Ring& r : g.rings) {
    if (r.piece_count == 0) continue;
    const Owner other = r.owner == kA ? kB : kA;
    const Passages& there = passages[other];
    auto decided = [&](int p, Label* out) {
      if (shared[p] != 0) {
        *out = shared[p] > 0 ? Label::SharedSame : Label::SharedOpposite;
        return true;
      }
      const int node = g.pieces[p].from;
      if (!there.touches(node)) return false;
      // Round the point, the other region lies counter-clockwise after each of its boundary's
      // pieces leaving the point, up to the next piece arriving. So the piece is inside when
      // the first of the other boundary's pieces met turning clockwise from it leaves the point.
      const Direction u = g.direction(p);
      Direction nearest{};
      bool nearest_leaves = false, any = false;
      for (int k = there.start[node]; k < there.start[node + 1]; ++k) {
        const auto [arriving, leaving] = there.items[k];
        for (const auto& [d, leaves] : {std::pair{g.direction(leaving), true},
                                        std::pair{g.direction(arriving).reversed(), false}}) {
          if (sameDirection(d, u)) continue;  // only for a shared piece, decided above
          if (!any || metBefore(u, nearest, d)) nearest = d, nearest_leaves = leaves, any = true;
        }
      }
      *out = nearest_leaves ? Label::Inside : Label::Outside;
      return true;
    };
    int start = -1;
    Label current = Label::Outside;
    for (int p = r.first_piece; p < r.first_piece + r.piece_count && start < 0; ++p)
      if (decided(p, &current)) start = p;
    if (start < 0) {  // never meets the other boundary
      const bool inside = insideBoundary(g, g.edges[g.pieces[r.first_piece].edge].v0, other);
      for (int p = r.first_piece; p < r.first_piece + r.piece_count; ++p)
        g.labels[p] = inside ? Label::Inside : Label::Outside;
      continue;
    }
    int p = start;
    do {
      Label l;
      if (decided(p, &l))
        current = l;
      else if (current == Label::SharedSame || current == Label::SharedOpposite)
        current = Label::Outside;  // cannot happen: a shared piece ends where the boundaries meet
      g.labels[p] = current;
      p = g.nextInRing(p);
    } while (p != start);
  }
}

// A kept piece, walked from -> to along direction d on line `line` (reversed pieces turned).
struct Kept {
  int from, to;
  Direction d;
  Line line;
};

// 3. Keep the pieces the operation asks for.
const std::vector<Kept>& keep(const Graph& g, BooleanOp op) {
  thread_local std::vector<Kept> kept;
  kept.clear();
  for (std::size_t i = 0; i < g.pieces.size(); ++i) {
    const int p = static_cast<int>(i);
    const Owner o = g.owner(p);
    const Label l = g.labels[i];
    bool forward = false, backward = false;
    switch (op) {
      case BooleanOp::Intersection:
        forward = l == Label::Inside || (l == Label::SharedSame && o == kA);
        break;
      case BooleanOp::Union:
        forward = l == Label::Outside || (l == Label::SharedSame && o == kA);
        break;
      case BooleanOp::AMinusB:
        forward = o == kA && (l == Label::Outside || l == Label::SharedOpposite);
        backward = o == kB && l == Label::Inside;
        break;
      case BooleanOp::BMinusA:
        forward = o == kB && (l == Label::Outside || l == Label::SharedOpposite);
        backward = o == kA && l == Label::Inside;
        break;
    }
    const Edge& e = g.edges[g.pieces[i].edge];
    if (forward) kept.push_back({g.pieces[i].from, g.pieces[i].to, e.d, e.line});
    if (backward)
      kept.push_back(
          {g.pieces[i].to, g.pieces[i].from, e.d.reversed(), {-e.line.a, -e.line.b, -e.line.c}});
  }
  return kept;
}

struct RingOut {
  std::vector<int> nodes;
  std::vector<Direction> out;  // direction leaving each node
  std::vector<Line> lines;     // the line of that piece
};

// 4. Walk the kept pieces into closed rings: from each piece go on with the piece that leaves
// its end; where several leave one point (the regions touch there), take the first one met
// turning clockwise from the way back, so that each ring keeps its region on its left and
// closes on the nearest corner.
std::vector<RingOut> walk(const Graph& g, const std::vector<Kept>& kept) {
  thread_local std::vector<int> start, leaving, fill;
  thread_local std::vector<char> used;
  start.assign(g.nodes.size() + 1, 0);
  for (const Kept& k : kept) ++start[k.from + 1];
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  leaving.resize(kept.size());
  {
    fill.assign(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < kept.size(); ++k)
      leaving[fill[kept[k].from]++] = static_cast<int>(k);
  }
  used.assign(kept.size(), 0);
  std::vector<RingOut> rings;
  for (std::size_t first = 0; first < kept.size(); ++first) {
    if (used[first]) continue;
    RingOut ring;
    int cur = static_cast<int>(first);
    for (std::size_t steps = 0; steps <= kept.size(); ++steps) {
      used[cur] = 1;
      ring.nodes.push_back(kept[cur].from);
      ring.out.push_back(kept[cur].d);
      ring.lines.push_back(kept[cur].line);
      const int node = kept[cur].to;
      const Direction back = kept[cur].d.reversed();
      int next = -1;
      for (int i = start[node]; i < start[node + 1]; ++i) {
        const int c = leaving[i];
        // the largest counter-clockwise angle from the way back (the way back itself last)
        if (next < 0)
          next = c;
        else if (sameDirection(kept[next].d, back))
          next = c;
        else if (!sameDirection(kept[c].d, back) && metBefore(back, kept[next].d, kept[c].d))
          next = c;
      }
      if (next < 0 || next == static_cast<int>(first)) break;
      if (used[next]) break;  // only on invalid input: the ring is left open
      cur = next;
    }
    rings.push_back(std::move(ring));
  }
  return rings;
}

// Split a ring that passes one point twice into rings that pass it once, then drop the points
// where a ring runs straight on (in that order: a point passed twice may be passed straight once).
std::vector<RingOut> tidy(std::vector<RingOut> rings, std::size_t node_count) {
  std::vector<RingOut> loops;
  thread_local std::vector<int> seen;
  seen.assign(node_count, -1);
  for (RingOut& r : rings) {
    // A stack of points; when a point comes round again, the points since its first visit
    // close a ring of their own.
    RingOut stack;
    for (std::size_t i = 0; i < r.nodes.size(); ++i) {
      const int node = r.nodes[i];
      if (seen[node] >= 0) {
        const std::size_t from = static_cast<std::size_t>(seen[node]);
        RingOut loop;
        loop.nodes.assign(stack.nodes.begin() + from, stack.nodes.end());
        loop.out.assign(stack.out.begin() + from, stack.out.end());
        loop.lines.assign(stack.lines.begin() + from, stack.lines.end());
        for (int v : loop.nodes) seen[v] = -1;
        stack.nodes.resize(from), stack.out.resize(from), stack.lines.resize(from);
        loops.push_back(std::move(loop));
      }
      seen[node] = static_cast<int>(stack.nodes.size());
      stack.nodes.push_back(node);
      stack.out.push_back(r.out[i]);
      stack.lines.push_back(r.lines[i]);
    }
    for (int v : stack.nodes) seen[v] = -1;
    loops.push_back(std::move(stack));
  }
  std::vector<RingOut> out;
  for (const RingOut& r : loops) {
    RingOut s;
    const std::size_t n = r.nodes.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (sameDirection(r.out[(i + n - 1) % n], r.out[i])) continue;
      s.nodes.push_back(r.nodes[i]);
      s.out.push_back(r.out[i]);
      s.lines.push_back(r.lines[i]);
    }
    if (s.nodes.size() >= 3) out.push_back(std::move(s));
  }
  return out;
}

// The lowest vertex (then the leftmost) of a ring: a corner where it turns its true way.
std::size_t lowestLeftmost(const RingOut& r, const std::vector<Vertex>& nodes) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < r.nodes.size(); ++i) {
    const Vertex &v = nodes[r.nodes[i]], &b = nodes[r.nodes[best]];
    const int cy = compareFractions(v.y, v.d, b.y, b.d);
    if (cy < 0 || (cy == 0 && compareFractions(v.x, v.d, b.x, b.d) < 0)) best = i;
  }
  return best;
}

// Is the ring's vertex v (a node of the graph, not necessarily of `ring`) inside `ring`?
// `leaving` is the direction the vertex's own ring leaves it by, used when v lies on `ring`.
bool insideRing(const RingOut& ring, int v, Direction leaving, const std::vector<Vertex>& nodes) {
  const std::size_t n = ring.nodes.size();
  for (std::size_t i = 0; i < n; ++i)
    if (ring.nodes[i] == v) return pointsInto(ring.out[(i + n - 1) % n], ring.out[i], leaving);
  const Vertex& p = nodes[v];
  bool inside = false;
  for (std::size_t i = 0; i < n; ++i) {
    const Vertex &a = nodes[ring.nodes[i]], &b = nodes[ring.nodes[(i + 1) % n]];
    if (side(ring.lines[i], p) == 0) {
      // On the edge's line: on the edge itself (where a point the ring runs straight through
      // was dropped, or a ring of the same region touches it), decided by the angle it leaves at
      const Direction d = ring.out[i];
      const bool by_x = (d.x < 0 ? -d.x : d.x) >= (d.y < 0 ? -d.y : d.y);
      const int from =
          by_x ? compareFractions(p.x, p.d, a.x, a.d) : compareFractions(p.y, p.d, a.y, a.d);
      const int to =
          by_x ? compareFractions(p.x, p.d, b.x, b.d) : compareFractions(p.y, p.d, b.y, b.d);
      if (from * to <= 0) return pointsInto(d, d, leaving);
    }
    const bool a_above = compareFractions(a.y, a.d, p.y, p.d) > 0,
               b_above = compareFractions(b.y, b.d, p.y, p.d) > 0;
    if (a_above == b_above) continue;
    const int s = side(ring.lines[i], p);  // > 0: p left of the edge as walked
    if (b_above ? s > 0 : s < 0) inside = !inside;
  }
  return inside;
}

// 5. Sort the rings into outer boundaries (counter-clockwise) and holes (clockwise), and put
// each hole under the smallest outer ring around it.
ExactRegion assemble(const std::vector<RingOut>& rings, const std::vector<Vertex>& nodes) {
  std::vector<int> outers, holes;
  std::vector<double> size(rings.size(), 0.0);
  for (std::size_t i = 0; i < rings.size(); ++i) {
    const RingOut& r = rings[i];
    const std::size_t n = r.nodes.size(), k = lowestLeftmost(r, nodes);
    const Direction in = r.out[(k + n - 1) % n], out = r.out[k];
    (cross(in.x, in.y, out.x, out.y) > 0 ? outers : holes).push_back(static_cast<int>(i));
    double a = 0;
    for (std::size_t j = 0; j < n; ++j) {
      const Vertex &p = nodes[r.nodes[j]], &q = nodes[r.nodes[(j + 1) % n]];
      const double px = static_cast<double>(p.x) / static_cast<double>(p.d),
                   py = static_cast<double>(p.y) / static_cast<double>(p.d);
      const double qx = static_cast<double>(q.x) / static_cast<double>(q.d),
                   qy = static_cast<double>(q.y) / static_cast<double>(q.d);
      a += px * qy - qx * py;
    }
    size[i] = std::abs(a);
  }
  std::sort(outers.begin(), outers.end(),
            [&](int l, int r) { return size[l] != size[r] ? size[l] < size[r] : l < r; });
  ExactRegion region(outers.size());
  auto points = [&](const RingOut& r) {
    ExactRing ring;
    ring.reserve(r.nodes.size());
    for (std::size_t i = 0; i < r.nodes.size(); ++i) {
      const Vertex& v = nodes[r.nodes[i]];
      ring.push_back({v.x, v.y, v.d, r.lines[i].a, r.lines[i].b, r.lines[i].c});
    }
    return ring;
  };
  for (std::size_t i = 0; i < outers.size(); ++i) region[i].outer = points(rings[outers[i]]);
  for (int h : holes) {
    std::size_t owner = 0;
    if (outers.size() > 1) {
      const RingOut& r = rings[h];
      const std::size_t k = lowestLeftmost(r, nodes);
      owner = outers.size();
      for (std::size_t i = 0; i < outers.size() && owner == outers.size(); ++i)
        if (insideRing(rings[outers[i]], r.nodes[k], r.out[k], nodes)) owner = i;
      if (owner == outers.size()) continue;  // only on invalid input
    } else if (outers.empty()) {
      continue;  // only on invalid input
    }
    region[owner].holes.push_back(points(rings[h]));
  }
  return region;
}

}  // namespace

double detail::nearestQuotient(i128 n, std::int64_t d) {
  if (n == 0 || d <= 0) return d > 0 ? 0.0 : std::numeric_limits<double>::quiet_NaN();
  const bool negative = n < 0;
  const u128 num = negative ? -static_cast<u128>(n) : static_cast<u128>(n);
  const auto den = static_cast<std::uint64_t>(d);
  auto bitLength = [](u128 v) {
    const auto hi = static_cast<std::uint64_t>(v >> 64), lo = static_cast<std::uint64_t>(v);
    return hi ? 128 - std::countl_zero(hi) : 64 - std::countl_zero(lo);
  };
  // q = floor(num / den * 2^s), with s chosen so that q has 55 or 56 bits: 53 kept, the rest
  // and whether anything was left over decide the rounding
  const int s = 55 - (bitLength(num) - (64 - std::countl_zero(den)));
  u128 q;
  bool inexact;
  if (s >= 0) {  // num < 2^128 and den < 2^64: num * 2^s stays below 2^120
    const u128 scaled = num << s;
    q = scaled / den;
    inexact = scaled % den != 0;
  } else {  // floor(floor(num / 2^k) / den) = floor(num / (2^k den))
    const int k = -s;
    const u128 shifted = num >> k;
    q = shifted / den;
    inexact = shifted % den != 0 || (num & ((u128{1} << k) - 1)) != 0;
  }
  const int drop = bitLength(q) - 53;
  auto kept = static_cast<std::uint64_t>(q >> drop);
  const u128 rest = q & ((u128{1} << drop) - 1), half = u128{1} << (drop - 1);
  if (rest > half || (rest == half && (inexact || (kept & 1)))) ++kept;
  const double magnitude = std::ldexp(static_cast<double>(kept), drop - s);
  return negative ? -magnitude : magnitude;
}

const char* booleanOpName(BooleanOp op) {
  switch (op) {
    case BooleanOp::Intersection:
      return "A∩B";
    case BooleanOp::Union:
      return "A∪B";
    case BooleanOp::AMinusB:
      return "A−B";
    case BooleanOp::BMinusA:
      return "B−A";
  }
  return "?";
}

std::string invalidRegionReason(const GridRegion& region) {
  struct Seg {
    GridPoint p, q;
    int poly, ring, index, ring_size;
  };
  std::vector<Seg> segs;
  int ring_count = 0;
  auto where = [](int poly, int ring) {
    return "polygon " + std::to_string(poly) +
           (ring == 0 ? " outer ring" : " hole " + std::to_string(ring - 1));
  };
  for (std::size_t pi = 0; pi < region.size(); ++pi) {
    for (std::size_t ri = 0; ri <= region[pi].holes.size(); ++ri) {
      const GridRing& r = ri == 0 ? region[pi].outer : region[pi].holes[ri - 1];
      const std::string at = where(static_cast<int>(pi), static_cast<int>(ri));
      if (r.size() < 3) return at + ": fewer than 3 vertices";
      for (std::size_t i = 0; i < r.size(); ++i) {
        if (r[i].x < -kClipCoordinateLimit || r[i].x > kClipCoordinateLimit ||
            r[i].y < -kClipCoordinateLimit || r[i].y > kClipCoordinateLimit)
          return at + " vertex " + std::to_string(i) + ": coordinate beyond ±2^28";
        if (r[i] == r[(i + 1) % r.size()])
          return at + " vertex " + std::to_string(i) + ": repeated (an edge of length 0)";
      }
      if (twiceSignedArea(r) == 0) return at + ": area 0";
      const int ring = ring_count++;
      for (std::size_t i = 0; i < r.size(); ++i)
        segs.push_back({r[i], r[(i + 1) % r.size()], static_cast<int>(pi), ring,
                        static_cast<int>(i), static_cast<int>(r.size())});
    }
  }
  // No two edges cross or run along one another; they may touch at a point.
  for (std::size_t i = 0; i < segs.size(); ++i)
    for (std::size_t j = i + 1; j < segs.size(); ++j) {
      const Seg &s = segs[i], &t = segs[j];
      if (std::max(s.p.x, s.q.x) < std::min(t.p.x, t.q.x) ||
          std::max(t.p.x, t.q.x) < std::min(s.p.x, s.q.x) ||
          std::max(s.p.y, s.q.y) < std::min(t.p.y, t.q.y) ||
          std::max(t.p.y, t.q.y) < std::min(s.p.y, s.q.y))
        continue;
      const std::string what = "edge " + std::to_string(s.index) + " of " + "ring " +
                               std::to_string(s.ring) + " and edge " + std::to_string(t.index) +
                               " of ring " + std::to_string(t.ring);
      const int d1 = detail::orient2d(s.p.x, s.p.y, s.q.x, s.q.y, t.p.x, t.p.y);
      const int d2 = detail::orient2d(s.p.x, s.p.y, s.q.x, s.q.y, t.q.x, t.q.y);
      const int d3 = detail::orient2d(t.p.x, t.p.y, t.q.x, t.q.y, s.p.x, s.p.y);
      const int d4 = detail::orient2d(t.p.x, t.p.y, t.q.x, t.q.y, s.q.x, s.q.y);
      const bool adjacent = s.ring == t.ring && (t.index == (s.index + 1) % s.ring_size ||
                                                 s.index == (t.index + 1) % s.ring_size);
      if (d1 == 0 && d2 == 0) {  // collinear: they may share one point, no more
        const bool by_x = s.p.x != s.q.x;
        const std::int64_t s0 = by_x ? std::min(s.p.x, s.q.x) : std::min(s.p.y, s.q.y),
                           s1 = by_x ? std::max(s.p.x, s.q.x) : std::max(s.p.y, s.q.y);
        const std::int64_t t0 = by_x ? std::min(t.p.x, t.q.x) : std::min(t.p.y, t.q.y),
                           t1 = by_x ? std::max(t.p.x, t.q.x) : std::max(t.p.y, t.q.y);
        if (std::min(s1, t1) > std::max(s0, t0)) return what + ": run along one another";
        if (std::min(s1, t1) == std::max(s0, t0) && s.ring == t.ring && !adjacent)
          return what + ": touch (a ring must not touch itself)";
        continue;
      }
      if ((d1 > 0 && d2 > 0) || (d1 < 0 && d2 < 0) || (d3 > 0 && d4 > 0) || (d3 < 0 && d4 < 0))
        continue;
      if (d1 != 0 && d2 != 0 && d3 != 0 && d4 != 0) return what + ": cross";
      // They touch at a point: an end of one on the other. Rings of a region may touch one
      // another so; a ring may not touch itself, except where its edges follow one another.
      if (s.ring == t.ring && !adjacent) return what + ": touch (a ring must not touch itself)";
    }
  // Rings nest properly: each hole inside its outer ring, holes apart, polygons apart. Rings
  // that only touch may lie partly inside one another (a ring touching another at two points
  // can have one arc inside it and one outside), so no sample point decides it: the clipper
  // does, on inputs it already handles (each ring simple, each polygon checked before the
  // pairs of polygons): H − outer, H1 ∩ H2 and P ∩ Q must be empty (a result's rings are
  // simple, so a result that is not empty has area).
  auto alone = [](const GridRing& r) { return GridRegion{GridPolygon{r, {}}}; };
  auto overlap = [](const GridRegion& x, const GridRegion& y, BooleanOp op) {
    return !booleanOp(x, y, op).empty();
  };
  for (std::size_t pi = 0; pi < region.size(); ++pi) {
    const GridPolygon& p = region[pi];
    for (std::size_t h = 0; h < p.holes.size(); ++h) {
      const std::string at = where(static_cast<int>(pi), static_cast<int>(h) + 1);
      if (overlap(alone(p.holes[h]), alone(p.outer), BooleanOp::AMinusB))
        return at + " is not inside its outer ring";
      for (std::size_t k = 0; k < h; ++k)
        if (overlap(alone(p.holes[h]), alone(p.holes[k]), BooleanOp::Intersection))
          return at + " overlaps " + where(static_cast<int>(pi), static_cast<int>(k) + 1);
    }
  }
  for (std::size_t pi = 0; pi < region.size(); ++pi)
    for (std::size_t pj = 0; pj < pi; ++pj)
      if (overlap(GridRegion{region[pi]}, GridRegion{region[pj]}, BooleanOp::Intersection))
        return where(static_cast<int>(pi), 0) + " overlaps " + where(static_cast<int>(pj), 0);
  return {};
}

ExactRegion booleanOp(const ExactRegion& a, const ExactRegion& b, BooleanOp op) {
  thread_local Graph g;
  g.reset();
  g.build(a, b);
  label(g);
  return assemble(tidy(walk(g, keep(g, op)), g.nodes.size()), g.nodes);
}

ExactRegion booleanOp(const GridRegion& a, const GridRegion& b, BooleanOp op) {
  return booleanOp(exactRegion(a), exactRegion(b), op);
}

ExactRegion exactRegion(const GridRegion& region) {
  auto ring = [](const GridRing& r) {
    ExactRing out(r.size());
    for (std::size_t i = 0, n = r.size(); i < n; ++i) {
      const GridPoint p = r[i], q = r[(i + 1) % n];
      const Line l = lineThrough(p, q.x - p.x, q.y - p.y);
      out[i] = {p.x, p.y, 1, l.a, l.b, l.c};
    }
    return out;
  };
  ExactRegion exact;
  exact.reserve(region.size());
  for (const GridPolygon& p : region) {
    ExactPolygon& e = exact.emplace_back();
    e.outer = ring(p.outer);
    for (const GridRing& h : p.holes) e.holes.push_back(ring(h));
  }
  return exact;
}

std::string invalidRegionReason(const ExactRegion& region) {
  const std::int64_t ab = std::int64_t{1} << 29, cmax = std::int64_t{1} << 58,
                     dmax = std::int64_t{1} << 60;
  const i128 xmax = i128{1} << 89;
  for (std::size_t pi = 0; pi < region.size(); ++pi)
    for (std::size_t ri = 0; ri <= region[pi].holes.size(); ++ri) {
      const ExactRing& r = ri == 0 ? region[pi].outer : region[pi].holes[ri - 1];
      const std::string at = "polygon " + std::to_string(pi) +
                             (ri == 0 ? " outer ring" : " hole " + std::to_string(ri - 1));
      if (r.size() < 3) return at + ": fewer than 3 vertices";
      for (std::size_t i = 0, n = r.size(); i < n; ++i) {
        const ExactPoint& p = r[i];
        const std::string v = at + " vertex " + std::to_string(i);
        if (p.d <= 0 || p.d >= dmax || p.x <= -xmax || p.x >= xmax || p.y <= -xmax || p.y >= xmax)
          return v + ": out of range";
        if (p.a < -ab || p.a > ab || p.b < -ab || p.b > ab || p.c < -cmax || p.c > cmax ||
            (p.a == 0 && p.b == 0))
          return v + ": its edge's line is out of range";
        const Vertex here{p.x, p.y, p.d},
            next{r[(i + 1) % n].x, r[(i + 1) % n].y, r[(i + 1) % n].d};
        const Line l{p.a, p.b, p.c};
        if (side(l, here) != 0 || side(l, next) != 0) return v + ": not on its edge's line";
        if (compare(along(here, directionOf(l)), along(next, directionOf(l))) >= 0)
          return v + ": its edge runs against its line's direction, or has length 0";
      }
    }
  return {};
}

double area(const ExactRegion& region) {
  auto ring = [](const ExactRing& r) {
    double s = 0;
    for (std::size_t i = 0, n = r.size(); i < n; ++i)
      s += r[i].xd() * r[(i + 1) % n].yd() - r[(i + 1) % n].xd() * r[i].yd();
    return std::abs(s) / 2;
  };
  double s = 0;
  for (const ExactPolygon& p : region) {
    s += ring(p.outer);
    for (const ExactRing& h : p.holes) s -= ring(h);
  }
  return s;
}

}  // namespace hsr
