// The octree method (Meagher 1982, Doctor & Torborg 1981; the notes' "octree" visibility).
//
// Build once, in world space: put the scene in a box, and while a box holds more than a few
// polygons, cut it at its middle into eight octants and give each octant the polygons that
// reach into it (a polygon crossing an octant's face is clipped there: the octant holds the
// piece on its side, with the polygon's id and plane). The tree serves every view.
//
// Draw, for an eye: visit the octants front to back. At a node, the child containing the
// eye's side of all three middle planes comes first, the one on the far side of all three
// last: with the children taken by how many of the planes separate them from the eye, no
// octant can hide one visited before it. So a pixel, once written, is final: it shows the
// nearest surface, and no later octant may write it again. Hence:
//   - each pixel is written at most once;
//   - an octant whose screen footprint (the bounding rectangle of its projected box) is
//     already fully written is skipped with everything under it: what it holds is hidden;
//   - an octant outside the view frustum is skipped too;
//   - within a leaf, its few polygons are resolved exactly: at each pixel not yet written,
//     the nearest of its pieces there (the shared fragment depth; of equal depths the one
//     submitted first, as the z-buffer), then written once.
// A piece is drawn as its polygon's screen triangles (the shared pipeline, edge setup and
// fill rule) restricted to the box's side of each face that cut it: a world plane restricted
// to the polygon's plane is a line of the picture, and the two octants beside a face take the
// two sides of the same line, so they share out the polygon's pixels exactly. Pieces keep the
// polygon's depth plane: depth never drifts. See-through polygons are blended afterwards, as
// the z-buffer blends them.
//
// Cost: build O(polygons x depth); per frame O(octants visited + pixels of the pieces drawn),
// hidden octants costing one footprint test. Memory: the tree, and three numbers per pixel.
//
// Tests: tests/visibility/octree_test.cpp and every suite of the registry its capabilities join.

#include "visibility/octree.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/bit_cast.hpp"
#include "core/check.hpp"
#include "core/frame.hpp"
#include "core/parallel.hpp"
#include "core/stopwatch.hpp"
#include "raster/edge.hpp"
#include "raster/fill_polygons.hpp"
#include "raster/fragment.hpp"
#include "raster/lines.hpp"
#include "raster/triangle.hpp"
#include "visibility/algorithm.hpp"

namespace hsr::detail {

// ---------------------------------------------------------------------------------------------
// Building.

namespace {

struct Item {
  PolygonId polygon;
  std::uint8_t cuts;
};

struct Builder {
  const std::vector<glm::dvec3>& lo;  // each polygon's bounding box
  const std::vector<glm::dvec3>& hi;
  Octree& tree;
  const OctreeLimits& limits;

  // Fills node `n` (its box set) with `items`.
  void build(std::uint32_t n, std::vector<Item> items, int depth) {
    tree.stats.depth = std::max<std::uint64_t>(tree.stats.depth, depth);
    tree.nodes[n].depth = static_cast<std::uint8_t>(depth);
    if (items.size() > limits.leaf_polygons && depth < limits.max_depth) {
      const glm::dvec3 box_lo = tree.nodes[n].lo, box_hi = tree.nodes[n].hi;
      const glm::dvec3 mid = (box_lo + box_hi) * 0.5;
      std::vector<Item> child[8];
      std::size_t handed = 0;
      for (const Item& it : items) {
        // Per axis: below the middle, above it (a polygon in the middle plane counts as above),
        // or across it (then the piece on each side is cut by the middle plane). The planes are
        // axis-aligned and the vertices exact, so the comparisons are exact: no epsilon, which
        // (as 10^-6 of the scene's diagonal) once let a polygon reach 300 units across a plane
        // uncut in a scene 10^8 wide, and be drawn in the wrong octant's turn.
        bool below[3], above[3], across[3];
        for (int a = 0; a < 3; ++a) {
          across[a] = lo[it.polygon][a] < mid[a] && hi[it.polygon][a] > mid[a];
          above[a] = across[a] || lo[it.polygon][a] >= mid[a];
          below[a] = across[a] || !above[a];
        }
        for (int c = 0; c < 8; ++c) {
          std::uint8_t cuts = it.cuts;
          bool in = true;
          for (int a = 0; a < 3 && in; ++a) {
            const bool up = (c >> a) & 1;
            in = up ? above[a] : below[a];
            // The child's face at the middle replaces the parent's face on that side.
            const int face = 2 * a + (up ? 0 : 1);
            cuts =
                static_cast<std::uint8_t>((cuts & ~(1u << face)) | (across[a] ? 1u << face : 0u));
          }
          if (in) child[c].push_back({it.polygon, cuts}), ++handed;
        }
      }
      // Cutting must separate the polygons: when it would copy more than half of them into
      // several octants (octants as small as the polygons, or polygons all crossing one point),
      // the node stays a leaf (unless the limits cut this deep regardless, for teaching).
      if (2 * handed <= 3 * items.size() || depth < limits.cut_regardless_to) {
        const auto first = static_cast<std::int32_t>(tree.nodes.size());
        tree.nodes[n].first_child = first;
        tree.nodes.resize(tree.nodes.size() + 8);
        for (int c = 0; c < 8; ++c) {
          OctreeNode& k = tree.nodes[static_cast<std::size_t>(first + c)];
          for (int a = 0; a < 3; ++a) {
            k.lo[a] = ((c >> a) & 1) ? mid[a] : box_lo[a];
            k.hi[a] = ((c >> a) & 1) ? box_hi[a] : mid[a];
          }
        }
        items.clear();
        items.shrink_to_fit();
        std::uint32_t leaves = 0;
        for (int c = 0; c < 8; ++c) {
          build(static_cast<std::uint32_t>(first + c), std::move(child[c]), depth + 1);
          leaves += tree.nodes[static_cast<std::size_t>(first + c)].leaves;
        }
        tree.nodes[n].leaves = leaves;
        return;
      }
    }
    OctreeNode& leaf = tree.nodes[n];
    leaf.first_entry = static_cast<std::uint32_t>(tree.entries.size());
    leaf.entry_count = static_cast<std::uint32_t>(items.size());
    leaf.leaves = 1;
    for (const Item& it : items) tree.entries.push_back({it.polygon, it.cuts});
    tree.stats.leaves++;
  }
};

}  // namespace

Octree buildOctree(const Scene& scene, const OctreeLimits& limits) {
  const detail::Stopwatch t0;
  Octree tree;
  tree.limits = limits;
  const std::size_t n = scene.polygonCount();
  std::vector<glm::dvec3> lo(n), hi(n);
  std::vector<Item> all;
  all.reserve(n);
  glm::dvec3 box_lo(INFINITY), box_hi(-INFINITY);
  for (PolygonId p = 0; p < n; ++p) {
    glm::dvec3 l(INFINITY), h(-INFINITY);
    bool finite = true;
    for (const std::uint32_t v : scene.polygon(p)) {
      const glm::dvec3 x(scene.position(v));
      finite = finite && std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z);
      l = glm::min(l, x);
      h = glm::max(h, x);
    }
    if (!finite || scene.polygon(p).size() < 3) continue;  // the pipeline drops these too
    lo[p] = l, hi[p] = h;
    box_lo = glm::min(box_lo, l);
    box_hi = glm::max(box_hi, h);
    all.push_back({p, 0});
  }
  tree.stats.polygons = all.size();
  tree.nodes.resize(1);
  if (all.empty()) box_lo = box_hi = glm::dvec3(0.0);
  tree.nodes[0].lo = box_lo;
  tree.nodes[0].hi = box_hi;
  Builder b{lo, hi, tree, limits};
  b.build(0, std::move(all), 0);
  tree.stats.nodes = tree.nodes.size();
  tree.stats.entries = tree.entries.size();
  tree.stats.bytes =
      tree.nodes.capacity() * sizeof(OctreeNode) + tree.entries.capacity() * sizeof(OctreeEntry);
  tree.fingerprint = sceneFingerprint(scene);
  tree.stats.build_ms = t0.ms();
  return tree;
}

// ---------------------------------------------------------------------------------------------
// Drawing.

namespace {

constexpr std::string_view kStepBuild = "build";
constexpr std::string_view kStepOctant = "octant";
constexpr std::string_view kStepDone = "done";

constexpr int kTile = 8;  // written pixels are counted per 8x8 tile, to test footprints fast
constexpr int kBandRows = 8 * kTile;  // rows per band (a whole number of tiles)

// A pixel rectangle in 8 bytes (the picture's sides are at most 2^14).
struct SmallBox {
  std::int16_t x0, y0, x1, y1;
};

// The memory kept between frames: the tree (rebuilt when the scene changes) and the per-pixel
// scratch of a leaf's exact resolution.
struct Scratch {
  std::shared_ptr<const Octree> tree;
  const Scene* scene = nullptr;
  std::vector<float> leaf_z;            // the nearest depth so far in the current leaf ...
  std::vector<std::uint32_t> leaf_tri;  // ... its screen triangle ...
  std::vector<std::uint32_t> stamp;     // ... valid where stamp == the leaf's number
  std::vector<std::uint32_t> tile_written;
  std::vector<std::uint32_t> tri_start;  // each polygon's first screen triangle
  std::vector<SmallBox> polygon_box;     // the rectangle around each polygon's opaque ones
  std::size_t bytes() const {
    return (leaf_z.capacity() + leaf_tri.capacity() + stamp.capacity() + tile_written.capacity() +
            tri_start.capacity()) *
               4 +
           polygon_box.capacity() * sizeof(SmallBox);
  }
};

struct Counts {
  std::uint64_t visited = 0, outside = 0, covered = 0, covered_leaves = 0;
  std::uint64_t leaves_drawn = 0, leaves_hidden = 0, pieces = 0, triangles_covered = 0;
  std::uint64_t pixels_written = 0, rewritten = 0;
  FragmentCounts fragments;
  void add(const Counts& o) {
    visited += o.visited, outside += o.outside, covered += o.covered,
        covered_leaves += o.covered_leaves;
    leaves_drawn += o.leaves_drawn, leaves_hidden += o.leaves_hidden, pieces += o.pieces;
    triangles_covered += o.triangles_covered;
    pixels_written += o.pixels_written, rewritten += o.rewritten;
    fragments += o.fragments;
  }
};

// The per-frame preparation shared by the bands: the scratch sized and cleared, each
// polygon's screen triangles found (the pipeline gives them in id order).
void prepareScratch(const AlgorithmInput& in, const Frame& frame, Scratch& s) {
  const std::size_t pixels = static_cast<std::size_t>(frame.width) * frame.height;
  s.leaf_z.resize(pixels);
  s.leaf_tri.resize(pixels);
  s.stamp.assign(pixels, 0);
  const int tiles_x = (frame.width + kTile - 1) / kTile;
  s.tile_written.assign(static_cast<std::size_t>(tiles_x) * ((frame.height + kTile - 1) / kTile),
                        0);
  s.tri_start.assign(in.scene.polygonCount() + 1, 0);
  const auto w = static_cast<std::int16_t>(frame.width),
             h = static_cast<std::int16_t>(frame.height);
  s.polygon_box.assign(in.scene.polygonCount(), SmallBox{w, h, -1, -1});
  for (const ScreenTriangle& t : in.prepared.triangles) {
    s.tri_start[t.id + 1]++;
    if (t.transparent()) continue;
    SmallBox& b = s.polygon_box[t.id];
    b = {std::min(b.x0, t.x0), std::min(b.y0, t.y0), std::max(b.x1, t.x1), std::max(b.y1, t.y1)};
  }
  for (std::size_t k = 1; k < s.tri_start.size(); ++k) s.tri_start[k] += s.tri_start[k - 1];
}

// Draws the rows of one band of the picture: the tree is traversed for each band, with
// footprints cut to the band, so bands own their pixels and run in parallel.
class Painter {
 public:
  Painter(const AlgorithmInput& in, Frame& frame, const Octree& tree, Scratch& s, int row0,
          int row1)
      : in_(in),
        frame_(frame),
        fb_(frame),
        tree_(tree),
        s_(s),
        tris_(in.prepared.triangles),
        band_{0, row0, frame.width - 1, row1} {
    tiles_x_ = (frame.width + kTile - 1) / kTile;
    device_from_world_ = deviceFromWorld(in.camera);
    clip_from_world_ = glm::dmat4(in.camera.projection()) * glm::dmat4(in.camera.view());
    device_plane_from_world_plane_ = glm::transpose(glm::inverse(device_from_world_));
    eye_ = glm::dvec3(in.camera.eye);
    toward_eye_ = glm::normalize(glm::dvec3(in.camera.eye) - glm::dvec3(in.camera.target));
  }

  Counts counts;

  // The octants front to back, from the root.
  void run() {
    if (tree_.nodes.empty()) return;
    std::vector<std::uint32_t> stack{0};
    while (!stack.empty()) {
      const std::uint32_t n = stack.back();
      stack.pop_back();
      const OctreeNode& node = tree_.nodes[n];
      if (node.first_child < 0 && node.entry_count == 0) continue;  // an empty octant
      if (boxOutsideFrustum(clip_from_world_, node.lo, node.hi)) {
        counts.outside++;
        continue;
      }
      const PixelBox footprint = cut(footprintOf(node), band_);
      if (footprint.empty()) {  // between pixel centres, off the picture or off the band
        counts.outside++;
        continue;
      }
      if (fullyWritten(footprint)) {  // everything in it is hidden
        counts.covered++;
        counts.covered_leaves += node.leaves;
        trace(n, footprint,
              "skipped with everything under it: its footprint is already fully written");
        continue;
      }
      counts.visited++;
      if (node.first_child >= 0) {
        // Children front to back: the eye's octant first, then those one plane away, two, three.
        static constexpr int kByPlanesAway[8] = {0, 1, 2, 4, 3, 5, 6, 7};
        const int nearest = eyeOctant(node);
        for (int k = 7; k >= 0; --k)
          stack.push_back(
              static_cast<std::uint32_t>(node.first_child + (nearest ^ kByPlanesAway[k])));
        continue;
      }
      // A leaf's own footprint is tighter: the rectangle around its pieces' triangles.
      const PixelBox content = contentFootprint(node, footprint);
      if (content.empty() || fullyWritten(content)) {
        counts.covered++;
        counts.covered_leaves++;
        trace(n, content, "skipped: the rectangle around its pieces is already fully written");
        continue;
      }
      const std::uint64_t written = drawLeaf(node, content);
      (written ? counts.leaves_drawn : counts.leaves_hidden)++;
      trace(n, footprint,
            written ? "drawn: " + std::to_string(written) + " pixels written, each once and final"
                    : std::string("drawn, but every pixel of it was already written: hidden"));
    }
  }

 private:
  // std::nextafter(d, 0.0f), inline: one step of the float's magnitude toward zero.
  static float stepTowardZero(float d) {
    if (d == 0.0f || d != d) return d == 0.0f ? 0.0f : d;
    return bitCast<float>(bitCast<std::uint32_t>(d) - 1u);
  }

  static PixelBox cut(const PixelBox& a, const PixelBox& b) {
    return {std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
  }

  // The child of `node` on the eye's side of each of its middle planes.
  int eyeOctant(const OctreeNode& node) const {
    // child 0's top
    const glm::dvec3 mid = tree_.nodes[static_cast<std::size_t>(node.first_child)].hi;
    int c = 0;
    for (int a = 0; a < 3; ++a) {
      const bool up = in_.camera.ortho ? toward_eye_[a] > 0 : eye_[a] >= mid[a];
      c |= up ? 1 << a : 0;
    }
    return c;
  }

  // The pixel centres that the box's projection can reach: the rectangle around its corners
  // (the whole picture when a corner lies behind the eye).
  PixelBox footprintOf(const OctreeNode& node) const {
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int i = 0; i < 8; ++i) {
      const glm::dvec4 h = device_from_world_ * glm::dvec4((i & 1) ? node.hi.x : node.lo.x,
                                                           (i & 2) ? node.hi.y : node.lo.y,
                                                           (i & 4) ? node.hi.z : node.lo.z, 1.0);
      if (!(h.w > 1e-9)) return {0, 0, frame_.width - 1, frame_.height - 1};
      const double x = h.x / h.w, y = h.y / h.w;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
    // One pixel more each way: the pipeline snaps vertices to 1/256 pixel.
    const double kLimit = 1e9;
    return {static_cast<int>(std::max(0.0, std::ceil(std::max(x0, -kLimit)) - 1)),
            static_cast<int>(std::max(0.0, std::ceil(std::max(y0, -kLimit)) - 1)),
            static_cast<int>(std::min(frame_.width - 1.0, std::floor(std::min(x1, kLimit)) + 1)),
            static_cast<int>(std::min(frame_.height - 1.0, std::floor(std::min(y1, kLimit)) + 1))};
  }

  PixelBox contentFootprint(const OctreeNode& leaf, const PixelBox& footprint) const {
    PixelBox b{frame_.width, frame_.height, -1, -1};
    for (std::uint32_t k = 0; k < leaf.entry_count; ++k) {
      const SmallBox& p = s_.polygon_box[tree_.entries[leaf.first_entry + k].polygon];
      b = {std::min<int>(b.x0, p.x0), std::min<int>(b.y0, p.y0), std::max<int>(b.x1, p.x1),
           std::max<int>(b.y1, p.y1)};
    }
    return {std::max(b.x0, footprint.x0), std::max(b.y0, footprint.y0),
            std::min(b.x1, footprint.x1), std::min(b.y1, footprint.y1)};
  }

  bool fullyWritten(const PixelBox& b) const {
    for (int ty = b.y0 / kTile; ty <= b.y1 / kTile; ++ty)
      for (int tx = b.x0 / kTile; tx <= b.x1 / kTile; ++tx) {
        const int px0 = tx * kTile, py0 = ty * kTile;
        const int px1 = std::min(px0 + kTile, frame_.width) - 1,
                  py1 = std::min(py0 + kTile, frame_.height) - 1;
        const std::uint32_t tile_pixels =
            static_cast<std::uint32_t>((px1 - px0 + 1) * (py1 - py0 + 1));
        const std::uint32_t written = s_.tile_written[static_cast<std::size_t>(ty) * tiles_x_ + tx];
        if (written == tile_pixels) continue;
        if (px0 >= b.x0 && px1 <= b.x1 && py0 >= b.y0 && py1 <= b.y1)
          return false;  // whole tile, not full
        for (int y = std::max(py0, b.y0); y <= std::min(py1, b.y1); ++y)
          for (int x = std::max(px0, b.x0); x <= std::min(px1, b.x1); ++x)
            if (fb_.ids[fb_.index(x, y)] == kNoPolygon) return false;
      }
    return true;
  }

  // A leaf's pieces resolved exactly at each pixel not yet written; then each pixel written once.
  std::uint64_t drawLeaf(const OctreeNode& leaf, const PixelBox& footprint) {
    const std::uint32_t stamp = ++leaf_number_;
    touched_.clear();
    // The pieces' triangles lie all over the pipeline's list: ask for them all at once.
    for (std::uint32_t k = 0; k < leaf.entry_count; ++k)
      __builtin_prefetch(&tris_[s_.tri_start[tree_.entries[leaf.first_entry + k].polygon]]);
    for (std::uint32_t k = 0; k < leaf.entry_count; ++k) {
      const OctreeEntry& e = tree_.entries[leaf.first_entry + k];
      const std::uint32_t first = s_.tri_start[e.polygon], last = s_.tri_start[e.polygon + 1];
      if (first == last) continue;  // culled or clipped away by the pipeline
      counts.pieces++;
      for (std::uint32_t i = first; i < last; ++i) {
        const ScreenTriangle& t = tris_[i];
        if (t.transparent()) continue;  // blended afterwards
        const PixelBox box = cut(t.box(), footprint);
        if (box.empty() || fullyWritten(box)) {  // hidden by nearer octants
          counts.triangles_covered++;
          continue;
        }
        cutsOf(leaf, e.cuts, t.depth);
        resolveTriangle(t, i, footprint, stamp);
      }
    }
    // Write each pixel once: the nearest piece, if nearer than the cleared depth.
    std::uint64_t written = 0;
    for (const std::uint32_t k : touched_) {
      const bool again = fb_.ids[k] != kNoPolygon;
      if (again) {
        counts.rewritten++;  // a float tie with a nearer octant, settled as the z-buffer does
      } else if (!(s_.leaf_z[k] < fb_.depth[k])) {
        continue;
      }
      const ScreenTriangle& t = tris_[s_.leaf_tri[k]];
      fb_.depth[k] = s_.leaf_z[k];
      fb_.ids[k] = t.id;
      fb_.rgba[k] = t.rgba;
      fb_.overdraw[k]++;
      const int x = static_cast<int>(k % frame_.width), y = static_cast<int>(k / frame_.width);
      if (again) continue;
      s_.tile_written[static_cast<std::size_t>(y / kTile) * tiles_x_ + x / kTile]++;
      ++written;
    }
    counts.pixels_written += written;
    counts.fragments.written += written;
    return written;
  }

  // The faces that cut this piece, as lines of the picture: each face's world plane carried to
  // device space and restricted to the polygon's plane (its depth plane z(x, y)); the octant's
  // side is where the face's plane is >= 0 (low face: x >= its value) or < 0 (high face), so
  // the two octants beside a face take the two sides of one line.
  void cutsOf(const OctreeNode& leaf, std::uint8_t mask, const DepthPlane& p) {
    cuts_.clear();
    for (int face = 0; face < 6; ++face) {
      if (!((mask >> face) & 1)) continue;
      const int a = face / 2;
      const bool low = face % 2 == 0;
      glm::dvec4 world(0.0);
      world[a] = 1.0;
      world.w = -(low ? leaf.lo[a] : leaf.hi[a]);
      const glm::dvec4 d = device_plane_from_world_plane_ * world;
      cuts_.push_back({d.x + d.z * p.dzdx, d.y + d.z * p.dzdy, d.w + d.z * p.z0, !low});
    }
  }

  void resolveTriangle(const ScreenTriangle& t, std::uint32_t index, const PixelBox& footprint,
                       std::uint32_t stamp) {
    const int y0 = std::max<int>(t.y0, footprint.y0), y1 = std::min<int>(t.y1, footprint.y1);
    const int x0 = std::max<int>(t.x0, footprint.x0), x1 = std::min<int>(t.x1, footprint.x1);
    if (y0 > y1 || x0 > x1) return;
    TriangleSetup s = setupTriangle(t, y0);
    for (int y = y0; y <= y1; ++y, nextRow(s)) {
      int lo = x0, hi = x1;
      if (!spanOfRow(s, &lo, &hi)) continue;
      const double row = depthRowStart(t.depth, y);
      for (int x = lo; x <= hi; ++x) {
        const std::size_t k = fb_.index(x, y);
        const float z = depthInRow(row, t.depth, x);
        // Written by a nearer octant: final. Except where a float cannot tell the two apart:
        // the same float depth, or one a step nearer; there the z-buffer's rule decides (the
        // nearer float; of equal ones the polygon submitted first).
        if (fb_.ids[k] != kNoPolygon && s_.stamp[k] != stamp &&
            !(z == stepTowardZero(fb_.depth[k]) || (z == fb_.depth[k] && index < s_.leaf_tri[k])))
          continue;
        bool inside = true;
        for (const PixelHalfPlane& h : cuts_) inside = inside && h.contains(x, y);
        if (!inside) continue;  // this pixel of the polygon belongs to another octant
        counts.fragments.tested++;
        if (s_.stamp[k] != stamp) {
          s_.stamp[k] = stamp;
          s_.leaf_z[k] = z;
          s_.leaf_tri[k] = index;
          touched_.push_back(static_cast<std::uint32_t>(k));
        } else if (z < s_.leaf_z[k] || (z == s_.leaf_z[k] && index < s_.leaf_tri[k])) {
          s_.leaf_z[k] = z;
          s_.leaf_tri[k] = index;
        }
      }
    }
  }

  void trace(std::uint32_t n, const PixelBox& fp, const std::string& what) {
    if (!in_.trace) return;
    if (trace_count_ == 0)  // the octants that can be pictured: every leaf holding something
      for (const OctreeNode& node : tree_.nodes)
        trace_count_ += node.first_child < 0 && node.entry_count > 0;
    if (!in_.trace->wants(kStepOctant, traced_++, trace_count_)) return;
    const OctreeNode& node = tree_.nodes[n];
    std::vector<TraceOutline> outlines;
    // The box's twelve edges, where all its corners are in front of the eye.
    glm::vec2 c[8];
    bool ok = true;
    for (int i = 0; i < 8; ++i) {
      const glm::dvec4 h = device_from_world_ * glm::dvec4((i & 1) ? node.hi.x : node.lo.x,
                                                           (i & 2) ? node.hi.y : node.lo.y,
                                                           (i & 4) ? node.hi.z : node.lo.z, 1.0);
      ok = ok && h.w > 1e-9;
      c[i] = glm::vec2(static_cast<float>(h.x / h.w), static_cast<float>(h.y / h.w));
    }
    if (ok)
      for (int i = 0; i < 8; ++i)
        for (int a = 0; a < 3; ++a)
          if (!(i & (1 << a))) outlines.push_back({c[i], c[i | (1 << a)]});
    in_.trace->record(
        {kStepOctant,
         std::string(node.first_child >= 0 ? "Octant" : "Leaf octant") + " at depth " +
             std::to_string(node.depth) +
             (node.first_child < 0
                  ? " holding " + std::to_string(node.entry_count) + " polygons or pieces"
                  : std::string()) +
             ", footprint [" + std::to_string(fp.x0) + ".." + std::to_string(fp.x1) + "] x [" +
             std::to_string(fp.y0) + ".." + std::to_string(fp.y1) + "]: " + what +
             ". Octants are visited front to back, so written pixels are final.",
         &frame_, std::move(outlines)});
  }

  const AlgorithmInput& in_;
  Frame& frame_;
  const FrameView fb_;
  const Octree& tree_;
  Scratch& s_;
  const ScreenTriangles& tris_;
  glm::dmat4 device_from_world_, clip_from_world_, device_plane_from_world_plane_;
  glm::dvec3 eye_, toward_eye_;
  int tiles_x_ = 0;
  std::uint32_t leaf_number_ = 0;
  std::uint64_t traced_ = 0, trace_count_ = 0;
  std::vector<PixelHalfPlane> cuts_;
  std::vector<std::uint32_t> touched_;  // the pixels the current leaf resolves
  PixelBox band_;
};

}  // namespace

void drawOctree(const AlgorithmInput& in, Frame& frame) {
  detail::Stopwatch t0;
  std::unique_ptr<Scratch> own;
  Scratch& s = algorithmScratch(in, own);
  // The tree: built once, kept while the scene is the same. Explained, it is cut finer, so that
  // a teaching scene of a few polygons shows its octants (kOctreeTeachingLimits).
  const std::uint64_t fingerprint = sceneFingerprint(in.scene);
  const OctreeLimits limits = in.trace ? kOctreeTeachingLimits : OctreeLimits{};
  bool built = false;
  if (!s.tree || s.scene != &in.scene || s.tree->fingerprint != fingerprint ||
      !(s.tree->limits == limits)) {
    s.tree = std::make_shared<const Octree>(buildOctree(in.scene, limits));
    s.scene = &in.scene;
    built = true;
    frame.stats.addStage("octree build", s.tree->stats.build_ms);
  }
  const Octree& tree = *s.tree;
  if (in.trace && in.trace->wants(kStepBuild, 0, 1))
    in.trace->record(
        {kStepBuild,
         "The octree, built once in world space for every view: " +
             std::to_string(tree.stats.nodes) + " octants, " + std::to_string(tree.stats.leaves) +
             " leaves, depth " + std::to_string(tree.stats.depth) + "; " +
             std::to_string(tree.stats.polygons) + " polygons held as " +
             std::to_string(tree.stats.entries) +
             " pieces (a polygon crossing octants is clipped to each). " +
             "Cut finer than for rendering, to show the octants: a leaf holds at most " +
             std::to_string(limits.leaf_polygons) + " polygon, the first " +
             std::to_string(limits.cut_regardless_to) +
             " levels cut whatever they copy (rendering: " + std::to_string(kOctreeLeafPolygons) +
             " a leaf; the same picture).",
         &frame,
         {}});
  t0.restart();
  // The picture in bands of kBandRows rows, in parallel; the bands are fixed, so the picture
  // and every count are the same at any thread count.
  prepareScratch(in, frame, s);
  const int band_rows = in.trace ? std::max(frame.height, 1) : kBandRows;
  const int bands = (frame.height + band_rows - 1) / band_rows;
  std::vector<Counts> per_band(static_cast<std::size_t>(bands));
  auto drawBand = [&](int b) {
    Painter painter(in, frame, tree, s, b * band_rows,
                    std::min(frame.height, (b + 1) * band_rows) - 1);
    painter.run();
    per_band[static_cast<std::size_t>(b)] = painter.counts;
  };
  if (in.trace) {
    for (int b = 0; b < bands; ++b) drawBand(b);
  } else {
    tbb::parallel_for(0, bands, drawBand);
  }
  Counts c;
  for (const Counts& b : per_band) c.add(b);

  // See-through polygons over the finished picture, in submission order, as the z-buffer.
  const FrameView fb(frame);
  const PixelBox viewport{0, 0, frame.width - 1, frame.height - 1};
  const RasterPath path = rasterPath(DepthFunc::Less);
  for (const ScreenTriangle& t : in.prepared.triangles)
    if (t.transparent()) rasterTriangle<DepthFunc::Less>(t, viewport, fb, true, path, c.fragments);
  for (const ScreenLine& o : in.prepared.outline) drawOutlinePen(o, viewport, fb);

  if (in.trace && in.trace->wants(kStepDone, 0, 1))
    in.trace->record({kStepDone,
                      "Done: " + std::to_string(c.visited) + " octants visited, " +
                          std::to_string(c.covered) + " skipped as hidden (" +
                          std::to_string(c.covered_leaves) + " leaves under them), " +
                          std::to_string(c.outside) + " outside the view; " +
                          std::to_string(c.pixels_written) + " pixels written, each once.",
                      &frame,
                      {}});
  frame.stats.fragments_tested += c.fragments.tested;
  frame.stats.fragments_written += c.fragments.written;
  frame.stats.state_bytes += tree.stats.bytes + s.bytes();
  frame.stats.addCounter("octree: built for this frame", built ? 1 : 0);
  frame.stats.addCounter("octree: octants", tree.stats.nodes);
  frame.stats.addCounter("octree: leaves", tree.stats.leaves);
  frame.stats.addCounter("octree: depth", tree.stats.depth);
  frame.stats.addCounter("octree: pieces in the tree", tree.stats.entries);
  frame.stats.addCounter("octree: octants visited", c.visited);
  frame.stats.addCounter("octree: octants skipped, covered", c.covered);
  frame.stats.addCounter("octree: octants skipped, outside the view", c.outside);
  frame.stats.addCounter("octree: leaves under covered octants", c.covered_leaves);
  frame.stats.addCounter("octree: leaves drawn, visible", c.leaves_drawn);
  frame.stats.addCounter("octree: leaves drawn, hidden", c.leaves_hidden);
  frame.stats.addCounter("octree: pieces drawn", c.pieces);
  frame.stats.addCounter("octree: triangles skipped, covered", c.triangles_covered);
  frame.stats.addCounter("octree: pixels written once", c.pixels_written);
  frame.stats.addCounter("octree: pixels rewritten on a float tie", c.rewritten);
  frame.stats.addStage("octree traverse + draw", t0.ms());
}

}  // namespace hsr::detail
