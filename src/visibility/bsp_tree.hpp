#pragma once
// A 3D BSP tree of a scene's polygons (Fuchs, Kedem & Naylor 1980; the notes' "BSP trees"),
// built once in world space and traversed for any eye. bsp_tree.cpp builds it; bsp.cpp paints
// from it.
//
// Every node holds a splitting plane (the plane of one of its polygons), the polygons lying in
// that plane, and two subtrees: the polygons wholly in front of the plane and those wholly
// behind. A polygon crossing the plane is split in two; its pieces keep their parent's id and
// remember every plane that cut them and on which side they lie, so that a renderer can give
// each piece exactly its share of the parent's pixels.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "hsr/bsp.hpp"
#include "hsr/scene.hpp"

namespace hsr::detail {

// How a node's splitter is chosen among the polygons that reach it.
enum class SplitterChoice {
  kFirst,     // the first polygon of the list (the notes' "pick any polygon")
  kRandom,    // a polygon drawn at random (seeded: the same tree for the same seed)
  kFewest,    // the one that splits fewest others, among up to kFewestCandidates of the list
  kBalanced,  // best of `candidates` sampled by 8 x splits + |front - behind|
  kBestOfK,   // best of `candidates` sampled by splits alone
};
bool parseSplitterChoice(std::string_view s, SplitterChoice* out);
std::string_view toString(SplitterChoice c);

// A polygon of the tree: the parent's vertices (or a piece of them) and the cuts made on it.
struct BspPolygon {
  std::vector<glm::dvec3> vertices;
  PolygonId id = kNoPolygon;
  std::uint32_t piece = 0;  // which triangle of a non-planar polygon (the pipeline's order)
  std::uint32_t first_cut = 0, cut_count = 0;  // its cuts in BspTree::cuts
};

// One cut: the node whose plane cut the polygon, and the side the piece lies on.
struct BspCut {
  std::uint32_t node = 0;
  bool front = false;
};

struct BspNode {
  glm::dvec4 plane{0.0};  // unit normal (x, y, z) and offset w: n . p + w = 0
  std::uint32_t first_polygon = 0, polygon_count = 0;  // its coplanar polygons in BspTree::polygons
  std::int32_t front = -1, back = -1;                  // children (-1: empty)
  glm::dvec3 lo{0.0}, hi{0.0};                         // bounds of every polygon in the subtree
};

struct BspTree {
  std::vector<BspNode> nodes;        // nodes[0] is the root (when there is one)
  std::vector<BspPolygon> polygons;  // every polygon and piece, node by node
  std::vector<BspCut> cuts;
  double epsilon = 0;  // plane distance within which a vertex is on a plane
  BspStats stats;
};

// Builds the tree of `scene`'s polygons. The epsilon is 1e-6 of the scene's bounding-box
// diagonal: a vertex nearer a plane than that is on it. A non-planar polygon (the pipeline's
// test) is entered as its triangles, as the pipeline draws it. `progress(done, total)` is
// called now and then when given. Throws hsr::Error on options it cannot take.
// What became of one node's list, for `hsr explain bsp` (`report`, called once per node as it
// is made, front subtrees before back ones).
struct BspNodeReport {
  std::uint32_t node = 0;
  PolygonId splitter = kNoPolygon;  // the polygon whose plane splits
  const std::vector<glm::dvec3>& splitter_vertices;
  std::size_t list = 0, front = 0, behind = 0;        // the list, and what went to each side
  const std::vector<std::vector<glm::dvec3>>& split;  // the polygons split in two
  std::size_t on = 0;                                 // kept at the node (the splitter too)
  std::uint32_t depth = 0;
};
BspTree buildBspTree(
    const Scene& scene, const BspOptions& options,
    const std::function<void(std::uint64_t done, std::uint64_t total)>& progress = {},
    const std::function<void(const BspNodeReport&)>& report = {});

// Fills in the tree's node bounds and the statistics a loaded tree does not store (every one
// but build_ms).
void finishBspTree(BspTree& tree);

// Which side of a node's plane the eye lies on: > 0 in front, < 0 behind, 0 exactly on it.
// No epsilon here: an eye nearer a plane than the tree's epsilon still sees one side of the
// polygons in it (an epsilon as large as a millionth of a scene with one huge polygon could
// hold the eye), and only an eye exactly in the plane sees them edge-on.
int eyeSide(const BspNode& node, const glm::dvec3& eye);

}  // namespace hsr::detail
