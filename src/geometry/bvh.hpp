#pragma once
// A bounding volume hierarchy over triangles, for casting rays (the ray caster and
// hsr::RayScene). Built top down with the surface-area heuristic over binned centroids
// (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies"), then collapsed
// to eight children per node so that one ray tests eight boxes at each step (Dammertz, Hanika &
// Keller 2008; Embree's BVH8), choosing which binary nodes become eight-wide ones by the least
// summed area (Ylitie, Karras & Laine 2017's optimal collapse). Leaves hold up to four
// triangles side by side.
//
// Guarantees: every triangle with finite vertices is in exactly one leaf; a ray that hits a
// triangle reaches its leaf (the box test is conservative: its far distance is widened by
// 2 gamma(3), Ize 2013, "Robust BVH ray traversal"); the nearest hit is chosen with ties to the
// lowest triangle number, so the answer does not depend on the traversal order, the SIMD or
// scalar node test, or the thread count.
//
// Cost: build O(n log n), about 100 B per triangle (nodes and leaves on huge pages where the
// system gives them); a ray visits O(log n) nodes on typical scenes, and a group of neighbouring
// rays shares the box tests of the levels where they run side by side. Tests:
// tests/geometry/bvh_test.cpp, tests/agreement/embree_test.cpp.

#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "core/large_pages.hpp"
#include "geometry/ray_triangle.hpp"

namespace hsr::detail {

inline constexpr std::uint32_t kBvhNoTriangle = 0xFFFFFFFFu;

// Children per node: with eight, a ray takes a third of a binary tree's steps from the root to
// a leaf (Embree's BVH8); a step tests the eight boxes side by side, four at a time with SSE.
inline constexpr int kBvhWidth = 8;

// kBvhWidth boxes side by side (structure of arrays, one SSE register per four) and what is in
// them.
struct alignas(64) BvhNode {
  float lo[3][kBvhWidth], hi[3][kBvhWidth];  // [axis][child]; an empty child's box is inside out
  std::uint32_t child[kBvhWidth];  // an inner node's index; kLeaf | a leaf's block; or kEmpty
  std::uint32_t pad[8];

  static constexpr std::uint32_t kLeaf = 0x80000000u;
  static constexpr std::uint32_t kEmpty = 0xFFFFFFFFu;
};
static_assert(sizeof(BvhNode) == 256, "four cache lines a node");

// Up to four triangles side by side, for a leaf.
struct alignas(16) BvhTriangles4 {
  float a[3][4], b[3][4], c[3][4];  // [axis][lane]
  std::uint32_t triangle[4];        // the caller's triangle number, kBvhNoTriangle if unused
};

// How a binary subtree is best spread over up to kBvhWidth slots of the eight-wide node above
// it: the optimal collapse of Ylitie, Karras & Laine 2017 ("Efficient incoherent ray traversal
// on GPUs through compressed wide BVHs", section 4), for leaves the binary tree has already
// made. A subtree given i slots either stands whole in one (a leaf, or an eight-wide node of
// its own, whose cost is its area plus its children's best spread over eight slots) or gives
// its left part k slots and its right part the rest. Leaves cost the same however the tree is
// collapsed, so the cost is the SAH's node term alone: the summed area of the eight-wide nodes.
// Greedy collapsing left a third of the nodes holding just two leaves, each a step of its own.
struct CollapsePlan {
  float cost[kBvhWidth];          // cost[i - 1]: the best with at most i slots
  std::uint8_t left[kBvhWidth];   // its slots for the left part; 0: the subtree whole in one slot
  std::uint8_t right[kBvhWidth];  // and for the right part
  std::uint8_t node_left, node_right;  // an eight-wide node of this subtree: its children's spread
  // (no initialisers: the plans are made in place, without a zero fill of the whole array)
};

// The plan of a subtree from its children's plans (a leaf: both null, area unused). Open to
// the tests, which check it against every collapse of small random trees.
void planCollapse(const CollapsePlan* left, const CollapsePlan* right, float area,
                  CollapsePlan* out);

struct BvhStats {
  std::uint64_t triangles = 0;  // in the tree (non-finite ones are left out)
  std::uint64_t nodes = 0, leaves = 0, depth = 0;
  std::uint64_t bytes = 0;
  double build_ms = 0;
  double sah_cost = 0;  // the tree's SAH cost, traversal step 1, triangle test 1 (lower is better)
};

struct Bvh {
  // (on huge pages where the system gives them: a ray's walk reads a few lines of many pages)
  // nodes[0] is the root (an empty tree has no nodes)
  std::vector<BvhNode, LargePageAllocator<BvhNode>> nodes;
  std::vector<BvhTriangles4, LargePageAllocator<BvhTriangles4>> leaves;
  glm::vec3 lo{0.0f}, hi{0.0f};          // bounds of everything
  std::uint32_t root = BvhNode::kEmpty;  // nodes[0], or a leaf when there are at most 4
  BvhStats stats;
};

// Builds over triangles (a[i], b[i], c[i]); triangle i is reported as i. Uses the calling
// task arena's threads (oneTBB); the tree is the same at any thread count.
Bvh buildBvh(std::span<const glm::vec3> a, std::span<const glm::vec3> b,
             std::span<const glm::vec3> c);

struct BvhHit {
  float t = std::numeric_limits<float>::infinity();
  float u = 0, v = 0;
  std::uint32_t triangle = kBvhNoTriangle;
  bool counter_clockwise = false;
  std::uint8_t lane = 0;   // where the triangle sits in the tree: bvh.leaves[leaf], this lane
  std::uint32_t leaf = 0;  // (its vertices there are still in the cache when the hit is reported)
};

// The vertices of a hit's triangle, as the tree holds them (the caller's a, b, c exactly).
inline void bvhTriangleOf(const Bvh& bvh, const BvhHit& h, glm::vec3* a, glm::vec3* b,
                          glm::vec3* c) {
  const BvhTriangles4& l = bvh.leaves[h.leaf];
  *a = {l.a[0][h.lane], l.a[1][h.lane], l.a[2][h.lane]};
  *b = {l.b[0][h.lane], l.b[1][h.lane], l.b[2][h.lane]};
  *c = {l.c[0][h.lane], l.c[1][h.lane], l.c[2][h.lane]};
}

struct BvhTraversalCounts {
  std::uint64_t nodes = 0;        // inner nodes visited
  std::uint64_t triangles = 0;    // ray/triangle tests
  std::uint64_t group_nodes = 0;  // inner nodes a group of rays was tested against together
  // When set (a teaching view), every box the ray enters, in the order entered (lo, hi)
  std::vector<std::pair<glm::vec3, glm::vec3>>* entered = nullptr;
};

// The nearest hit with tmin < t < tmax on the allowed sides; of hits at the same t, the lowest
// triangle number. A ray with a non-finite origin or direction, or a zero direction, hits
// nothing. `counts` may be null.
BvhHit intersectNearest(const Bvh& bvh, const glm::vec3& org, const glm::vec3& dir, float tmin,
                        float tmax, HitSides sides, BvhTraversalCounts* counts = nullptr);
// The nearest hit and the hits just behind it: every hit with t <= limit(context, nearest t),
// nearest first (of equal t, the lowest triangle first); at most kBvhCandidates, the farthest
// dropped beyond that. For a caller that settles near-ties by a rule of its own (the ray caster
// gives them to the z-buffer's float depth). `limit(c, t)` must be >= t and grow with t.
inline constexpr int kBvhCandidates = 8;
struct BvhCandidates {
  int count = 0;
  BvhHit hit[kBvhCandidates];
};
using BvhBandLimit = float (*)(const void* context, float nearest_t);
void intersectNearestBand(const Bvh& bvh, const glm::vec3& org, const glm::vec3& dir, float tmin,
                          float tmax, HitSides sides, BvhBandLimit limit, const void* context,
                          BvhCandidates* out, BvhTraversalCounts* counts = nullptr);

// Rays cast together (a camera's neighbouring pixels): the same answers as intersectNearest
// and intersectNearestBand ray by ray, bit for bit, found with less work where the rays run
// side by side. The group's rays are bounded together (their origins and reciprocal
// directions); a box no ray of the group can enter is known from one test for them all, so a
// group that passes beside the scene costs one node test, and where the group enters a
// single child of a node its rays start there rather than at the root. Rays whose directions
// differ in sign along an axis, or that are not valid, are cast one by one. `counts` adds the
// nodes each ray visits and the group's tests.
// the ray caster's groups (4x4 pixels); RayScene batches take 32; any n works
inline constexpr int kBvhGroupSize = 16;
void intersectNearestGroup(const Bvh& bvh, const glm::vec3* org, const glm::vec3* dir, int n,
                           float tmin, float tmax, HitSides sides, BvhHit* out,
                           BvhTraversalCounts* counts = nullptr);
void intersectNearestBandGroup(const Bvh& bvh, const glm::vec3* org, const glm::vec3* dir, int n,
                               float tmin, float tmax, HitSides sides, BvhBandLimit limit,
                               const void* context, BvhCandidates* out,
                               BvhTraversalCounts* counts = nullptr);

// Whether anything is hit with tmin < t < tmax (either side).
bool intersectAny(const Bvh& bvh, const glm::vec3& org, const glm::vec3& dir, float tmin,
                  float tmax);

// Whether the ray is one the queries answer (finite origin, finite non-zero direction).
bool rayIsValid(const glm::vec3& org, const glm::vec3& dir);

// The box tests of a node for one ray, as a bit per child hit and each child's entry
// distance: the SSE sibling and the scalar one (the same bits; which runs is chosen at build
// time, HSR_NO_SIMD picks the scalar). Open to the tests, which pin the two together.
struct BoxRay {
  float org[3], inv[3];  // inv: 1 / direction (an infinity where a component is 0)
  int near_is_hi[3];     // per axis: the near face is `hi` (the direction is negative)
};
BoxRay boxRayOf(const glm::vec3& org, const glm::vec3& dir);
unsigned boxHitsScalar(const BvhNode& node, const BoxRay& r, float tmin, float tmax,
                       float tnear[kBvhWidth]);
unsigned boxHitsSse(const BvhNode& node, const BoxRay& r, float tmin, float tmax,
                    float tnear[kBvhWidth]);
bool boxHitsSseAvailable();

// A group of rays bounded together for the box test: per axis the range of their origins and
// of their reciprocal directions (all of one sign). Open to the tests, which check that a box
// the group test rules out is one every ray's own test (boxHitsScalar) rules out.
struct BoxRayGroup {
  float org_lo[3], org_hi[3], inv_lo[3], inv_hi[3];
  int near_is_hi[3];
};
// False where the rays cannot be bounded so (a sign differs, an inverse is not finite, a ray is
// not valid, or n < 1).
bool boxRayGroupOf(const glm::vec3* org, const glm::vec3* dir, int n, BoxRayGroup* group);
// A bit per child that some ray of the group may enter (a superset of every ray's bits).
unsigned groupBoxHits(const BvhNode& node, const BoxRayGroup& group, float tmin, float tmax);

// A leaf's triangles (the lanes in `used`) for one ray, up to their edge functions: the
// watertight test's first steps, computed as it computes them (the SSE build: four lanes at
// once; the scalar build: lane by lane), and the lanes it may still hit (left out only where
// the test rejects a triangle for its edge functions' signs). leafLaneHit finishes the test for
// one lane from there: the same answer as intersectTriangle, bit for bit. Open to the tests,
// which pin the two to it.
struct LeafScreen {
  alignas(16) float U[4], V[4], W[4];     // the edge functions
  alignas(16) float az[4], bz[4], cz[4];  // the vertices' sheared, scaled heights
  unsigned candidates = 0;
};
void screenLeaf(const BvhTriangles4& leaf, const ShearedRay& r, unsigned used, LeafScreen* out);
bool leafLaneHit(const BvhTriangles4& leaf, const LeafScreen& screen, int lane, const ShearedRay& r,
                 float tmin, float tmax, HitSides sides, TriangleHit* hit);

}  // namespace hsr::detail
