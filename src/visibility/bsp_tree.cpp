// Building a 3D BSP tree, as the notes give it:
//
//   1. Choose a polygon of the list; its plane is the node's splitting plane.
//   2. Classify every other polygon against that plane: in front, behind, on it (coplanar),
//      or spanning it.
//   3. Spanning polygons are split along the plane; each piece joins its side's list.
//   4. Coplanar polygons stay at the node; build the front subtree from the front list and
//      the back subtree from the back list, the same way, until the lists are empty.
//
// Classification and splitting are the shared ones (geometry/polygon.hpp: classifyAgainstPlane,
// splitVertices). Classification: the distance of each vertex from the plane, in double; a vertex
// within `epsilon` (1e-6 of the scene's bounding-box diagonal) is on the plane, so a polygon
// whose vertices are all within it is coplanar, and one with vertices only on one side (or on
// the plane) goes to that side. Splitting puts a vertex on the plane into both pieces and an
// edge's crossing point, computed once, into both: the pieces meet exactly. Each piece
// remembers the cut, so that a renderer hands each piece exactly its parent's pixels on its
// side (bsp.cpp).
//
// The recursion is a loop over a stack of lists: a tree as deep as its polygon count (a worst
// case the "first" choice reaches on sorted input) never overflows the call stack.
// Cost: O(n log n) classifications for a balanced tree, O(n^2) at worst, times `candidates`
// for the sampled choices (a convex cluster, where every polygon's plane has all the others on
// one side, is a chain: O(k^2) for its k polygons); memory: per polygon or piece 40 B, its
// vertices (24 B each) and its cuts (8 B per ancestor that cut it), per node 96 B.
// Tests: bsp_test.cpp (row 11, split consistency).
//
// Tests: tests/visibility/bsp_test.cpp.

#include "visibility/bsp_tree.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/random.hpp"
#include "core/stopwatch.hpp"
#include "geometry/polygon.hpp"
#include "geometry/triangulate.hpp"
#include "hsr/error.hpp"
#include "pipeline/pipeline.hpp"

namespace hsr::detail {

namespace {

constexpr int kFewestCandidates = 512;

// The plane of a polygon (Newell's normal, unit length, through the centroid), or false when
// it has no area or is not finite.
bool planeOf(const std::vector<glm::dvec3>& v, glm::dvec4* plane) {
  const glm::dvec3 normal = newellNormal(v.size(), [&](std::size_t i) { return v[i]; });
  const double len = glm::length(normal);
  if (!(len > 0.0) || !std::isfinite(len)) return false;
  glm::dvec3 c(0.0);
  for (const glm::dvec3& p : v) c += p;
  c /= static_cast<double>(v.size());
  const glm::dvec3 n = normal / len;
  *plane = glm::dvec4(n, -glm::dot(n, c));
  return std::isfinite(plane->w);
}

// A node's plane as geometry/polygon.hpp's Plane, for its classification (step 2) and
// splitting (step 3): a vertex within epsilon of the plane is on it.
Plane asPlane(const glm::dvec4& plane) { return Plane{glm::dvec3(plane), plane.w}; }

struct Task {
  std::vector<std::uint32_t> list;
  std::int32_t parent = -1;  // the node whose child this list becomes
  bool front = false;
  std::uint32_t depth = 1;
};

}  // namespace

bool parseSplitterChoice(std::string_view s, SplitterChoice* out) {
  for (const SplitterChoice c :
       {SplitterChoice::kFirst, SplitterChoice::kRandom, SplitterChoice::kFewest,
        SplitterChoice::kBalanced, SplitterChoice::kBestOfK})
    if (toString(c) == s) return *out = c, true;
  return false;
}

std::string_view toString(SplitterChoice c) {
  switch (c) {
    case SplitterChoice::kFirst:
      return "first";
    case SplitterChoice::kRandom:
      return "random";
    case SplitterChoice::kFewest:
      return "fewest";
    case SplitterChoice::kBalanced:
      return "balanced";
    case SplitterChoice::kBestOfK:
      return "best-of-k";
  }
  return "?";
}

int eyeSide(const BspNode& node, const glm::dvec3& eye) {
  const double d = asPlane(node.plane).value(eye);
  return d > 0 ? 1 : d < 0 ? -1 : 0;
}

BspTree buildBspTree(const Scene& scene, const BspOptions& options,
                     const std::function<void(std::uint64_t, std::uint64_t)>& progress,
                     const std::function<void(const BspNodeReport&)>& report) {
  const detail::Stopwatch t0;
  SplitterChoice choice;
  if (!parseSplitterChoice(options.splitter, &choice))
    throw Error("unknown BSP splitter choice '" + options.splitter +
                "' (first, random, fewest, balanced, best-of-k)");
  if (options.candidates < 1 || options.candidates > 4096)
    throw Error("BSP splitter candidates must be 1..4096 (got " +
                std::to_string(options.candidates) + ")");
  BspTree tree;
  // The epsilon: 1e-6 of the scene's size. The vertices are floats, good to about 6e-8 of
  // their magnitude: polygons meant to be coplanar (a duplicate, two triangles of one quad)
  // stray from each other's planes by that much, and must be found on them, not split along
  // a plane they lie in (a cut that thin is no line of the picture).
  glm::dvec3 lo(std::numeric_limits<double>::infinity()),
      hi(-std::numeric_limits<double>::infinity());
  for (const glm::vec3& p : scene.positions())
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) {
      lo = glm::min(lo, glm::dvec3(p));
      hi = glm::max(hi, glm::dvec3(p));
    }
  const double diagonal = lo.x <= hi.x ? glm::length(hi - lo) : 1.0;
  tree.epsilon = 1e-6 * std::max(diagonal, 1e-30);

  // The polygons: each scene polygon with a plane, or the fan of a non-planar one.
  std::vector<glm::dvec4> planes;
  std::vector<Triangle> triangles;
  Task root;
  for (PolygonId id = 0; id < scene.polygonCount(); ++id) {
    std::vector<glm::dvec3> v;
    bool finite = true;
    for (const std::uint32_t i : scene.polygon(id)) {
      const glm::vec3& p = scene.position(i);
      finite = finite && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
      v.emplace_back(p);
    }
    glm::dvec4 plane;
    if (!finite || v.size() < 3 || !planeOf(v, &plane)) continue;
    ++tree.stats.input_polygons;
    auto add = [&](std::vector<glm::dvec3> w, const glm::dvec4& pl, std::uint32_t piece) {
      root.list.push_back(static_cast<std::uint32_t>(tree.polygons.size()));
      tree.polygons.push_back({std::move(w), id, piece, 0, 0});
      planes.push_back(pl);
    };
    const std::span<const std::uint32_t> vi = scene.polygon(id);
    if (vi.size() == 3 || isPlanar(scene, vi, canonicalPlane(vi.size(), [&](std::size_t i) {
                                     return glm::dvec3(scene.position(vi[i]));
                                   }))) {
      add(std::move(v), plane, 0);
      continue;
    }
    triangles.clear();
    triangulatePolygon(scene, id, triangles);
    for (std::uint32_t k = 0; k < triangles.size(); ++k) {
      std::vector<glm::dvec3> t;
      for (const std::uint32_t i : triangles[k].v) t.emplace_back(scene.position(i));
      glm::dvec4 tp;
      if (planeOf(t, &tp)) add(std::move(t), tp, k);
    }
  }

  SplitMix64 rng(options.seed);  // seeded and portable: the same tree everywhere
  std::vector<Task> stack;
  if (!root.list.empty()) stack.push_back(std::move(root));
  std::vector<std::uint32_t> order;  // the polygons kept at nodes, node by node
  std::vector<glm::dvec3> front_part, back_part;
  while (!stack.empty()) {
    Task task = std::move(stack.back());
    stack.pop_back();
    const std::vector<std::uint32_t>& list = task.list;
    const double eps = tree.epsilon;

    // 1. The splitter.
    struct Score {
      std::uint64_t splits = 0, front = 0, back = 0;
    };
    auto score = [&](const glm::dvec4& plane) {
      Score sc;
      for (const std::uint32_t q : list) {
        switch (classifyAgainstPlane(tree.polygons[q].vertices, asPlane(plane), eps)) {
          case PlaneSide::kSpanning:
            ++sc.splits;
            break;
          case PlaneSide::kFront:
            ++sc.front;
            break;
          case PlaneSide::kBehind:
            ++sc.back;
            break;
          case PlaneSide::kOn:
            break;
        }
      }
      return sc;
    };
    auto cost = [&](const Score& sc) {
      const double imbalance =
          static_cast<double>(sc.front > sc.back ? sc.front - sc.back : sc.back - sc.front);
      return choice == SplitterChoice::kBalanced ? 8.0 * static_cast<double>(sc.splits) + imbalance
                                                 : static_cast<double>(sc.splits);
    };
    std::uint32_t splitter = list[0];
    if (list.size() > 1) {
      switch (choice) {
        case SplitterChoice::kFirst:
          break;
        case SplitterChoice::kRandom:
          splitter = list[rng.next() % list.size()];
          break;
        case SplitterChoice::kFewest:
        case SplitterChoice::kBalanced:
        case SplitterChoice::kBestOfK: {
          const bool all = choice == SplitterChoice::kFewest && list.size() <= kFewestCandidates;
          const std::size_t k = choice == SplitterChoice::kFewest
                                    ? std::min<std::size_t>(list.size(), kFewestCandidates)
                                    : static_cast<std::size_t>(std::max(options.candidates, 1));
          double best = std::numeric_limits<double>::infinity();
          for (std::size_t i = 0; i < k; ++i) {
            const std::uint32_t c = all ? list[i] : list[rng.next() % list.size()];
            const Score sc = score(planes[c]);
            if (cost(sc) < best) best = cost(sc), splitter = c;
          }
          break;
        }
      }
    }
    const glm::dvec4 plane = planes[splitter];
    // The node.
    const auto node_index = static_cast<std::uint32_t>(tree.nodes.size());
    tree.nodes.push_back({});
    tree.nodes.back().plane = plane;
    if (task.parent >= 0)
      (task.front ? tree.nodes[task.parent].front : tree.nodes[task.parent].back) =
          static_cast<std::int32_t>(node_index);

    // 2 and 3. Classify, split the spanning ones.
    Task front{{}, static_cast<std::int32_t>(node_index), true, task.depth + 1};
    Task back{{}, static_cast<std::int32_t>(node_index), false, task.depth + 1};
    std::vector<std::uint32_t> on;
    std::vector<std::vector<glm::dvec3>> split_ones;  // only when reporting
    for (const std::uint32_t q : list) {
      const PlaneSide side =
          q == splitter ? PlaneSide::kOn
                        : classifyAgainstPlane(tree.polygons[q].vertices, asPlane(plane), eps);
      if (side == PlaneSide::kOn) {
        on.push_back(q);
      } else if (side == PlaneSide::kFront) {
        front.list.push_back(q);
      } else if (side == PlaneSide::kBehind) {
        back.list.push_back(q);
      } else {
        splitVertices(tree.polygons[q].vertices, asPlane(plane), eps, &front_part, &back_part);
        ++tree.stats.splits;
        if (report) split_ones.push_back(tree.polygons[q].vertices);
        const PolygonId id = tree.polygons[q].id;
        const std::uint32_t sub = tree.polygons[q].piece;
        const std::uint32_t first_cut = tree.polygons[q].first_cut,
                            cut_count = tree.polygons[q].cut_count;
        for (const bool is_front : {true, false}) {
          std::vector<glm::dvec3>& part = is_front ? front_part : back_part;
          if (part.size() < 3) continue;
          BspPolygon piece{part, id, sub, static_cast<std::uint32_t>(tree.cuts.size()),
                           cut_count + 1};
          for (std::uint32_t c = 0; c < cut_count; ++c)
            tree.cuts.push_back(tree.cuts[first_cut + c]);
          tree.cuts.push_back({node_index, is_front});
          (is_front ? front.list : back.list)
              .push_back(static_cast<std::uint32_t>(tree.polygons.size()));
          tree.polygons.push_back(std::move(piece));
          planes.push_back(planes[q]);
        }
      }
    }
    if (report)
      report({node_index, tree.polygons[splitter].id, tree.polygons[splitter].vertices, list.size(),
              front.list.size(), back.list.size(), split_ones, on.size(), task.depth});
    // 4. Coplanar polygons stay; recurse on both sides (back pushed first: front is built
    // first, any order gives the same tree for a given seed).
    BspNode& node = tree.nodes[node_index];
    node.first_polygon = static_cast<std::uint32_t>(order.size());
    node.polygon_count = static_cast<std::uint32_t>(on.size());
    order.insert(order.end(), on.begin(), on.end());
    if (!back.list.empty()) stack.push_back(std::move(back));
    if (!front.list.empty()) stack.push_back(std::move(front));
    if (progress && (tree.nodes.size() & 4095) == 0)
      progress(order.size(), tree.stats.input_polygons + tree.stats.splits);
  }

  // Keep the polygons the nodes hold (not the split ones), node by node.
  std::vector<BspPolygon> kept;
  std::vector<BspCut> kept_cuts;
  kept.reserve(order.size());
  for (const std::uint32_t i : order) {
    BspPolygon& p = kept.emplace_back(std::move(tree.polygons[i]));
    const auto first = static_cast<std::uint32_t>(kept_cuts.size());
    kept_cuts.insert(kept_cuts.end(), tree.cuts.begin() + p.first_cut,
                     tree.cuts.begin() + p.first_cut + p.cut_count);
    p.first_cut = first;
  }
  tree.polygons = std::move(kept);
  tree.cuts = std::move(kept_cuts);
  finishBspTree(tree);
  tree.stats.build_ms = t0.ms();
  if (progress) progress(order.size(), order.size());
  return tree;
}

void finishBspTree(BspTree& tree) {
  // Children have larger indices than their parents: bounds and polygon counts come up from
  // the last node, depths go down from the first.
  std::vector<std::uint64_t> below(tree.nodes.size(), 0), depth(tree.nodes.size(), 1);
  BspStats& s = tree.stats;
  s.depth = 0;
  double depth_sum = 0, balance_sum = 0;
  std::uint64_t inner = 0;
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    const BspNode& n = tree.nodes[i];
    for (const std::int32_t c : {n.front, n.back})
      if (c >= 0) depth[c] = depth[i] + 1;
    s.depth = std::max(s.depth, depth[i]);
    depth_sum += static_cast<double>(depth[i]) * n.polygon_count;
  }
  for (std::size_t i = tree.nodes.size(); i-- > 0;) {
    BspNode& n = tree.nodes[i];
    n.lo = glm::dvec3(std::numeric_limits<double>::infinity());
    n.hi = glm::dvec3(-std::numeric_limits<double>::infinity());
    for (std::uint32_t k = 0; k < n.polygon_count; ++k)
      for (const glm::dvec3& p : tree.polygons[n.first_polygon + k].vertices) {
        n.lo = glm::min(n.lo, p);
        n.hi = glm::max(n.hi, p);
      }
    below[i] = n.polygon_count;
    for (const std::int32_t c : {n.front, n.back})
      if (c >= 0) {
        n.lo = glm::min(n.lo, tree.nodes[c].lo);
        n.hi = glm::max(n.hi, tree.nodes[c].hi);
        below[i] += below[c];
      }
    if (n.front >= 0 || n.back >= 0) {
      const double a = n.front >= 0 ? static_cast<double>(below[n.front]) : 0.0;
      const double b = n.back >= 0 ? static_cast<double>(below[n.back]) : 0.0;
      balance_sum += std::min(a, b) / std::max(a, b);
      ++inner;
    }
  }
  s.polygons = tree.polygons.size();
  s.nodes = tree.nodes.size();
  s.mean_depth = s.polygons ? depth_sum / static_cast<double>(s.polygons) : 0.0;
  s.balance = inner ? balance_sum / static_cast<double>(inner) : 1.0;
  // What the tree needs: its nodes, its polygons with their vertices, their cuts.
  s.bytes = tree.nodes.size() * sizeof(BspNode) + tree.polygons.size() * sizeof(BspPolygon) +
            tree.cuts.size() * sizeof(BspCut);
  for (const BspPolygon& p : tree.polygons) s.bytes += p.vertices.size() * sizeof(glm::dvec3);
}

}  // namespace hsr::detail

namespace hsr {

const BspStats& Bsp::stats() const { return tree_->stats; }
double Bsp::epsilon() const { return tree_->epsilon; }

Bsp buildBsp(Scene scene, const BspOptions& options,
             const std::function<void(std::uint64_t, std::uint64_t)>& progress) {
  Bsp bsp;
  bsp.scene_ = std::make_shared<const Scene>(std::move(scene));
  bsp.tree_ =
      std::make_shared<const detail::BspTree>(detail::buildBspTree(*bsp.scene_, options, progress));
  bsp.options_ = options;
  return bsp;
}

}  // namespace hsr
