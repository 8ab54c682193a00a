#pragma once
// The octree method's tree (octree.cpp): built once over the scene in world space, reused for
// every view. Open to the tests.

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "core/scene_digest.hpp"
#include "hsr/scene.hpp"

namespace hsr::detail {

// A polygon held by a leaf: the piece of it inside the leaf's box. `cuts` says which faces of
// the box cut it (bit 2 axis: the low face, bit 2 axis + 1: the high face); the piece is the
// polygon on the box's side of those planes. A polygon lying in a face's plane belongs to the
// cell above that plane alone, uncut.
struct OctreeEntry {
  PolygonId polygon;
  std::uint8_t cuts;
};

struct OctreeNode {
  glm::dvec3 lo, hi;              // the octant
  std::int32_t first_child = -1;  // 8 consecutive children (bit 0: x above the middle, bit 1:
                                  // y, bit 2: z), or -1 for a leaf
  std::uint32_t first_entry = 0, entry_count = 0;  // a leaf's polygons
  std::uint32_t leaves = 1;                        // leaves in the subtree (itself, for a leaf)
  std::uint8_t depth = 0;
};

struct OctreeStats {
  std::uint64_t polygons = 0;  // scene polygons in the tree
  std::uint64_t entries = 0;   // leaf entries: a polygon crossing octants counts once per octant
  std::uint64_t nodes = 0, leaves = 0, depth = 0;
  std::uint64_t bytes = 0;
  double build_ms = 0;
};

inline constexpr std::uint32_t kOctreeLeafPolygons = 16;  // a leaf holds at most this many ...
inline constexpr int kOctreeMaxDepth = 10;                // ... unless this deep

// When a node is cut: while it holds more than `leaf_polygons` and is less than `max_depth`
// deep, where cutting separates its polygons (copies at most half of them into several
// octants); down to `cut_regardless_to` it is cut whether or not it separates them.
struct OctreeLimits {
  std::uint32_t leaf_polygons = kOctreeLeafPolygons;
  int max_depth = kOctreeMaxDepth;
  int cut_regardless_to = 0;
  bool operator==(const OctreeLimits&) const = default;
};
// For teaching (hsr explain): the few polygons of a teaching scene would fit one leaf, so that
// the pictures would show one octant at depth 0. A leaf holds one polygon, and the first two
// levels are cut whatever they copy: the subdivision shows, and the result is the same (the
// method is exact for any tree).
inline constexpr OctreeLimits kOctreeTeachingLimits{1, 5, 2};

struct Octree {
  std::vector<OctreeNode> nodes;  // nodes[0] is the root
  std::vector<OctreeEntry> entries;
  OctreeStats stats;
  std::uint64_t fingerprint = 0;  // of the scene it was built for
  OctreeLimits limits;            // it was built with
};

Octree buildOctree(const Scene& scene, const OctreeLimits& limits = {});

}  // namespace hsr::detail
