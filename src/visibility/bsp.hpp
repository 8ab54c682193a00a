#pragma once
// Traversing a BSP tree for an eye (bsp.cpp): the order `bsp` paints in, for the CLI's
// `hsr bsp` and the tests as well.

#include <cstdint>
#include <functional>

#include "hsr/camera.hpp"
#include "visibility/algorithm.hpp"
#include "visibility/bsp_tree.hpp"

namespace hsr::detail {

struct BspTraversalStats {
  std::uint64_t drawn = 0;    // polygons handed to draw
  std::uint64_t visited = 0;  // nodes whose planes were asked
  std::uint64_t skipped = 0;  // subtrees outside the view frustum, not entered
};

// Calls draw(polygon, node) for every polygon of the tree in painting order for `camera`'s
// eye, with the index of the node that holds it (a node's polygons come one after another):
// back to front (front to back when asked), skipping subtrees outside the view frustum.
void forEachBspPolygon(const BspTree& tree, const Camera& camera, bool front_to_back,
                       const std::function<void(const BspPolygon&, std::uint32_t node)>& draw,
                       BspTraversalStats* stats = nullptr);

// Paints the prepared scene's polygons in the tree's back-to-front order, with no depth test.
void paintFromBspTree(const BspTree& tree, const AlgorithmInput& in, Frame& frame);

}  // namespace hsr::detail
