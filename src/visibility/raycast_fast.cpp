// Ray casting reorganised for speed: the same answers as raycast.cpp (the notes' loop, one ray
// and one triangle at a time), bit for bit, with every ray's triangles found through a bounding
// volume hierarchy and the rays cast in groups on all cores.
//
// The rays: the pixel centre carried back through the pipeline's own device-from-world matrix,
// to the far plane, as in raycast.cpp. The hits: a bounding volume hierarchy (geometry/bvh.hpp:
// binned SAH, eight boxes a node, the same watertight ray/triangle test of Woop, Benthin & Wald
// 2013, whose leaves hold the triangles' vertices exactly), built once per scene and kept while
// the scene is unchanged, the same one hsr::RayScene answers queries with. A ray keeps what the
// textbook loop keeps: the nearest hit and the hits within the band of ties behind it, nearest
// first, of equal t the lower triangle; a box is entered only while it may still hold one. The
// pixels are cast in 16x16 tiles, each in groups of 4x4 neighbours that share a box test wherever
// all of them pass beside a box (each ray's answer is still its own). The pixel is settled from
// its hits by the code the textbook loop uses (raycast_hits.hpp).
//
// Guarantee: bit-identical to raycast-textbook (tests/cross/textbook_test.cpp), and so to the
// z-buffer wherever raycast.cpp says. `hsr explain raycast` walks raycast.cpp.
// Cost: build O(n log n) once; per frame O(pixels x log n). Memory: the hierarchy, about
// 100 B per triangle, and no depth buffer of its own. Tests: tests/visibility/raycast_test.cpp,
// tests/geometry/bvh_test.cpp, tests/agreement/embree_test.cpp.

#include <atomic>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/check.hpp"
#include "core/parallel.hpp"
#include "core/scene_digest.hpp"
#include "core/stopwatch.hpp"
#include "raster/depth.hpp"
#include "raster/fragment.hpp"
#include "geometry/ray_scene_data.hpp"
#include "visibility/raycast_hits.hpp"

namespace hsr::detail {
namespace {

// What the ray caster keeps between frames: the hierarchy of the scene it was built for.
struct Scratch {
  std::shared_ptr<const RayScene> rays;
  const Scene* scene = nullptr;
  std::uint64_t fingerprint = 0;
  std::vector<std::uint8_t> see_through;  // per material, when it was built
  PolygonLooks looks;                     // refilled each frame from the pipeline's triangles
};
constexpr int kTile = 16;  // pixels are cast in 16x16 tiles: neighbouring rays visit the same nodes
constexpr int kGroup = 4;  // and in groups of 4x4 (kBvhGroupSize) within a tile
static_assert(kGroup * kGroup == kBvhGroupSize && kTile % kGroup == 0);

struct TileCounts {
  std::uint64_t rays = 0, hits = 0, nodes = 0, triangles = 0, tie_sets = 0;
};

}  // namespace

void drawRaycast(const AlgorithmInput& in, Frame& frame) {
  detail::Stopwatch t0;
  std::unique_ptr<Scratch> own;
  Scratch& s = algorithmScratch(in, own);
  // The hierarchy of the opaque polygons (see-through ones are blended afterwards): built once,
  // kept while the scene and which materials are see-through stay the same
  const std::uint64_t fingerprint = sceneFingerprint(in.scene);
  std::vector<std::uint8_t> see_through;
  for (const Material& m : in.scene.materials) see_through.push_back(materialSeeThrough(m));
  bool built = false;
  if (!s.rays || s.scene != &in.scene || s.fingerprint != fingerprint ||
      s.see_through != see_through) {
    s.rays = std::make_shared<const RayScene>(in.scene, /*opaque_only=*/true);
    s.scene = &in.scene;
    s.fingerprint = fingerprint;
    s.see_through = std::move(see_through);
    built = true;
    frame.stats.addStage("raycast build", s.rays->stats().build_ms);
  }
  const RaySceneData& data = s.rays->data();
  t0.restart();

  // Each polygon's colour and depth plane, as the pipeline made them
  s.looks.build(in.scene, in.prepared.triangles);

  // The rays: pixel centres carried back from device space to the far plane
  const Camera& cam = in.camera;
  const PixelRays pixel_rays(cam);
  const RayDepthBand band{cam.ortho, cam.near, cam.far};
  HitSides sides = HitSides::kBoth;
  const bool can_hit = raySidesFor(in.options, &sides);

  const FrameView fb(frame);
  const int tiles_x = (frame.width + kTile - 1) / kTile,
            tiles_y = (frame.height + kTile - 1) / kTile;
  std::vector<TileCounts> per_tile(static_cast<std::size_t>(tiles_x) * tiles_y);
  std::atomic<std::uint64_t> unshaded{0};
  auto castTile = [&](int tx, int ty) {
    TileCounts& c = per_tile[static_cast<std::size_t>(ty) * tiles_x + tx];
    BvhTraversalCounts work;
    std::uint64_t tile_unshaded = 0;
    const int x_end = std::min(frame.width, (tx + 1) * kTile),
              y_end = std::min(frame.height, (ty + 1) * kTile);
    // The tile's rays in groups of kGroup x kGroup neighbours, cast together (bvh.hpp: each
    // ray's answer is its own, found with one box test for the group where they run side by side)
    for (int gy = ty * kTile; gy < y_end; gy += kGroup) {
      for (int gx = tx * kTile; gx < x_end; gx += kGroup) {
        glm::vec3 org[kGroup * kGroup], dir[kGroup * kGroup];
        int px[kGroup * kGroup], py[kGroup * kGroup];
        int n = 0;
        float tmin = 0, tmax = 0;
        for (int y = gy; y < std::min(y_end, gy + kGroup); ++y) {
          for (int x = gx; x < std::min(x_end, gx + kGroup); ++x) {
            // A ray from the eye through the pixel centre
            const PixelRay ray = pixel_rays.at(x, y);
            org[n] = ray.org, dir[n] = ray.dir, px[n] = x, py[n] = y, tmin = ray.tmin,
            tmax = ray.tmax;
            ++n;
          }
        }
        c.rays += static_cast<std::uint64_t>(n);
        if (!can_hit) continue;
        BvhCandidates found[kGroup * kGroup];
        intersectNearestBandGroup(data.bvh, org, dir, n, tmin, tmax, sides, &rayBandLimit, &band,
                                  found, &work);
        for (int i = 0; i < n; ++i) {
          if (!s.looks.settle(in, fb, px[i], py[i], data.polygon, found[i], &tile_unshaded))
            continue;
          ++c.hits;
          if (found[i].count > 1) ++c.tie_sets;
        }
      }
    }
    c.nodes += work.nodes + work.group_nodes;
    c.triangles += work.triangles;
    unshaded.fetch_add(tile_unshaded, std::memory_order_relaxed);
  };
  tbb::parallel_for(tbb::blocked_range2d<int>(0, tiles_y, 1, 0, tiles_x, 1),
                    [&](const tbb::blocked_range2d<int>& r) {
                      for (int ty = r.rows().begin(); ty < r.rows().end(); ++ty)
                        for (int tx = r.cols().begin(); tx < r.cols().end(); ++tx) castTile(tx, ty);
                    });
  TileCounts c;
  for (const TileCounts& t : per_tile) {
    c.rays += t.rays, c.hits += t.hits, c.nodes += t.nodes, c.triangles += t.triangles;
    c.tie_sets += t.tie_sets;
  }
  frame.stats.addStage("raycast cast", t0.ms());

  // See-through polygons over the finished picture, in submission order, and the outline pen
  FragmentCounts fragments;
  rayFinishFrame(in, fb, fragments);

  frame.stats.fragments_tested += c.hits + fragments.tested;
  frame.stats.fragments_written += c.hits + fragments.written;
  frame.stats.state_bytes += s.rays->stats().bytes + s.looks.bytes();
  frame.stats.addCounter("raycast: built for this frame", built ? 1 : 0);
  frame.stats.addCounter("raycast: triangles in the hierarchy", data.bvh.stats.triangles);
  frame.stats.addCounter("raycast: nodes", data.bvh.stats.nodes);
  frame.stats.addCounter("raycast: leaves", data.bvh.stats.leaves);
  frame.stats.addCounter("raycast: depth", data.bvh.stats.depth);
  frame.stats.addCounter("raycast: rays", c.rays);
  frame.stats.addCounter("raycast: hits", c.hits);
  frame.stats.addCounter("raycast: nodes visited", c.nodes);
  frame.stats.addCounter("raycast: ray/triangle tests", c.triangles);
  frame.stats.addCounter("raycast: pixels with hits in one depth band, settled by float depth",
                         c.tie_sets);
  frame.stats.addCounter("raycast: hits shaded without a screen triangle", unshaded.load());
}

}  // namespace hsr::detail
