// The bounding volume hierarchy and its ray queries (geometry/bvh.hpp, hsr::RayScene).
// docs/testing.md row 9 (watertight: no ray from inside a closed mesh escapes) and row 13
// (NaN and infinite rays answer "no hit" and harm no other), the hierarchy's own invariants,
// and the SSE node test pinned to the scalar one bit for bit.

#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "core/bit_cast.hpp"
#include "core/random.hpp"
#include "cross/figures.hpp"
#include "geometry/bvh.hpp"
#include "geometry/ray_scene_data.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/ray_scene.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using testing::grouped;

float uniform(detail::SplitMix64& rng) {
  return static_cast<float>(rng.next() >> 40) / static_cast<float>(1u << 24);
}

// A closed UV sphere of radius r at `centre` (poles as triangle fans): every edge shared by
// exactly two triangles, which share its two vertices exactly.
Scene closedSphere(glm::vec3 centre, float r, int rings, int segments) {
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  s.beginObject("sphere");
  std::vector<std::uint32_t> v;
  const std::uint32_t north = s.addVertex(centre + glm::vec3(0, 0, r));
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double th = std::numbers::pi * i / rings, ph = 2 * std::numbers::pi * j / segments;
      v.push_back(s.addVertex(centre + glm::vec3(float(r * std::sin(th) * std::cos(ph)),
                                                 float(r * std::sin(th) * std::sin(ph)),
                                                 float(r * std::cos(th)))));
    }
  const std::uint32_t south = s.addVertex(centre + glm::vec3(0, 0, -r));
  auto at = [&](int i, int j) {
    return v[static_cast<std::size_t>(i) * segments + (j % segments)];
  };
  for (int j = 0; j < segments; ++j) s.addPolygon({north, at(0, j), at(0, j + 1)}, m);
  for (int i = 0; i + 1 < rings - 1; ++i)
    for (int j = 0; j < segments; ++j) {
      s.addPolygon({at(i, j), at(i + 1, j), at(i + 1, j + 1)}, m);
      s.addPolygon({at(i, j), at(i + 1, j + 1), at(i, j + 1)}, m);
    }
  for (int j = 0; j < segments; ++j)
    s.addPolygon({south, at(rings - 2, j + 1), at(rings - 2, j)}, m);
  return s;
}

// Row 9: a closed sphere of 200x200 segments, far from the origin (where floats are coarse)
// and at it: 10^6 random rays from inside, 10^5 aimed exactly at its vertices and 10^5 at its
// edges' midpoints, where cracks would show: none may escape. Then 10^5 rays at the centroids
// of a 100x100 grid of tiny triangles: each hits its own.
TEST(Bvh, WatertightNoRayEscapesAClosedSphere) {
  const std::size_t scale = static_cast<std::size_t>(testing::countScale());
  for (const auto& [centre, radius] :
       {std::pair{glm::vec3(148376.0f, 1234.0f, -223423.0f), 1000.0f},
        std::pair{glm::vec3(0.0f), 1.0f}}) {
    SCOPED_TRACE("centre x " + std::to_string(centre.x));
    const Scene sphere = closedSphere(centre, radius, 200, 200);
    const RayScene rays(sphere);
    detail::SplitMix64 rng(9);
    std::vector<glm::vec3> vertices, midpoints;
    for (std::size_t v = 0; v < sphere.vertexCount(); ++v)
      vertices.push_back(sphere.position(static_cast<std::uint32_t>(v)));
    for (PolygonId p = 0; p < sphere.polygonCount(); ++p) {
      const auto vi = sphere.polygon(p);
      for (int k = 0; k < 3; ++k)
        midpoints.push_back((sphere.position(vi[k]) + sphere.position(vi[(k + 1) % 3])) * 0.5f);
    }
    // (Copies of the bindings: Clang 14, the web build's, cannot capture a structured binding)
    auto inside = [&, c = centre, r = radius] {
      return c +
             0.5f * r * glm::vec3(uniform(rng) - 0.5f, uniform(rng) - 0.5f, uniform(rng) - 0.5f);
    };
    std::vector<glm::vec3> org, dir;
    for (std::size_t i = 0; i < 1000000 * scale; ++i)
      org.push_back(inside()),
          dir.push_back(glm::vec3(uniform(rng) - 0.5f, uniform(rng) - 0.5f, uniform(rng) - 0.5f));
    for (std::size_t i = 0; i < 100000 * scale; ++i) {
      org.push_back(inside()), dir.push_back(vertices[rng.next() % vertices.size()] - org.back());
      org.push_back(inside()), dir.push_back(midpoints[rng.next() % midpoints.size()] - org.back());
    }
    const std::vector<RayHit> hits = rays.intersect(org, dir);
    std::uint64_t misses = 0;
    for (const RayHit& h : hits) misses += !h.hit();
    testing::printFigures("row 9 watertight: a closed 200x200 sphere of radius " +
                          std::to_string(radius) + " at (" + std::to_string(centre.x) + ", " +
                          std::to_string(centre.y) + ", " + std::to_string(centre.z) + "): " +
                          grouped(org.size()) + " rays from inside (" + grouped(200000 * scale) +
                          " at vertices and edge midpoints), " + grouped(misses) + " escaped");
    EXPECT_EQ(misses, 0u);
  }
  // Tiny triangles: each centroid ray hits its own triangle
  Scene grid;
  const std::uint32_t m = grid.addMaterial({});
  grid.beginObject("grid");
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j) {
      const glm::vec3 o(i * 1e-3f, j * 1e-3f, 0.0f);
      grid.addPolygonVertices({o, o + glm::vec3(1e-3f, 0, 0), o + glm::vec3(0, 1e-3f, 0)}, m);
    }
  const RayScene grid_rays(grid);
  std::uint64_t own = 0;
  for (PolygonId p = 0; p < grid.polygonCount(); ++p) {
    const auto vi = grid.polygon(p);
    const glm::vec3 c = (grid.position(vi[0]) + grid.position(vi[1]) + grid.position(vi[2])) / 3.0f;
    for (int k = 0; k < 10; ++k)
      own += grid_rays.intersect(c + glm::vec3(0, 0, 1), glm::vec3(0.01f * (k - 5) * 1e-3f, 0, -1))
                 .polygon == p;
  }
  EXPECT_EQ(own, 10 * grid.polygonCount());
}

// Row 13: a ray with a NaN or infinite component, or a zero direction, hits nothing; the
// valid rays beside it in the same batch get the answer they get alone; and such rays cost no
// more than finite ones (the catalogue's bound: at most 2.5x).
TEST(Bvh, NaNAndInfiniteRaysHitNothingAndHarmNoOther) {
  const Scene scene = makeBuiltinScene("spheres:2000");
  const RayScene rays(scene);
  const Bounds b = scene.bounds();
  detail::SplitMix64 rng(13);
  const float nan = std::numeric_limits<float>::quiet_NaN(),
              inf = std::numeric_limits<float>::infinity();
  const std::size_t n = 200000;
  std::vector<glm::vec3> org(n), dir(n), bad_org(n), bad_dir(n);
  std::vector<std::uint8_t> bad(n);
  for (std::size_t i = 0; i < n; ++i) {
    org[i] = b.lo + (b.hi - b.lo) * glm::vec3(uniform(rng), uniform(rng), uniform(rng));
    dir[i] = glm::vec3(uniform(rng) - 0.5f, uniform(rng) - 0.5f, uniform(rng) - 0.5f);
    bad_org[i] = org[i], bad_dir[i] = dir[i];
    bad[i] = i % 2 == 1;
    if (!bad[i]) continue;
    switch (i / 2 % 5) {
      case 0:
        bad_org[i][static_cast<int>(i / 10 % 3)] = nan;
        break;
      case 1:
        bad_dir[i][static_cast<int>(i / 10 % 3)] = nan;
        break;
      case 2:
        bad_org[i][static_cast<int>(i / 10 % 3)] = -inf;
        break;
      case 3:
        bad_dir[i][static_cast<int>(i / 10 % 3)] = inf;
        break;
      default:
        bad_dir[i] = glm::vec3(0.0f);
        break;
    }
  }
  const std::vector<RayHit> good = rays.intersect(org, dir);
  const std::vector<RayHit> mixed = rays.intersect(bad_org, bad_dir);
  std::uint64_t hit_by_bad = 0, changed = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (bad[i]) {
      hit_by_bad += mixed[i].hit() || rays.occluded(bad_org[i], bad_dir[i]);
    } else {
      changed += mixed[i].polygon != good[i].polygon || mixed[i].t != good[i].t;
    }
  }
  EXPECT_EQ(hit_by_bad, 0u);
  EXPECT_EQ(changed, 0u);
  // Time per ray, all bad against all finite (single-threaded, best of 3)
  auto time = [&](const std::vector<glm::vec3>& o, const std::vector<glm::vec3>& d) {
    double best = 1e30;
    for (int rep = 0; rep < 3; ++rep) {
      const auto t0 = std::chrono::steady_clock::now();
      std::uint64_t sink = 0;
      for (std::size_t i = 1; i < n; i += 2) sink += rays.intersect(o[i], d[i]).polygon;
      best = std::min(best,
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      EXPECT_NE(sink, 1u);
    }
    return best;
  };
  const double bad_s = time(bad_org, bad_dir), good_s = time(org, dir);
  testing::printFigures("row 13 rays: " + grouped(n / 2) + " NaN/Inf/zero rays hit nothing, " +
                        grouped(n / 2) + " finite rays beside them unchanged; bad rays take " +
                        std::to_string(bad_s / good_s) + "x the time of finite ones");
  EXPECT_LE(bad_s, 2.5 * good_s);
}

// Centroids a few subnormal steps apart make the bins' scale infinite, and 0 x infinity a
// NaN: each bin is clamped as a float before it becomes an int (UBSan's float-cast-overflow
// watches this in CI), and the triangles are all found.
TEST(Bvh, SubnormalExtentsBinWithoutOverflow) {
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  s.beginObject("tiny");
  for (int k = 0; k < 40; ++k) {
    const float x = static_cast<float>(k % 8) * std::numeric_limits<float>::denorm_min();
    s.addPolygonVertices(
        {glm::vec3(x, -1, -1), glm::vec3(x, 1, -1), glm::vec3(x, 0, 1 + 0.01f * k)}, m);
  }
  const RayScene rays(s);
  EXPECT_EQ(rays.stats().triangles, 40u);
  const RayHit h = rays.intersect(glm::vec3(5, 0, 0), glm::vec3(-1, 0, 0));
  ASSERT_TRUE(h.hit());
  EXPECT_LT(h.polygon, 40u);
}

// Every finite triangle sits in exactly one leaf, inside every box on its way from the root.
TEST(Bvh, EveryTriangleInOneLeafInsideItsBoxes) {
  const Scene scene = makeBuiltinScene("spheres:3000");
  const RayScene rays(scene);
  const detail::Bvh& bvh = rays.data().bvh;
  std::vector<int> seen(rays.triangleCount(), 0);
  struct Item {
    std::uint32_t ref;
    glm::vec3 lo, hi;
  };
  std::vector<Item> stack{{bvh.root, bvh.lo, bvh.hi}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    if (it.ref & detail::BvhNode::kLeaf) {
      const detail::BvhTriangles4& leaf = bvh.leaves[it.ref & ~detail::BvhNode::kLeaf];
      for (int lane = 0; lane < 4 && leaf.triangle[lane] != detail::kBvhNoTriangle; ++lane) {
        seen[leaf.triangle[lane]]++;
        for (int a = 0; a < 3; ++a)
          for (const float c : {leaf.a[a][lane], leaf.b[a][lane], leaf.c[a][lane]}) {
            EXPECT_GE(c, it.lo[a]);
            EXPECT_LE(c, it.hi[a]);
          }
      }
      continue;
    }
    const detail::BvhNode& node = bvh.nodes[it.ref];
    for (int i = 0; i < detail::kBvhWidth; ++i) {
      if (node.child[i] == detail::BvhNode::kEmpty) continue;
      glm::vec3 lo, hi;
      for (int a = 0; a < 3; ++a) {
        lo[a] = node.lo[a][i], hi[a] = node.hi[a][i];
        EXPECT_GE(lo[a], it.lo[a]);
        EXPECT_LE(hi[a], it.hi[a]);
      }
      stack.push_back({node.child[i], lo, hi});
    }
  }
  for (std::size_t t = 0; t < seen.size(); ++t) ASSERT_EQ(seen[t], 1) << "triangle " << t;
  EXPECT_GT(bvh.stats.sah_cost, 0.0);
}

// The optimal collapse (Ylitie, Karras & Laine 2017): on random binary trees of up to 15
// leaves with whole-number areas (sums exact in float), the plan's cost for the root equals the
// least over every way of keeping some inner nodes as eight-wide ones (the root always kept,
// each kept node's children, once the others are dissolved into it, at most eight): the
// summed area of the kept nodes, found by trying them all.
TEST(Bvh, CollapsePlanIsTheLeastOverEveryCollapse) {
  struct Node {
    int left = -1, right = -1;  // -1: a leaf
    float area = 0;
  };
  detail::SplitMix64 rng(7);
  int trees_with_choice = 0;
  for (int trial = 0; trial < 400; ++trial) {
    // A random shape: split a random leaf until there are `leaves`
    const int leaves = 2 + static_cast<int>(rng.next() % 14);
    std::vector<Node> tree(1);
    std::vector<int> open{0};
    while (static_cast<int>(open.size()) < leaves) {
      const std::size_t pick = rng.next() % open.size();
      const int n = open[pick];
      tree[n].left = static_cast<int>(tree.size());
      tree[n].right = static_cast<int>(tree.size()) + 1;
      tree.resize(tree.size() + 2);
      open[pick] = tree[n].left;
      open.push_back(tree[n].right);
    }
    for (Node& n : tree) n.area = static_cast<float>(1 + rng.next() % 50);
    // The plans, children first (children always follow their parent here)
    std::vector<detail::CollapsePlan> plan(tree.size());
    for (int n = static_cast<int>(tree.size()) - 1; n >= 0; --n) {
      if (tree[n].left < 0)
        detail::planCollapse(nullptr, nullptr, 0.0f, &plan[n]);
      else
        detail::planCollapse(&plan[tree[n].left], &plan[tree[n].right], tree[n].area, &plan[n]);
    }
    // Every choice of kept inner nodes below the root
    std::vector<int> inner;
    for (int n = 1; n < static_cast<int>(tree.size()); ++n)
      if (tree[n].left >= 0) inner.push_back(n);
    if (tree[0].left < 0) continue;
    if (!inner.empty()) trees_with_choice++;
    float best = INFINITY;
    for (std::uint32_t keep = 0; keep < (1u << inner.size()); ++keep) {
      std::vector<bool> kept(tree.size(), false);
      kept[0] = true;
      for (std::size_t i = 0; i < inner.size(); ++i) kept[inner[i]] = (keep >> i) & 1u;
      // A kept node's children: its descendants reached through dissolved inner nodes
      bool fits = true;
      float cost = 0;
      for (int n = 0; n < static_cast<int>(tree.size()); ++n) {
        if (!kept[n] || tree[n].left < 0) continue;
        cost += tree[n].area;
        int children = 0;
        std::vector<int> walk{tree[n].left, tree[n].right};
        while (!walk.empty()) {
          const int c = walk.back();
          walk.pop_back();
          if (tree[c].left < 0 || kept[c])
            children++;
          else
            walk.push_back(tree[c].left), walk.push_back(tree[c].right);
        }
        fits = fits && children <= detail::kBvhWidth;
      }
      if (fits) best = std::min(best, cost);
    }
    ASSERT_EQ(plan[0].cost[0], best) << "trial " << trial << ", " << leaves << " leaves";
  }
  EXPECT_GT(trees_with_choice, 300);
}

// The node test is conservative: every box the ray meets within [tmin, tmax], by a slab test in
// double, is reported hit (the scalar test, in every build); and the SSE sibling gives the
// scalar test's bits, the mask and the entry distances (in the SIMD build, where they differ).
// Random boxes and rays, axis-parallel rays, flat boxes and rays starting on a face among them.
TEST(Bvh, NodeTestIsConservativeAndSseEqualsScalar) {
  detail::SplitMix64 rng(4);
  std::uint64_t cases = 0, hits = 0, exact_hits = 0;
  for (int i = 0; i < 200000; ++i) {
    detail::BvhNode node{};
    constexpr int W = detail::kBvhWidth;
    const int used = i % 3 == 0 ? 2 + i % 4 : W;  // some nodes with empty children
    for (int c = 0; c < W; ++c)
      for (int a = 0; a < 3; ++a) {
        const float x = uniform(rng) * 4 - 2, y = uniform(rng) * 4 - 2;
        node.lo[a][c] = std::min(x, y),
        node.hi[a][c] = i % 7 == 0 ? std::min(x, y) : std::max(x, y);
        if (c >= used)
          node.lo[a][c] = INFINITY, node.hi[a][c] = -INFINITY,
          node.child[c] = detail::BvhNode::kEmpty;
      }
    glm::vec3 o(uniform(rng) * 6 - 3, uniform(rng) * 6 - 3, uniform(rng) * 6 - 3);
    glm::vec3 d(uniform(rng) - 0.5f, uniform(rng) - 0.5f, uniform(rng) - 0.5f);
    if (i % 5 == 0) d[i % 3] = 0.0f;                       // parallel to a slab
    if (i % 11 == 0) o[i % 3] = node.lo[i % 3][i % used];  // starting on a face
    const detail::BoxRay r = detail::boxRayOf(o, d);
    float a[W], b[W];
    const unsigned ma = detail::boxHitsScalar(node, r, 0.0f, 10.0f, a);
    // The reference: the slab test in double, closed boxes
    for (int c = 0; c < used; ++c) {
      double t0 = 0.0, t1 = 10.0;
      for (int ax = 0; ax < 3; ++ax) {
        const double lo = node.lo[ax][c], hi = node.hi[ax][c], oa = o[ax], da = d[ax];
        if (da == 0.0) {
          if (oa < lo || oa > hi) t0 = 1, t1 = 0;
          continue;
        }
        const double u = (lo - oa) / da, v = (hi - oa) / da;
        t0 = std::max(t0, std::min(u, v));
        t1 = std::min(t1, std::max(u, v));
      }
      if (t0 <= t1) {
        ++exact_hits;
        ASSERT_TRUE(ma & (1u << c))
            << "case " << i << " box " << c << ": met in [" << t0 << ", " << t1 << "]";
      }
    }
    if (detail::boxHitsSseAvailable()) {
      const unsigned mb = detail::boxHitsSse(node, r, 0.0f, 10.0f, b);
      ASSERT_EQ(ma, mb) << "case " << i;
      for (int c = 0; c < W; ++c)
        if (ma & (1u << c)) {
          ASSERT_EQ(detail::bitCast<std::uint32_t>(a[c]), detail::bitCast<std::uint32_t>(b[c]));
        }
    }
    ++cases;
    hits += static_cast<unsigned>(std::popcount(ma));
  }
  EXPECT_GT(exact_hits, cases / 20);  // the boxes are met often enough for this to mean something
  EXPECT_LE(hits - exact_hits, cases * detail::kBvhWidth / 4000) << "conservative, but only just";
}

// The group test rules a box out only where every ray of the group rules it out: random boxes
// (some flat, some children empty) against groups of rays from one point (a camera) and from
// points spread out (an orthographic camera, or any batch), at random t ranges. It must also
// rule boxes out, or it saves nothing.
TEST(Bvh, GroupTestRulesOutOnlyWhatEveryRayRulesOut) {
  detail::SplitMix64 rng(21);
  constexpr int W = detail::kBvhWidth;
  std::uint64_t groups = 0, ruled_out = 0, ray_hits = 0;
  for (int i = 0; i < 40000; ++i) {
    detail::BvhNode node{};
    const int used = i % 3 == 0 ? 2 + i % 4 : W;
    for (int c = 0; c < W; ++c)
      for (int a = 0; a < 3; ++a) {
        const float x = uniform(rng) * 4 - 2, y = uniform(rng) * 4 - 2;
        node.lo[a][c] = std::min(x, y),
        node.hi[a][c] = i % 7 == 0 ? std::min(x, y) : std::max(x, y);
        if (c >= used)
          node.lo[a][c] = INFINITY, node.hi[a][c] = -INFINITY,
          node.child[c] = detail::BvhNode::kEmpty;
      }
    // A group: directions in a small cone (one octant), origins one point or a patch
    const int n = 1 + i % detail::kBvhGroupSize;
    const glm::vec3 centre(uniform(rng) * 6 - 3, uniform(rng) * 6 - 3, uniform(rng) * 6 - 3);
    const glm::vec3 aim(uniform(rng) - 0.5f, uniform(rng) - 0.5f, uniform(rng) - 0.5f);
    const float spread = i % 4 == 0 ? 0.5f : 0.02f, patch = i % 2 == 0 ? 0.0f : 0.3f;
    std::vector<glm::vec3> org(n), dir(n);
    for (int k = 0; k < n; ++k) {
      org[k] =
          centre + patch * glm::vec3(uniform(rng) - 0.5f, uniform(rng) - 0.5f, uniform(rng) - 0.5f);
      dir[k] =
          aim + spread * glm::vec3(uniform(rng) - 0.5f, uniform(rng) - 0.5f, uniform(rng) - 0.5f);
    }
    detail::BoxRayGroup group;
    if (!detail::boxRayGroupOf(org.data(), dir.data(), n, &group)) {
      // Refused only for a sign that differs along an axis
      bool mixed = false;
      for (int a = 0; a < 3; ++a) {
        bool pos = false, neg = false;
        for (const glm::vec3& d : dir) pos |= d[a] > 0.0f, neg |= !(d[a] > 0.0f);
        mixed |= pos && neg;
      }
      ASSERT_TRUE(mixed) << "case " << i;
      continue;
    }
    const float tmin = i % 5 == 0 ? 0.5f : 0.0f, tmax = i % 3 == 0 ? 2.0f : INFINITY;
    const unsigned gm = detail::groupBoxHits(node, group, tmin, tmax);
    for (int k = 0; k < n; ++k) {
      float tnear[W];
      const unsigned rm =
          detail::boxHitsScalar(node, detail::boxRayOf(org[k], dir[k]), tmin, tmax, tnear);
      ASSERT_EQ(rm & ~gm, 0u) << "case " << i << " ray " << k
                              << ": a box the ray enters, ruled out for the group";
      ray_hits += static_cast<unsigned>(std::popcount(rm));
    }
    ++groups;
    ruled_out += static_cast<unsigned>(used - std::popcount(gm));
  }
  EXPECT_GT(groups, 20000u);
  EXPECT_GT(ray_hits, groups);           // rays do enter boxes
  EXPECT_GT(ruled_out, groups * W / 4);  // and the group test rules many out
  // A group of one sign per axis but an invalid ray, or a zero direction, is refused
  const glm::vec3 o[2] = {{0, 0, 0}, {0, 0, 0}};
  const glm::vec3 bad[2] = {{1, 1, 1}, {1, 1, NAN}};
  const glm::vec3 zero[2] = {{1, 1, 1}, {1, 1, 0}};
  detail::BoxRayGroup g;
  EXPECT_FALSE(detail::boxRayGroupOf(o, bad, 2, &g));
  EXPECT_FALSE(detail::boxRayGroupOf(o, zero, 2, &g));
  EXPECT_TRUE(detail::boxRayGroupOf(o, zero, 1, &g));
}

// Rays cast as a group answer as the same rays cast one by one, bit for bit, in both the
// nearest-hit and the band search: a camera's rays over a scene (groups of neighbours, some
// beside the scene, some not), an orthographic camera's, and groups that cannot be bounded
// (random directions, NaN among them).
TEST(Bvh, GroupQueriesAnswerAsOneByOne) {
  const Scene scene = makeBuiltinScene("spheres:300");
  const RayScene rays(scene);
  const detail::Bvh& bvh = rays.data().bvh;
  std::uint64_t hits = 0, group_nodes = 0;
  auto band = [](const void*, float t) { return t * 1.001f; };
  auto check = [&](const std::vector<glm::vec3>& org, const std::vector<glm::vec3>& dir, float tmin,
                   float tmax) {
    for (std::size_t i = 0; i < org.size(); i += detail::kBvhGroupSize) {
      const int n = static_cast<int>(std::min<std::size_t>(detail::kBvhGroupSize, org.size() - i));
      detail::BvhHit one_group[detail::kBvhGroupSize];
      detail::BvhCandidates band_group[detail::kBvhGroupSize];
      detail::BvhTraversalCounts counts;
      detail::intersectNearestGroup(bvh, &org[i], &dir[i], n, tmin, tmax, detail::HitSides::kBoth,
                                    one_group, &counts);
      detail::intersectNearestBandGroup(bvh, &org[i], &dir[i], n, tmin, tmax,
                                        detail::HitSides::kCounterClockwiseOnly, band, nullptr,
                                        band_group);
      group_nodes += counts.group_nodes;
      for (int k = 0; k < n; ++k) {
        const detail::BvhHit h = detail::intersectNearest(bvh, org[i + k], dir[i + k], tmin, tmax,
                                                          detail::HitSides::kBoth);
        ASSERT_EQ(h.triangle, one_group[k].triangle) << "ray " << i + k;
        ASSERT_EQ(detail::bitCast<std::uint32_t>(h.t),
                  detail::bitCast<std::uint32_t>(one_group[k].t));
        ASSERT_EQ(detail::bitCast<std::uint32_t>(h.u),
                  detail::bitCast<std::uint32_t>(one_group[k].u));
        ASSERT_EQ(detail::bitCast<std::uint32_t>(h.v),
                  detail::bitCast<std::uint32_t>(one_group[k].v));
        hits += h.triangle != detail::kBvhNoTriangle;
        detail::BvhCandidates b;
        detail::intersectNearestBand(bvh, org[i + k], dir[i + k], tmin, tmax,
                                     detail::HitSides::kCounterClockwiseOnly, band, nullptr, &b);
        ASSERT_EQ(b.count, band_group[k].count) << "ray " << i + k;
        for (int c = 0; c < b.count; ++c) {
          ASSERT_EQ(b.hit[c].triangle, band_group[k].hit[c].triangle);
          ASSERT_EQ(detail::bitCast<std::uint32_t>(b.hit[c].t),
                    detail::bitCast<std::uint32_t>(band_group[k].hit[c].t));
        }
      }
    }
  };
  for (const bool ortho : {false, true}) {
    Camera cam = frameScene(scene, 96, 64);
    cam.ortho = ortho;
    const CameraRays c = cameraRays(cam);
    check(c.origins, c.directions, c.tmin, c.tmax);
  }
  detail::SplitMix64 rng(5);
  const Bounds box = scene.bounds();
  std::vector<glm::vec3> org(4000), dir(4000);
  for (std::size_t i = 0; i < org.size(); ++i) {
    org[i] = box.lo + (box.hi - box.lo) * glm::vec3(uniform(rng), uniform(rng), uniform(rng));
    dir[i] = glm::vec3(uniform(rng) - 0.5f, uniform(rng) - 0.5f, uniform(rng) - 0.5f);
    if (i % 97 == 0) dir[i].y = NAN;
  }
  check(org, dir, 0.0f, INFINITY);
  EXPECT_GT(hits, 1500u);
  EXPECT_GT(group_nodes, 0u);  // groups were formed
}

// The leaf test (SSE: the edge functions of four triangles at once) answers as the watertight
// test, bit for bit, and its quick rejection never leaves out a triangle that test hits,
// whatever the ray: random triangles, and triangles through the ray's origin line (edge
// functions exactly 0), from both sides and on every side setting.
TEST(Bvh, LeafTestAnswersAsTheWatertightTest) {
  detail::SplitMix64 rng(8);
  std::uint64_t hits = 0, dropped = 0, lanes = 0;
  for (int i = 0; i < 100000; ++i) {
    const glm::vec3 o(uniform(rng) * 4 - 2, uniform(rng) * 4 - 2, uniform(rng) * 4 - 2);
    glm::vec3 d(uniform(rng) - 0.5f, uniform(rng) - 0.5f, uniform(rng) - 0.5f);
    if (i % 9 == 0) d[i % 3] = 0.0f;
    const detail::ShearedRay r = detail::shearRay(o, d);
    detail::BvhTriangles4 leaf{};
    const int count = 1 + i % 4;
    for (int lane = 0; lane < 4; ++lane)
      leaf.triangle[lane] =
          lane < count ? static_cast<std::uint32_t>(lane) : detail::kBvhNoTriangle;
    for (int lane = 0; lane < count; ++lane) {
      glm::vec3 v[3];
      for (glm::vec3& p : v)
        p = o + d * (uniform(rng) * 4) +
            glm::vec3(uniform(rng) - 0.5f, uniform(rng) - 0.5f, uniform(rng) - 0.5f);
      if (i % 13 == lane) v[1] = o + d * 2.0f;  // a vertex on the ray: edge functions of 0
      if (i % 17 == lane) v[2] = v[1];          // degenerate
      for (int a = 0; a < 3; ++a)
        leaf.a[a][lane] = v[0][a], leaf.b[a][lane] = v[1][a], leaf.c[a][lane] = v[2][a];
    }
    const unsigned used = (1u << count) - 1;
    detail::LeafScreen screen;
    detail::screenLeaf(leaf, r, used, &screen);
    const unsigned kept = screen.candidates;
    ASSERT_EQ(kept & ~used, 0u) << "case " << i << ": an empty lane kept";
    for (int lane = 0; lane < count; ++lane) {
      ++lanes;
      detail::TriangleHit h;
      const glm::vec3 a(leaf.a[0][lane], leaf.a[1][lane], leaf.a[2][lane]);
      const glm::vec3 b(leaf.b[0][lane], leaf.b[1][lane], leaf.b[2][lane]);
      const glm::vec3 c(leaf.c[0][lane], leaf.c[1][lane], leaf.c[2][lane]);
      const bool hit =
          detail::intersectTriangle(r, a, b, c, -INFINITY, INFINITY, detail::HitSides::kBoth, &h);
      hits += hit;
      if (hit) {
        ASSERT_TRUE(kept & (1u << lane)) << "case " << i << " lane " << lane << ": a hit left out";
      }
      dropped += !(kept & (1u << lane));
      if (!(kept & (1u << lane))) continue;
      // The lane finished from the screen: the same answer, on each side setting and t range
      for (const detail::HitSides sides :
           {detail::HitSides::kBoth, detail::HitSides::kCounterClockwiseOnly,
            detail::HitSides::kClockwiseOnly}) {
        const float tmin = i % 5 == 0 ? 1.0f : -INFINITY, tmax = i % 7 == 0 ? 2.5f : INFINITY;
        detail::TriangleHit x, y;
        const bool full = detail::intersectTriangle(r, a, b, c, tmin, tmax, sides, &x);
        ASSERT_EQ(detail::leafLaneHit(leaf, screen, lane, r, tmin, tmax, sides, &y), full)
            << "case " << i;
        if (!full) continue;
        ASSERT_EQ(detail::bitCast<std::uint32_t>(x.t), detail::bitCast<std::uint32_t>(y.t));
        ASSERT_EQ(detail::bitCast<std::uint32_t>(x.u), detail::bitCast<std::uint32_t>(y.u));
        ASSERT_EQ(detail::bitCast<std::uint32_t>(x.v), detail::bitCast<std::uint32_t>(y.v));
        ASSERT_EQ(x.counter_clockwise, y.counter_clockwise);
      }
    }
  }
  EXPECT_GT(hits, lanes / 20);  // hits happen often enough to mean something
  EXPECT_GT(dropped, lanes / 4) << "the quick rejection rejects";
}

// nextUp is std::nextafter(x, infinity), bit for bit: zeros of both signs, subnormals, the
// largest float, infinities, NaN and random floats of every exponent.
TEST(Bvh, NextUpIsNextafterTowardInfinity) {
  std::vector<float> xs = {0.0f,
                           -0.0f,
                           std::numeric_limits<float>::denorm_min(),
                           -std::numeric_limits<float>::denorm_min(),
                           std::numeric_limits<float>::min(),
                           -std::numeric_limits<float>::min(),
                           std::numeric_limits<float>::max(),
                           -std::numeric_limits<float>::max(),
                           INFINITY,
                           -INFINITY,
                           1.0f,
                           -1.0f};
  detail::SplitMix64 rng(17);
  for (int i = 0; i < 200000; ++i)
    xs.push_back(detail::bitCast<float>(static_cast<std::uint32_t>(rng.next())));
  for (const float x : xs) {
    const float want = std::nextafter(x, INFINITY), got = detail::nextUp(x);
    if (std::isnan(x)) {
      ASSERT_TRUE(std::isnan(got));
      continue;
    }
    ASSERT_EQ(detail::bitCast<std::uint32_t>(got), detail::bitCast<std::uint32_t>(want)) << x;
  }
}

// The tree's arrays: aligned as their elements need at every size (on Linux an array of 2 MiB
// or more starts on a 2 MiB boundary, for the huge pages it asks for), and usable as any vector.
TEST(Bvh, LargePageArraysAreAlignedAndHoldTheirContents) {
  for (const std::size_t n :
       {std::size_t{1}, std::size_t{100}, std::size_t{9000}, std::size_t{20000}}) {
    std::vector<detail::BvhNode, detail::LargePageAllocator<detail::BvhNode>> v(n);
    ASSERT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % alignof(detail::BvhNode), 0u);
#if defined(__linux__)
    if (n * sizeof(detail::BvhNode) >= detail::kLargePage) {
      EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % detail::kLargePage, 0u);
    }
#endif
    for (std::size_t i = 0; i < n; ++i) v[i].child[0] = static_cast<std::uint32_t>(i);
    v.push_back(v[n / 2]);  // grows (and moves) as a vector does
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(v[i].child[0], i);
    EXPECT_EQ(v.back().child[0], n / 2);
  }
}

// The same answers from one ray at a time, a batch, and any thread count.
TEST(Bvh, BatchAndSingleQueriesAgreeAtAnyThreadCount) {
  const Scene scene = makeBuiltinScene("spheres:500");
  const RayScene rays(scene);
  const CameraRays cam = cameraRays(frameScene(scene, 160, 120));
  const std::vector<RayHit> batch = rays.intersect(cam.origins, cam.directions, cam.tmax, cam.tmin);
  std::uint64_t hit = 0;
  for (std::size_t i = 0; i < batch.size(); ++i) {
    const RayHit one = rays.intersect(cam.origins[i], cam.directions[i], cam.tmax, cam.tmin);
    ASSERT_EQ(one.polygon, batch[i].polygon);
    ASSERT_EQ(one.t, batch[i].t);
    hit += one.hit();
    if (one.hit()) {
      EXPECT_NEAR(glm::length(one.normal), 1.0f, 1e-5f);
      EXPECT_EQ(one.object, scene.object(one.polygon));
      // The hit point from the barycentrics is the hit point from t
      glm::vec3 v0, v1, v2;
      rays.triangleOf(one, &v0, &v1, &v2);
      const glm::vec3 p = (1 - one.u - one.v) * v0 + one.u * v1 + one.v * v2;
      const glm::vec3 q = cam.origins[i] + one.t * cam.directions[i];
      EXPECT_LT(glm::length(p - q), 1e-4f * (1 + glm::length(q)));
      // The normal (read from the tree's copy of the triangle) is the scene triangle's, to a few
      // float steps of a unit vector's components
      const glm::dvec3 n =
          glm::cross(glm::dvec3(v1) - glm::dvec3(v0), glm::dvec3(v2) - glm::dvec3(v0));
      const glm::dvec3 expected(n / glm::length(n));
      for (int a = 0; a < 3; ++a) ASSERT_NEAR(one.normal[a], expected[a], 4e-7) << "ray " << i;
      ASSERT_EQ(one.normal, batch[i].normal);
      EXPECT_EQ(rays.occluded(cam.origins[i], cam.directions[i], cam.tmax, cam.tmin), true);
    }
  }
  EXPECT_GT(hit, batch.size() / 20);
  EXPECT_THROW(rays.intersect(std::span(cam.origins).first(3), std::span(cam.directions).first(2)),
               Error);
  // Into the caller's array: the same answers; an array of the wrong size is refused
  std::vector<RayHit> into(batch.size());
  rays.intersect(cam.origins, cam.directions, into, cam.tmax, cam.tmin);
  for (std::size_t i = 0; i < batch.size(); ++i) {
    ASSERT_EQ(into[i].polygon, batch[i].polygon);
    ASSERT_EQ(detail::bitCast<std::uint32_t>(into[i].t),
              detail::bitCast<std::uint32_t>(batch[i].t));
  }
  EXPECT_THROW(rays.intersect(cam.origins, cam.directions, std::span(into).first(5)), Error);
}

}  // namespace
}  // namespace hsr
