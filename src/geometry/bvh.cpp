// The bounding volume hierarchy (bvh.hpp): binned SAH build, collapse to eight children per
// node, nearest-hit and any-hit traversal.

#include "geometry/bvh.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstddef>
#include <type_traits>

#include <glm/common.hpp>

#include "core/bit_cast.hpp"
#include "core/default_init.hpp"
#include "core/check.hpp"
#include "core/parallel.hpp"
#include "core/stopwatch.hpp"

#if defined(__SSE4_1__) && !defined(HSR_NO_SIMD)
#include <smmintrin.h>
#define HSR_BVH_SSE 1
#endif

namespace hsr::detail {
namespace {

// ---------------------------------------------------------------------------------------------
// Building

constexpr int kBins = 32;               // SAH candidates per axis (Wald 2007 uses 16 to 32)
constexpr std::uint32_t kLeafSize = 4;  // triangles per leaf: one BvhTriangles4
constexpr int kMedianDepth = 40;  // deeper than this, split at the median: depth stays bounded
constexpr std::uint32_t kParallelTriangles = 4096;  // smaller subtrees are built by one task

struct Box {
  glm::vec3 lo{INFINITY}, hi{-INFINITY};
  Box() = default;
  Box(const glm::vec3& l, const glm::vec3& h) : lo(l), hi(h) {}
  void extend(const Box& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  void extend(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  float halfArea() const {
    const glm::vec3 d = hi - lo;
    return d.x < 0.0f ? 0.0f : d.x * d.y + d.y * d.z + d.z * d.x;
  }
};

// A node of the binary tree the SAH builds, before it is collapsed.
// (No initialisers: the array has room for 2n nodes and the build writes each node it makes;
// the rest is never touched, so never zero-filled or even mapped.)
struct BinaryNode {
  glm::vec3 lo, hi;            // its box
  std::uint32_t left, right;   // inner: children
  std::uint32_t first, count;  // leaf: the PrimRefs [first, first + count)
  bool leaf;
  Box box() const { return {lo, hi}; }
};
static_assert(std::is_trivially_default_constructible_v<BinaryNode>);

// Per bin: the triangles whose centroid falls in it, and their boxes. A node of n triangles
// uses min(n, kBins) bins (more bins than triangles find no better split), and only those
// are cleared: a million-triangle build makes half a million small nodes.
struct Bins {
  // A bin's box, left uninitialised until the bin is used
  struct alignas(16) BinBox {
    float lo[4], hi[4];  // x, y, z and a lane kept at 0
    Box box() const { return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}; }
    void extend(const float* l, const float* h) {
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], l[a]), hi[a] = std::max(hi[a], h[a]);
    }
  };
  int used = kBins;
  BinBox box[3][kBins];
  std::uint32_t count[3][kBins];
  explicit Bins(int n = kBins) : used(n) {
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < used; ++i)
        box[a][i] = {{INFINITY, INFINITY, INFINITY, 0.0f}, {-INFINITY, -INFINITY, -INFINITY, 0.0f}},
        count[a][i] = 0;
  }
  void add(const Bins& o) {
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < used; ++i)
        box[a][i].extend(o.box[a][i].lo, o.box[a][i].hi), count[a][i] += o.count[a][i];
  }
};

// SAH cost of a leaf of n triangles, counted in blocks of four (they are tested together).
float blocks(std::uint32_t n) { return static_cast<float>((n + kLeafSize - 1) / kLeafSize); }

// A triangle while building: its box, its number, and its box's centre as its centroid
// (halves added: no overflow near FLT_MAX). Kept in one array that the build reorders in
// place, so each pass over a node reads memory in order.
struct PrimRef {
  glm::vec3 lo;
  std::uint32_t triangle;
  glm::vec3 hi;
  std::uint32_t pad;
  float centroid(int a) const { return 0.5f * lo[a] + 0.5f * hi[a]; }
  glm::vec3 centroid() const { return 0.5f * lo + 0.5f * hi; }
};

// A node's range of PrimRefs with the bounds of their boxes and of their centroids.
struct Range {
  std::uint32_t begin, end;
  Box box, centroids;
};

struct Builder {
  std::vector<PrimRef>& refs;
  std::vector<BinaryNode, DefaultInitAllocator<BinaryNode>>& nodes;
  std::vector<CollapsePlan, DefaultInitAllocator<CollapsePlan>>& plans;
  std::atomic<std::uint32_t> next_node{0};
  std::atomic<std::uint32_t> max_depth{0};

  std::uint32_t newNode() { return next_node.fetch_add(1, std::memory_order_relaxed); }

  // Builds the subtree over `r` into nodes[index].
  void build(std::uint32_t index, const Range& r, std::uint32_t depth) {
    std::uint32_t seen = max_depth.load(std::memory_order_relaxed);
    while (depth > seen && !max_depth.compare_exchange_weak(seen, depth)) {
    }
    BinaryNode& node = nodes[index];
    node.lo = r.box.lo, node.hi = r.box.hi;
    const std::uint32_t n = r.end - r.begin;
    node.leaf = n <= kLeafSize;
    if (node.leaf) {
      node.first = r.begin, node.count = n;
      planCollapse(nullptr, nullptr, 0.0f, &plans[index]);
      return;
    }
    Range left, right;
    split(r, depth, &left, &right);
    node.left = newNode();
    node.right = newNode();
    const std::uint32_t l = node.left, rr = node.right;
    if (n > kParallelTriangles) {
      tbb::parallel_invoke([&] { build(l, left, depth + 1); },
                           [&] { build(rr, right, depth + 1); });
    } else {
      build(l, left, depth + 1);
      build(rr, right, depth + 1);
    }
    planCollapse(&plans[l], &plans[rr], r.box.halfArea(), &plans[index]);
  }

  // Reorders r's PrimRefs into two non-empty halves, each with its bounds.
  void split(const Range& r, std::uint32_t depth, Range* left, Range* right) {
    const Box& cb = r.centroids;
    const glm::vec3 extent = cb.hi - cb.lo;
    const int widest =
        extent.x >= extent.y ? (extent.x >= extent.z ? 0 : 2) : (extent.y >= extent.z ? 1 : 2);
    // all centroids at one point: halve the range
    std::uint32_t mid = r.begin + (r.end - r.begin) / 2;
    if (extent[widest] > 0.0f && depth < kMedianDepth) {
      // Bin the centroids along each axis (in parallel for a large node)
      const int bin_count = static_cast<int>(std::min<std::uint32_t>(kBins, r.end - r.begin));
      glm::vec3 scale;
      for (int a = 0; a < 3; ++a)
        scale[a] = extent[a] > 0.0f ? static_cast<float>(bin_count) * 0.999f / extent[a] : 0.0f;
      // The bin as a float clamped to [0, kBins - 1] before it becomes an int: a tiny extent
      // makes the scale infinite, and 0 x infinity a NaN (max(0, NaN) is 0)
      auto binOf = [&](const PrimRef& p, int a) {
        const float k = (p.centroid(a) - cb.lo[a]) * scale[a];
        return static_cast<int>(std::min(static_cast<float>(bin_count - 1), std::max(0.0f, k)));
      };
      auto fill = [&](std::uint32_t b, std::uint32_t e, Bins& bins) {
#ifdef HSR_BVH_SSE
        // binOf's operations on the three axes at once (the same bins), and each bin's box
        // grown in one step
        const __m128 half = _mm_set1_ps(0.5f), zero = _mm_setzero_ps();
        const __m128 lo = _mm_setr_ps(cb.lo.x, cb.lo.y, cb.lo.z, 0.0f);
        const __m128 sc = _mm_setr_ps(scale.x, scale.y, scale.z, 0.0f);
        const __m128 top = _mm_set1_ps(static_cast<float>(bin_count - 1));
        for (std::uint32_t i = b; i < e; ++i) {
          const PrimRef& p = refs[i];
          // lane 3 (the triangle number and the padding) cleared: never a denormal to slow us
          const __m128 plo = _mm_blend_ps(_mm_loadu_ps(&p.lo.x), zero, 8);
          const __m128 phi = _mm_blend_ps(_mm_loadu_ps(&p.hi.x), zero, 8);
          const __m128 c = _mm_add_ps(_mm_mul_ps(half, plo), _mm_mul_ps(half, phi));
          const __m128 k = _mm_min_ps(_mm_max_ps(_mm_mul_ps(_mm_sub_ps(c, lo), sc), zero), top);
          alignas(16) std::int32_t bin[4];
          _mm_store_si128(reinterpret_cast<__m128i*>(bin), _mm_cvttps_epi32(k));
          for (int a = 0; a < 3; ++a) {
            Bins::BinBox& box = bins.box[a][bin[a]];
            _mm_store_ps(box.lo, _mm_min_ps(_mm_load_ps(box.lo), plo));
            _mm_store_ps(box.hi, _mm_max_ps(_mm_load_ps(box.hi), phi));
            bins.count[a][bin[a]]++;
          }
        }
#else
        for (std::uint32_t i = b; i < e; ++i) {
          const PrimRef& p = refs[i];
          for (int a = 0; a < 3; ++a) {
            const int k = binOf(p, a);
            bins.box[a][k].extend(&p.lo.x, &p.hi.x);
            bins.count[a][k]++;
          }
        }
#endif
      };
      Bins bins(bin_count);
      if (r.end - r.begin > 4 * kParallelTriangles) {
        bins = tbb::parallel_reduce(
            tbb::blocked_range<std::uint32_t>(r.begin, r.end, kParallelTriangles), Bins(bin_count),
            [&](const tbb::blocked_range<std::uint32_t>& br, Bins acc) {
              fill(br.begin(), br.end(), acc);
              return acc;
            },
            [](Bins x, const Bins& y) {
              x.add(y);
              return x;
            });
      } else {
        fill(r.begin, r.end, bins);
      }
      // Sweep: the cost of splitting after bin k is area(left) * blocks(left) + area(right) *
      // blocks(right)
      float best_cost = INFINITY;
      int best_axis = -1, best_bin = 0;
      for (int a = 0; a < 3; ++a) {
        if (!(extent[a] > 0.0f)) continue;
        float right_cost[kBins];
        Box acc;
        std::uint32_t count = 0;
        for (int k = bin_count - 1; k > 0; --k) {
          acc.extend(bins.box[a][k].box());
          count += bins.count[a][k];
          right_cost[k] = acc.halfArea() * blocks(count);
        }
        acc = Box{};
        count = 0;
        for (int k = 0; k < bin_count - 1; ++k) {
          acc.extend(bins.box[a][k].box());
          count += bins.count[a][k];
          const float cost = acc.halfArea() * blocks(count) + right_cost[k + 1];
          if (count > 0 && count < r.end - r.begin && cost < best_cost)
            best_cost = cost, best_axis = a, best_bin = k;
        }
      }
      if (best_axis >= 0) {
        // Partition in place, gathering each side's bounds on the way
        std::uint32_t i = r.begin, j = r.end;
        Box lb, lc, rb, rc;
        while (i < j) {
          PrimRef& p = refs[i];
          if (binOf(p, best_axis) <= best_bin) {
            lb.extend(Box{p.lo, p.hi}), lc.extend(p.centroid());
            ++i;
          } else {
            rb.extend(Box{p.lo, p.hi}), rc.extend(p.centroid());
            std::swap(p, refs[--j]);
          }
        }
        if (i > r.begin && i < r.end) {
          *left = {r.begin, i, lb, lc};
          *right = {i, r.end, rb, rc};
          return;
        }
      }
    }
    if (extent[widest] > 0.0f) {
      // The median along the widest axis (ties by triangle number, so the tree is deterministic)
      std::nth_element(
          refs.begin() + r.begin, refs.begin() + mid, refs.begin() + r.end,
          [&](const PrimRef& x, const PrimRef& y) {
            return x.centroid(widest) < y.centroid(widest) ||
                   (x.centroid(widest) == y.centroid(widest) && x.triangle < y.triangle);
          });
    }
    *left = bounds(r.begin, mid);
    *right = bounds(mid, r.end);
  }

  Range bounds(std::uint32_t begin, std::uint32_t end) const {
    Range r{begin, end, {}, {}};
    for (std::uint32_t i = begin; i < end; ++i) {
      r.box.extend(Box{refs[i].lo, refs[i].hi});
      r.centroids.extend(refs[i].centroid());
    }
    return r;
  }
};

// The binary tree collapsed to eight children per node, depth first.
struct Collapser {
  const std::vector<BinaryNode, DefaultInitAllocator<BinaryNode>>& binary;
  const std::vector<CollapsePlan, DefaultInitAllocator<CollapsePlan>>& plans;
  const std::vector<PrimRef>& refs;
  std::span<const glm::vec3> a, b, c;
  Bvh& bvh;
  std::uint64_t depth = 0;
  double sah = 0;  // sum over nodes of area * cost, divided by the root's area at the end

  std::uint32_t leaf(const BinaryNode& n) {
    BvhTriangles4 t{};
    for (int lane = 0; lane < 4; ++lane) {
      t.triangle[lane] = kBvhNoTriangle;
      for (int ax = 0; ax < 3; ++ax) t.a[ax][lane] = t.b[ax][lane] = t.c[ax][lane] = 0.0f;
    }
    for (std::uint32_t i = 0; i < n.count; ++i) {
      const std::uint32_t tri = refs[n.first + i].triangle;
      t.triangle[i] = tri;
      for (int ax = 0; ax < 3; ++ax)
        t.a[ax][i] = a[tri][ax], t.b[ax][i] = b[tri][ax], t.c[ax][i] = c[tri][ax];
    }
    // Lanes in ascending triangle number: the first hit of a tie is then the one kept
    std::uint32_t order[4] = {0, 1, 2, 3};
    std::sort(order, order + n.count,
              [&](std::uint32_t x, std::uint32_t y) { return t.triangle[x] < t.triangle[y]; });
    BvhTriangles4 sorted = t;
    for (std::uint32_t i = 0; i < n.count; ++i) {
      sorted.triangle[i] = t.triangle[order[i]];
      for (int ax = 0; ax < 3; ++ax) {
        sorted.a[ax][i] = t.a[ax][order[i]];
        sorted.b[ax][i] = t.b[ax][order[i]];
        sorted.c[ax][i] = t.c[ax][order[i]];
      }
    }
    sah += n.box().halfArea() * blocks(n.count);
    bvh.leaves.push_back(sorted);
    bvh.stats.leaves++;
    return BvhNode::kLeaf | static_cast<std::uint32_t>(bvh.leaves.size() - 1);
  }

  // The roots a subtree stands as in `slots` slots, by its plan
  void rootsOf(std::uint32_t index, int slots, std::uint32_t* kids, int* count) const {
    const CollapsePlan& p = plans[index];
    if (binary[index].leaf || p.left[slots - 1] == 0) {
      kids[(*count)++] = index;
      return;
    }
    rootsOf(binary[index].left, p.left[slots - 1], kids, count);
    rootsOf(binary[index].right, p.right[slots - 1], kids, count);
  }

  std::uint32_t collapse(std::uint32_t index, std::uint64_t level) {
    const BinaryNode& n = binary[index];
    if (n.leaf) return leaf(n);
    depth = std::max(depth, level);
    // The children: the roots the plan spreads the two halves over
    std::uint32_t kids[kBvhWidth];
    int count = 0;
    rootsOf(n.left, plans[index].node_left, kids, &count);
    rootsOf(n.right, plans[index].node_right, kids, &count);
    sah += n.box().halfArea();
    BvhNode node{};
    for (int i = 0; i < kBvhWidth; ++i) {
      if (i < count) {
        const Box box = binary[kids[i]].box();
        for (int ax = 0; ax < 3; ++ax) node.lo[ax][i] = box.lo[ax], node.hi[ax][i] = box.hi[ax];
      } else {
        for (int ax = 0; ax < 3; ++ax) node.lo[ax][i] = INFINITY, node.hi[ax][i] = -INFINITY;
        node.child[i] = BvhNode::kEmpty;
      }
    }
    const auto me = static_cast<std::uint32_t>(bvh.nodes.size());
    bvh.nodes.push_back(node);
    for (int i = 0; i < count; ++i) {
      const std::uint32_t ref = collapse(kids[i], level + 1);
      bvh.nodes[me].child[i] = ref;
    }
    return me;
  }
};

}  // namespace

void planCollapse(const CollapsePlan* l, const CollapsePlan* r, float area, CollapsePlan* out) {
  if (!l) {
    for (int i = 0; i < kBvhWidth; ++i) out->cost[i] = 0.0f, out->left[i] = out->right[i] = 0;
    return;
  }
  // spread[j - 1]: the best with the left and right parts given j slots between them
  float spread[kBvhWidth];
  std::uint8_t spread_left[kBvhWidth];
  spread[0] = INFINITY, spread_left[0] = 0;
  for (int j = 2; j <= kBvhWidth; ++j) {
    float best = INFINITY;
    int best_k = 1;
    for (int k = 1; k < j; ++k) {
      const float c = l->cost[k - 1] + r->cost[j - k - 1];
      if (c < best) best = c, best_k = k;
    }
    spread[j - 1] = best, spread_left[j - 1] = static_cast<std::uint8_t>(best_k);
  }
  out->node_left = spread_left[kBvhWidth - 1];
  out->node_right = static_cast<std::uint8_t>(kBvhWidth - out->node_left);
  out->cost[0] = area + spread[kBvhWidth - 1], out->left[0] = out->right[0] = 0;
  for (int i = 2; i <= kBvhWidth; ++i) {
    if (spread[i - 1] < out->cost[i - 2]) {
      out->cost[i - 1] = spread[i - 1];
      out->left[i - 1] = spread_left[i - 1];
      out->right[i - 1] = static_cast<std::uint8_t>(i - spread_left[i - 1]);
    } else {
      out->cost[i - 1] = out->cost[i - 2], out->left[i - 1] = out->left[i - 2],
                    out->right[i - 1] = out->right[i - 2];
    }
  }
}

Bvh buildBvh(std::span<const glm::vec3> a, std::span<const glm::vec3> b,
             std::span<const glm::vec3> c) {
  const detail::Stopwatch t0;
  HSR_CHECK(a.size() == b.size() && b.size() == c.size());
  Bvh bvh;
  // Each finite triangle's box
  std::vector<PrimRef> refs;
  refs.reserve(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    Box box;
    box.extend(a[i]);
    box.extend(b[i]);
    box.extend(c[i]);
    const bool finite = std::isfinite(box.lo.x) && std::isfinite(box.lo.y) &&
                        std::isfinite(box.lo.z) && std::isfinite(box.hi.x) &&
                        std::isfinite(box.hi.y) && std::isfinite(box.hi.z);
    if (!finite) continue;
    refs.push_back({box.lo, static_cast<std::uint32_t>(i), box.hi, 0});
  }
  bvh.stats.triangles = refs.size();
  if (refs.empty()) {
    bvh.stats.build_ms = t0.ms();
    return bvh;
  }
  // The binary tree: at most 2n - 1 nodes
  std::vector<BinaryNode, DefaultInitAllocator<BinaryNode>> binary(2 * refs.size());
  std::vector<CollapsePlan, DefaultInitAllocator<CollapsePlan>> plans(binary.size());
  Builder builder{refs, binary, plans};
  const Range all = builder.bounds(0, static_cast<std::uint32_t>(refs.size()));
  bvh.lo = all.box.lo, bvh.hi = all.box.hi;
  const std::uint32_t root = builder.newNode();
  builder.build(root, all, 0);
  // Collapsed, depth first
  Collapser collapser{binary, plans, refs, a, b, c, bvh};
  bvh.nodes.reserve(builder.next_node.load() / 3 + 1);
  bvh.leaves.reserve(refs.size() / 2 + 1);
  bvh.root = collapser.collapse(root, 1);
  bvh.stats.nodes = bvh.nodes.size();
  bvh.stats.depth = std::max<std::uint64_t>(collapser.depth, 1);
  const float root_area = binary[root].box().halfArea();
  bvh.stats.sah_cost = root_area > 0.0f ? collapser.sah / root_area : 0.0;
  bvh.stats.bytes =
      bvh.nodes.capacity() * sizeof(BvhNode) + bvh.leaves.capacity() * sizeof(BvhTriangles4);
  bvh.stats.build_ms = t0.ms();
  return bvh;
}

// ---------------------------------------------------------------------------------------------
// Traversal

namespace {

// Ize 2013: widening the far distance by 2 gamma(3) makes the float box test conservative.
constexpr float kWidenFar = 1.0f + 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);

// max and min as SSE's maxps/minps: a NaN in `a` yields `b`.
inline float maxps(float a, float b) { return a > b ? a : b; }
inline float minps(float a, float b) { return a < b ? a : b; }

}  // namespace

bool rayIsValid(const glm::vec3& org, const glm::vec3& dir) {
  return std::isfinite(org.x) && std::isfinite(org.y) && std::isfinite(org.z) &&
         std::isfinite(dir.x) && std::isfinite(dir.y) && std::isfinite(dir.z) &&
         (dir.x != 0.0f || dir.y != 0.0f || dir.z != 0.0f);
}

BoxRay boxRayOf(const glm::vec3& org, const glm::vec3& dir) {
  BoxRay r;
  for (int a = 0; a < 3; ++a) {
    r.org[a] = org[a];
    r.inv[a] = 1.0f / dir[a];  // +-infinity along an axis the ray is parallel to
    r.near_is_hi[a] = std::signbit(dir[a]) ? 1 : 0;
  }
  return r;
}

// The slab test (Kay & Kajiya 1986) for a node's boxes. A NaN, from a ray lying in a box's face,
// never narrows the interval, so the test stays conservative.
unsigned boxHitsScalar(const BvhNode& node, const BoxRay& r, float tmin, float tmax,
                       float tnear[kBvhWidth]) {
  unsigned mask = 0;
  for (int i = 0; i < kBvhWidth; ++i) {
    float t0 = tmin, t1 = INFINITY;
    for (int a = 0; a < 3; ++a) {
      const float near_face = r.near_is_hi[a] ? node.hi[a][i] : node.lo[a][i];
      const float far_face = r.near_is_hi[a] ? node.lo[a][i] : node.hi[a][i];
      t0 = maxps((near_face - r.org[a]) * r.inv[a], t0);
      t1 = minps((far_face - r.org[a]) * r.inv[a], t1);
    }
    t1 = minps(t1 * kWidenFar, tmax);
    tnear[i] = t0;
    if (t0 <= t1) mask |= 1u << i;
  }
  return mask;
}

#ifdef HSR_BVH_SSE
namespace {
// A ray as the SSE node test wants it, prepared once: origin and reciprocal direction in every
// lane, and where in a node each axis's near and far faces lie.
struct BoxRaySse {
  __m128 org[3], inv[3];
  std::uint32_t near_at[3], far_at[3];  // byte offsets of the near and far rows in a BvhNode
};
// Filled in place, a word at a time: a copy of the whole would read back as one 16-byte load
// what was just written in 4-byte stores, a stall on every ray.
inline void prepareBoxRaySse(const BoxRay& r, BoxRaySse& p) {
  for (int a = 0; a < 3; ++a) {
    p.org[a] = _mm_set1_ps(r.org[a]);
    p.inv[a] = _mm_set1_ps(r.inv[a]);
    const std::uint32_t lo =
        static_cast<std::uint32_t>(offsetof(BvhNode, lo) + sizeof(float[kBvhWidth]) * a);
    const std::uint32_t hi =
        static_cast<std::uint32_t>(offsetof(BvhNode, hi) + sizeof(float[kBvhWidth]) * a);
    p.near_at[a] = r.near_is_hi[a] ? hi : lo;
    p.far_at[a] = r.near_is_hi[a] ? lo : hi;
  }
}
inline __m128 row(const BvhNode& node, std::uint32_t at, int quad) {
  return _mm_load_ps(reinterpret_cast<const float*>(reinterpret_cast<const char*>(&node) + at) +
                     4 * quad);
}
// The scalar test's operations, in its order, four boxes at once (the quads of a node are
// independent: the processor overlaps them).
inline unsigned boxHitsPrepared(const BvhNode& node, const BoxRaySse& r, __m128 tmin, float tmax,
                                float tnear[kBvhWidth]) {
  unsigned mask = 0;
  const __m128 widen = _mm_set1_ps(kWidenFar), limit = _mm_set1_ps(tmax);
  for (int q = 0; q < kBvhWidth / 4; ++q) {
    __m128 t0 = tmin, t1 = _mm_set1_ps(INFINITY);
    for (int a = 0; a < 3; ++a) {
      t0 = _mm_max_ps(_mm_mul_ps(_mm_sub_ps(row(node, r.near_at[a], q), r.org[a]), r.inv[a]), t0);
      t1 = _mm_min_ps(_mm_mul_ps(_mm_sub_ps(row(node, r.far_at[a], q), r.org[a]), r.inv[a]), t1);
    }
    t1 = _mm_min_ps(_mm_mul_ps(t1, widen), limit);
    _mm_storeu_ps(tnear + 4 * q, t0);
    mask |= static_cast<unsigned>(_mm_movemask_ps(_mm_cmple_ps(t0, t1))) << (4 * q);
  }
  return mask;
}
}  // namespace
unsigned boxHitsSse(const BvhNode& node, const BoxRay& r, float tmin, float tmax,
                    float tnear[kBvhWidth]) {
  BoxRaySse p;
  prepareBoxRaySse(r, p);
  return boxHitsPrepared(node, p, _mm_set1_ps(tmin), tmax, tnear);
}
bool boxHitsSseAvailable() { return true; }
#else
unsigned boxHitsSse(const BvhNode& node, const BoxRay& r, float tmin, float tmax,
                    float tnear[kBvhWidth]) {
  return boxHitsScalar(node, r, tmin, tmax, tnear);
}
bool boxHitsSseAvailable() { return false; }
#endif

// The group's bounds. Each ray's own test computes (face - org) * inv per axis, in float:
// both steps are monotone in org and in inv (rounding is monotone), so over the group each
// product lies between the products at the corners of the origins' and inverses' ranges, and
// 1 / dir is monotone too, so the inverses lie between the inverses of the directions' bounds.
// (the walk calls the body itself: inlined whatever the optimiser's budget at link time)
[[gnu::always_inline]] inline bool boxRayGroupOfInline(const glm::vec3* org, const glm::vec3* dir,
                                                       int n, BoxRayGroup* g) {
  if (n < 1) return false;
  glm::vec3 olo, ohi, dlo, dhi;
#ifdef HSR_BVH_SSE
  // Four lanes a vector, the fourth ignored: a vec3 and the next one's first float (the last
  // one's three floats read alone, never past the array). x - x is NaN just where x is not
  // finite: unordered with itself.
  auto load = [](const glm::vec3* v, bool last) {
    return last ? _mm_setr_ps(v->x, v->y, v->z, 0.0f) : _mm_loadu_ps(&v->x);
  };
  __m128 o = load(org, n == 1), d = load(dir, n == 1);
  __m128 o_lo = o, o_hi = o, d_lo = d, d_hi = d;
  __m128 bad = _mm_setzero_ps();
  for (int i = 0; i < n; ++i) {
    o = load(org + i, i == n - 1), d = load(dir + i, i == n - 1);
    bad = _mm_or_ps(
        bad, _mm_or_ps(_mm_cmpunord_ps(_mm_sub_ps(o, o), o), _mm_cmpunord_ps(_mm_sub_ps(d, d), d)));
    o_lo = _mm_min_ps(o_lo, o), o_hi = _mm_max_ps(o_hi, o);
    d_lo = _mm_min_ps(d_lo, d), d_hi = _mm_max_ps(d_hi, d);
  }
  if (_mm_movemask_ps(bad) & 7) return false;
  alignas(16) float b[4][4];
  _mm_store_ps(b[0], o_lo), _mm_store_ps(b[1], o_hi), _mm_store_ps(b[2], d_lo),
      _mm_store_ps(b[3], d_hi);
  olo = {b[0][0], b[0][1], b[0][2]}, ohi = {b[1][0], b[1][1], b[1][2]};
  dlo = {b[2][0], b[2][1], b[2][2]}, dhi = {b[3][0], b[3][1], b[3][2]};
#else
  olo = ohi = org[0], dlo = dhi = dir[0];
  glm::vec3 finite(0.0f);  // x - x is 0 for a finite x, NaN for an infinity or a NaN
  for (int i = 0; i < n; ++i) {
    finite += (org[i] - org[i]) + (dir[i] - dir[i]);
    olo = glm::min(olo, org[i]), ohi = glm::max(ohi, org[i]);
    dlo = glm::min(dlo, dir[i]), dhi = glm::max(dhi, dir[i]);
  }
  if (!(finite.x == 0.0f && finite.y == 0.0f && finite.z == 0.0f)) return false;
#endif
  for (int a = 0; a < 3; ++a) {
    // both signs (or a zero) along this axis; one sign means no direction is 0, every ray valid
    if (!(dlo[a] > 0.0f || dhi[a] < 0.0f)) return false;
    g->org_lo[a] = olo[a], g->org_hi[a] = ohi[a];
    g->inv_lo[a] = 1.0f / dhi[a], g->inv_hi[a] = 1.0f / dlo[a];  // 1 / x falls as x grows
    if (!std::isfinite(g->inv_lo[a]) || !std::isfinite(g->inv_hi[a])) return false;
    g->near_is_hi[a] = dhi[a] < 0.0f ? 1 : 0;
  }
  return true;
}
bool boxRayGroupOf(const glm::vec3* org, const glm::vec3* dir, int n, BoxRayGroup* g) {
  return boxRayGroupOfInline(org, dir, n, g);
}

// boxHitsScalar's interval for the whole group: its entry no later than any ray's, its exit no
// earlier. No NaN arises (the inverses are finite and not 0; an empty child's faces are
// infinities, which give it an empty interval).
// (the walk calls the body itself: inlined whatever the optimiser's budget at link time)
[[gnu::always_inline]] inline unsigned groupBoxHitsInline(const BvhNode& node, const BoxRayGroup& g,
                                                          float tmin, float tmax) {
  float t0[kBvhWidth], t1[kBvhWidth];
  for (int i = 0; i < kBvhWidth; ++i) t0[i] = tmin, t1[i] = INFINITY;
  for (int a = 0; a < 3; ++a) {
    const float* near_face = g.near_is_hi[a] ? node.hi[a] : node.lo[a];
    const float* far_face = g.near_is_hi[a] ? node.lo[a] : node.hi[a];
    const float olo = g.org_lo[a], ohi = g.org_hi[a], ilo = g.inv_lo[a], ihi = g.inv_hi[a];
    for (int i = 0; i < kBvhWidth; ++i) {  // (eight lanes side by side: the compiler's SIMD)
      const float n0 = near_face[i] - ohi, n1 = near_face[i] - olo;
      const float f0 = far_face[i] - ohi, f1 = far_face[i] - olo;
      const float enter = std::min(std::min(n0 * ilo, n0 * ihi), std::min(n1 * ilo, n1 * ihi));
      const float leave = std::max(std::max(f0 * ilo, f0 * ihi), std::max(f1 * ilo, f1 * ihi));
      t0[i] = std::max(t0[i], enter);
      t1[i] = std::min(t1[i], leave);
    }
  }
  unsigned mask = 0;
  for (int i = 0; i < kBvhWidth; ++i)
    if (t0[i] <= std::min(t1[i] * kWidenFar, tmax)) mask |= 1u << i;
  return mask;
}
unsigned groupBoxHits(const BvhNode& node, const BoxRayGroup& g, float tmin, float tmax) {
  return groupBoxHitsInline(node, g, tmin, tmax);
}

// A leaf's triangles up to their edge functions, with the watertight test's operations in its
// order (so the same floats): four at once in SSE, or lane by lane in the scalar build. A lane
// is left out only where the test would reject it for its edge functions' signs: all three
// non-zero and of mixed signs.
// (the walk calls the body itself: inlined whatever the optimiser's budget at link time)
[[gnu::always_inline]] inline void screenLeafInline(const BvhTriangles4& leaf, const ShearedRay& r,
                                                    unsigned used, LeafScreen* out) {
#ifdef HSR_BVH_SSE
  const __m128 ox = _mm_set1_ps(r.org[r.kx]), oy = _mm_set1_ps(r.org[r.ky]),
               oz = _mm_set1_ps(r.org[r.kz]);
  const __m128 sx = _mm_set1_ps(r.sx), sy = _mm_set1_ps(r.sy), sz = _mm_set1_ps(r.sz);
  auto project = [&](const float(&v)[3][4], __m128& x, __m128& y, float* z) {
    const __m128 vz = _mm_sub_ps(_mm_load_ps(v[r.kz]), oz);
    x = _mm_sub_ps(_mm_sub_ps(_mm_load_ps(v[r.kx]), ox), _mm_mul_ps(sx, vz));
    y = _mm_sub_ps(_mm_sub_ps(_mm_load_ps(v[r.ky]), oy), _mm_mul_ps(sy, vz));
    _mm_store_ps(z, _mm_mul_ps(sz, vz));
  };
  __m128 ax, ay, bx, by, cx, cy;
  project(leaf.a, ax, ay, out->az);
  project(leaf.b, bx, by, out->bz);
  project(leaf.c, cx, cy, out->cz);
  const __m128 U = _mm_sub_ps(_mm_mul_ps(cx, by), _mm_mul_ps(cy, bx));
  const __m128 V = _mm_sub_ps(_mm_mul_ps(ax, cy), _mm_mul_ps(ay, cx));
  const __m128 W = _mm_sub_ps(_mm_mul_ps(bx, ay), _mm_mul_ps(by, ax));
  _mm_store_ps(out->U, U);
  _mm_store_ps(out->V, V);
  _mm_store_ps(out->W, W);
  const __m128 zero = _mm_setzero_ps();
  const __m128 some_neg =
      _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(U, zero), _mm_cmplt_ps(V, zero)), _mm_cmplt_ps(W, zero));
  const __m128 some_pos =
      _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(U, zero), _mm_cmpgt_ps(V, zero)), _mm_cmpgt_ps(W, zero));
  const __m128 some_zero =
      _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(U, zero), _mm_cmpeq_ps(V, zero)), _mm_cmpeq_ps(W, zero));
  const __m128 outside = _mm_andnot_ps(some_zero, _mm_and_ps(some_neg, some_pos));
  out->candidates = used & ~static_cast<unsigned>(_mm_movemask_ps(outside));
#else
  out->candidates = 0;
  for (int lane = 0; lane < 4; ++lane) {
    float x[3], y[3];
    const float(*v[3])[4] = {leaf.a, leaf.b, leaf.c};
    float* z[3] = {out->az, out->bz, out->cz};
    for (int k = 0; k < 3; ++k) {
      const float vz = v[k][r.kz][lane] - r.org[r.kz];
      x[k] = (v[k][r.kx][lane] - r.org[r.kx]) - r.sx * vz;
      y[k] = (v[k][r.ky][lane] - r.org[r.ky]) - r.sy * vz;
      z[k][lane] = r.sz * vz;
    }
    const float U = x[2] * y[1] - y[2] * x[1], V = x[0] * y[2] - y[0] * x[2],
                W = x[1] * y[0] - y[1] * x[0];
    out->U[lane] = U, out->V[lane] = V, out->W[lane] = W;
    const bool outside = U != 0.0f && V != 0.0f && W != 0.0f &&
                         (U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f);
    if ((used & (1u << lane)) && !outside) out->candidates |= 1u << lane;
  }
#endif
}
void screenLeaf(const BvhTriangles4& leaf, const ShearedRay& r, unsigned used, LeafScreen* out) {
  screenLeafInline(leaf, r, used, out);
}

// (the walk calls the body itself: inlined whatever the optimiser's budget at link time)
[[gnu::always_inline]] inline bool leafLaneHitInline(const BvhTriangles4& leaf,
                                                     const LeafScreen& screen, int lane,
                                                     const ShearedRay& r, float tmin, float tmax,
                                                     HitSides sides, TriangleHit* hit) {
  const float U = screen.U[lane], V = screen.V[lane], W = screen.W[lane];
  if (U == 0.0f || V == 0.0f || W == 0.0f) {  // the test's fallback to double: the test itself
    const glm::vec3 a(leaf.a[0][lane], leaf.a[1][lane], leaf.a[2][lane]);
    const glm::vec3 b(leaf.b[0][lane], leaf.b[1][lane], leaf.b[2][lane]);
    const glm::vec3 c(leaf.c[0][lane], leaf.c[1][lane], leaf.c[2][lane]);
    return intersectTriangle(r, a, b, c, tmin, tmax, sides, hit);
  }
  return finishTriangleHit(U, V, W, screen.az[lane], screen.bz[lane], screen.cz[lane], tmin, tmax,
                           sides, hit);
}
bool leafLaneHit(const BvhTriangles4& leaf, const LeafScreen& screen, int lane, const ShearedRay& r,
                 float tmin, float tmax, HitSides sides, TriangleHit* hit) {
  return leafLaneHitInline(leaf, screen, lane, r, tmin, tmax, sides, hit);
}

namespace {

// A ray made ready once for the node test this build uses (the SSE sibling's lanes and face
// offsets, or the scalar test's BoxRay), then tested against node after node.
struct NodeTestRay {
  BoxRay box;
#ifdef HSR_BVH_SSE
  BoxRaySse sse;
#endif
  NodeTestRay(const glm::vec3& org, const glm::vec3& dir) : box(boxRayOf(org, dir)) {
#ifdef HSR_BVH_SSE
    prepareBoxRaySse(box, sse);
#endif
  }
  unsigned test(const BvhNode& node, float tmin, float tmax, float tnear[kBvhWidth]) const {
#ifdef HSR_BVH_SSE
    return boxHitsPrepared(node, sse, _mm_set1_ps(tmin), tmax, tnear);
#else
    return boxHitsScalar(node, box, tmin, tmax, tnear);
#endif
  }
};

// at most a node's children pushed per level
constexpr int kStackSize = kBvhWidth * (kMedianDepth + 32) + 8;

struct StackEntry {
  std::uint32_t ref;
  float tnear;
};

// Hits sorted by t, then by triangle number.
bool before(const BvhHit& x, const BvhHit& y) {
  return x.t < y.t || (x.t == y.t && x.triangle < y.triangle);
}

// The lanes of a leaf that hold a triangle (they are filled from lane 0).
inline unsigned usedLanes(const BvhTriangles4& leaf) {
  unsigned used = 0;
  for (int lane = 0; lane < 4; ++lane)
    if (leaf.triangle[lane] != kBvhNoTriangle) used |= 1u << lane;
  return used;
}

// One ray's nearest-hit search; with kBand, the hits within limit(nearest) are kept too. Depth
// first, the nearest child next and the others on a stack (farthest deepest); a box is entered
// only while its entry distance is within the limit.
template <bool kBand>
struct NearestSearch {
  // What is kept: the nearest hit, or with kBand the nearest and its band
  using Out = std::conditional_t<kBand, BvhCandidates, BvhHit>;
  const Bvh& bvh;
  glm::vec3 org, dir;
  ShearedRay sheared;  // made when the first leaf is reached (most rays that miss reach none)
  bool sheared_ready = false;
  NodeTestRay box_ray;
  float tmin;
  float tmax;
  HitSides sides;
  BvhBandLimit limit_of;
  const void* context;
  Out* out;
  // Hits are looked for up to `limit`: tmax until something is hit, then the nearest hit's t
  // (or its band's end)
  float limit;
  bool found = false;
  std::uint64_t visited = 0, tested = 0;
  std::vector<std::pair<glm::vec3, glm::vec3>>* entered = nullptr;

  NearestSearch(const Bvh& b, const glm::vec3& o_, const glm::vec3& d_, float t0, float t1,
                HitSides s, BvhBandLimit l, const void* c, Out* o)
      : bvh(b),
        org(o_),
        dir(d_),
        box_ray(o_, d_),
        tmin(t0),
        tmax(t1),
        sides(s),
        limit_of(l),
        context(c),
        out(o),
        limit(t1) {
    if constexpr (kBand) out->count = 0;
  }

  // A leaf: its triangles, each kept when nearer than what was kept (a tie: the lower number)
  void leaf(std::uint32_t ref) {
    const BvhTriangles4& leaf = bvh.leaves[ref & ~BvhNode::kLeaf];
    if (!sheared_ready) shearRayInto(org, dir, sheared), sheared_ready = true;
    const unsigned used = usedLanes(leaf);
    tested += static_cast<unsigned>(std::popcount(used));
    LeafScreen screen;
    screenLeafInline(leaf, sheared, used, &screen);
    for (unsigned lanes = screen.candidates; lanes != 0; lanes &= lanes - 1) {
      const int lane = std::countr_zero(lanes);
      TriangleHit h;
      // Up to the limit itself once something is hit (a tie), short of tmax before
      const float upto = found ? nextUp(limit) : tmax;
      if (!leafLaneHitInline(leaf, screen, lane, sheared, tmin, upto, sides, &h)) continue;
      const BvhHit hit{h.t,
                       h.u,
                       h.v,
                       leaf.triangle[lane],
                       h.counter_clockwise,
                       static_cast<std::uint8_t>(lane),
                       ref & ~BvhNode::kLeaf};
      if constexpr (!kBand) {
        if (found && !before(hit, *out)) continue;  // as near, a higher number
        *out = hit;
        found = true;
        limit = hit.t;
        continue;
      } else {
        // Insert in order, the farthest falling off the end
        int i = out->count < kBvhCandidates ? out->count++ : kBvhCandidates;
        if (i == kBvhCandidates && !before(hit, out->hit[kBvhCandidates - 1])) continue;
        if (i == kBvhCandidates) --i;
        for (; i > 0 && before(hit, out->hit[i - 1]); --i) out->hit[i] = out->hit[i - 1];
        out->hit[i] = hit;
        if (i == 0) {  // a new nearest: the limit moves in, and hits beyond it go
          found = true;
          limit = kBand ? limit_of(context, hit.t) : hit.t;
          while (out->count > 1 && out->hit[out->count - 1].t > limit) --out->count;
        }
      }
    }
  }

  // Everything below `ref` (a node or a leaf) the ray may reach.
  void from(std::uint32_t ref) {
    // The stack as two arrays: an entry is read back as it was written, a word at a time
    std::uint32_t stack_ref[kStackSize];
    float stack_tnear[kStackSize];
    int sp = 0;
    for (;;) {
      // Down through inner nodes: test the node's boxes, go on into the nearest one hit
      while (!(ref & BvhNode::kLeaf)) {
        ++visited;
        const BvhNode& node = bvh.nodes[ref];
        float tnear[kBvhWidth];
        unsigned mask = box_ray.test(node, tmin, limit, tnear);
        if (entered)
          for (int i = 0; i < kBvhWidth; ++i)
            if (mask & (1u << i))
              entered->push_back({{node.lo[0][i], node.lo[1][i], node.lo[2][i]},
                                  {node.hi[0][i], node.hi[1][i], node.hi[2][i]}});
        if (mask == 0) goto pop;
        int first = std::countr_zero(mask);
        mask &= mask - 1;
        if (mask == 0) {  // one box: straight in
          ref = node.child[first];
          continue;
        }
        // Several: the nearest next, the others onto the stack, farthest deepest
        const int base = sp;
        do {
          int i = std::countr_zero(mask);
          mask &= mask - 1;
          if (tnear[i] < tnear[first]) std::swap(i, first);
          int j = sp++;  // child i among the pushed ones, kept farthest first
          for (; j > base && stack_tnear[j - 1] < tnear[i]; --j)
            stack_ref[j] = stack_ref[j - 1], stack_tnear[j] = stack_tnear[j - 1];
          stack_ref[j] = node.child[i], stack_tnear[j] = tnear[i];
        } while (mask != 0);
        ref = node.child[first];
      }
      leaf(ref);
    pop:
      // The next box on the stack still within the limit (a nearer hit may have been found since)
      do {
        if (sp == 0) return;
        --sp;
      } while (stack_tnear[sp] > limit);
      ref = stack_ref[sp];
    }
  }

  void report(BvhTraversalCounts* counts) const {
    if (counts) counts->nodes += visited, counts->triangles += tested;
  }
};

// One ray's search from `start` (the root, or a node its group's test showed to be the only
// way in).
template <bool kBand>
void traverseNearest(const Bvh& bvh, std::uint32_t start, const glm::vec3& org,
                     const glm::vec3& dir, float tmin, float tmax, HitSides sides,
                     BvhBandLimit limit_of, const void* context,
                     typename NearestSearch<kBand>::Out* out, BvhTraversalCounts* counts,
                     bool known_valid = false) {
  if constexpr (kBand) out->count = 0;
  if (start == BvhNode::kEmpty || !(known_valid || rayIsValid(org, dir)) || !(tmin < tmax)) return;
  NearestSearch<kBand> search(bvh, org, dir, tmin, tmax, sides, limit_of, context, out);
  if (counts) search.entered = counts->entered;
  search.from(start);
  search.report(counts);
}

// A group of rays: where they may enter the tree, found once for them all, then each ray's own
// search from there. The answers are each ray's from the root: a triangle a ray hits lies in a
// box the ray's own test enters, so in one the group's test enters too (groupBoxHits); where
// that is one child of a node, every triangle any of the rays hits lies below it.
template <bool kBand>
void traverseGroup(const Bvh& bvh, const glm::vec3* org, const glm::vec3* dir, int n, float tmin,
                   float tmax, HitSides sides, BvhBandLimit limit_of, const void* context,
                   typename NearestSearch<kBand>::Out* out, BvhTraversalCounts* counts) {
  std::uint32_t start = bvh.root;
  BoxRayGroup group;
  bool grouped = false;  // (then every ray is valid)
  // (a teaching view records every box each ray enters from the root: no shortcut there)
  if (start != BvhNode::kEmpty && tmin < tmax && !(counts && counts->entered) &&
      boxRayGroupOfInline(org, dir, n, &group)) {
    grouped = true;
    while (!(start & BvhNode::kLeaf)) {
      const BvhNode& node = bvh.nodes[start];
      const unsigned mask = groupBoxHitsInline(node, group, tmin, tmax);
      if (counts) ++counts->group_nodes;
      if (mask == 0) {  // every ray passes beside the node's boxes: nothing is hit
        start = BvhNode::kEmpty;
        break;
      }
      if (mask & (mask - 1)) break;  // several ways in: each ray chooses from here
      start = node.child[std::countr_zero(mask)];
    }
  }
  for (int i = 0; i < n; ++i) {
    if constexpr (kBand)
      out[i].count = 0;
    else
      out[i] = BvhHit{};
  }
  if (start == BvhNode::kEmpty) return;  // (the whole group passes beside the scene, often)
  for (int i = 0; i < n; ++i)
    traverseNearest<kBand>(bvh, start, org[i], dir[i], tmin, tmax, sides, limit_of, context,
                           &out[i], counts, grouped);
}

}  // namespace

BvhHit intersectNearest(const Bvh& bvh, const glm::vec3& org, const glm::vec3& dir, float tmin,
                        float tmax, HitSides sides, BvhTraversalCounts* counts) {
  BvhHit nearest;
  traverseNearest<false>(bvh, bvh.root, org, dir, tmin, tmax, sides, nullptr, nullptr, &nearest,
                         counts);
  return nearest;
}

void intersectNearestBand(const Bvh& bvh, const glm::vec3& org, const glm::vec3& dir, float tmin,
                          float tmax, HitSides sides, BvhBandLimit limit, const void* context,
                          BvhCandidates* out, BvhTraversalCounts* counts) {
  traverseNearest<true>(bvh, bvh.root, org, dir, tmin, tmax, sides, limit, context, out, counts);
}

void intersectNearestGroup(const Bvh& bvh, const glm::vec3* org, const glm::vec3* dir, int n,
                           float tmin, float tmax, HitSides sides, BvhHit* out,
                           BvhTraversalCounts* counts) {
  traverseGroup<false>(bvh, org, dir, n, tmin, tmax, sides, nullptr, nullptr, out, counts);
}

void intersectNearestBandGroup(const Bvh& bvh, const glm::vec3* org, const glm::vec3* dir, int n,
                               float tmin, float tmax, HitSides sides, BvhBandLimit limit,
                               const void* context, BvhCandidates* out,
                               BvhTraversalCounts* counts) {
  traverseGroup<true>(bvh, org, dir, n, tmin, tmax, sides, limit, context, out, counts);
}

bool intersectAny(const Bvh& bvh, const glm::vec3& org, const glm::vec3& dir, float tmin,
                  float tmax) {
  if (bvh.root == BvhNode::kEmpty || !rayIsValid(org, dir) || !(tmin < tmax)) return false;
  const ShearedRay sheared = shearRay(org, dir);
  const NodeTestRay box_ray(org, dir);
  StackEntry stack[kStackSize];
  int sp = 0;
  stack[sp++] = {bvh.root, tmin};
  while (sp > 0) {
    const StackEntry e = stack[--sp];
    if (e.ref & BvhNode::kLeaf) {
      const BvhTriangles4& leaf = bvh.leaves[e.ref & ~BvhNode::kLeaf];
      for (int lane = 0; lane < 4 && leaf.triangle[lane] != kBvhNoTriangle; ++lane) {
        TriangleHit h;
        const glm::vec3 a(leaf.a[0][lane], leaf.a[1][lane], leaf.a[2][lane]);
        const glm::vec3 b(leaf.b[0][lane], leaf.b[1][lane], leaf.b[2][lane]);
        const glm::vec3 c(leaf.c[0][lane], leaf.c[1][lane], leaf.c[2][lane]);
        if (intersectTriangle(sheared, a, b, c, tmin, tmax, HitSides::kBoth, &h)) return true;
      }
      continue;
    }
    const BvhNode& node = bvh.nodes[e.ref];
    float tnear[kBvhWidth];
    const unsigned mask = box_ray.test(node, tmin, tmax, tnear);
    for (int i = 0; i < kBvhWidth; ++i)
      if (mask & (1u << i)) stack[sp++] = {node.child[i], tnear[i]};
  }
  return false;
}

}  // namespace hsr::detail
