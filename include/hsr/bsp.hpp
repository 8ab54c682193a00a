#pragma once
// A BSP tree built once and rendered from any viewpoint (the notes' "BSP trees"; algorithm
// "bsp" builds one per render instead). A Bsp holds the scene it was built from and the tree;
// it is saved to and loaded from a versioned binary file (docs/bsp-format.md).
//
//   const hsr::Bsp bsp = hsr::buildBsp(hsr::loadScene("model.obj"), {.splitter = "fewest"});
//   hsr::saveBsp(bsp, "model.bsp");
//   const hsr::Frame f = hsr::render(hsr::loadBsp("model.bsp"), camera, options);

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "hsr/camera.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace hsr {

namespace detail {
struct BspTree;
}

struct BspStats {
  std::uint64_t input_polygons = 0;  // of the scene with a plane (degenerate ones are left out)
  std::uint64_t polygons = 0;        // in the tree, pieces included
  std::uint64_t splits = 0;          // polygons split in two
  std::uint64_t nodes = 0;
  std::uint64_t depth = 0;  // longest path from the root, in nodes
  double mean_depth = 0;    // mean depth of the node a polygon is stored at
  double balance = 0;       // mean over inner nodes of min(front, back) / max(front, back)
  double build_ms = 0;      // as built (a loaded tree keeps the figure of its build)
  std::uint64_t bytes = 0;  // memory the tree holds (the scene's not counted)
};

class Bsp {
 public:
  const Scene& scene() const { return *scene_; }
  const BspOptions& options() const { return options_; }
  const BspStats& stats() const;
  double epsilon() const;  // a vertex nearer a plane than this is on it
  const detail::BspTree& tree() const { return *tree_; }

 private:
  friend Bsp buildBsp(Scene, const BspOptions&,
                      const std::function<void(std::uint64_t, std::uint64_t)>&);
  friend Bsp readBsp(std::string_view, const std::string&);
  std::shared_ptr<const Scene> scene_;
  std::shared_ptr<const detail::BspTree> tree_;
  BspOptions options_;
};

// Builds the tree of `scene`'s polygons in world space. `progress(done, total)`, when given, is
// called now and then with the polygons placed so far and the current total (splits add to it).
// Throws hsr::Error on an unknown splitter or a candidate count outside 1..4096.
Bsp buildBsp(Scene scene, const BspOptions& options = {},
             const std::function<void(std::uint64_t done, std::uint64_t total)>& progress = {});

// Writes the scene and the tree atomically (hsr/output.hpp); throws hsr::Error.
void saveBsp(const Bsp& bsp, const std::filesystem::path& path);

// Reads a file saveBsp wrote. A file that is not one, of another version, truncated, corrupt
// (its checksum) or inconsistent (an index out of range, a node that is not part of one tree)
// is refused with hsr::Error and one line; memory is never allocated beyond the file's size.
Bsp loadBsp(const std::filesystem::path& path);
// The same from a file's bytes in memory; `name` stands for the file in messages.
Bsp readBsp(std::string_view bytes, const std::string& name);

// Renders the tree's scene for `camera` from the tree, with no rebuild: algorithm "bsp"
// (options.algorithm is ignored; options.bsp too, the tree is built).
Frame render(const Bsp& bsp, const Camera& camera, RenderOptions options = {});
// The same, drawing into `frame` and reusing its buffers' memory (for repeated frames).
void render(const Bsp& bsp, const Camera& camera, RenderOptions options, Frame& frame);

// The order the tree draws its polygons in for `camera`'s eye (their ids; each piece of a split
// polygon in its place): back to front as painted, or front to back when asked (the order a
// renderer that stops at the first hit wants). Subtrees outside the view are left out.
std::vector<PolygonId> bspOrder(const Bsp& bsp, const Camera& camera, bool front_to_back = false);

// The tree in Graphviz's dot language: a node per tree node (its plane, its polygons), edges
// to the front and back subtrees. At most `max_nodes` nodes, then one that says how many more.
std::string bspDot(const Bsp& bsp, std::size_t max_nodes = 100000);

// The tree as indented text, a line per node (depth first, front subtree first): its plane,
// its polygons' ids, and its subtrees' sizes. At most `max_nodes` lines, then how many more.
std::string bspOutline(const Bsp& bsp, std::size_t max_nodes = 60);

}  // namespace hsr
