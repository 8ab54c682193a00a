// Ray casting (Appel 1968; the notes' "ray casting"): the one algorithm of the notes that works
// before the perspective transformation. For each pixel, a ray from the eye through the
// pixel's centre, in world space; of the polygons it meets between the near and far planes,
// the nearest is visible there.
//
// The rays: the pixel centre carried back through the pipeline's own
// device-from-world matrix, to the far plane. Perspective: from the eye, t = near / far at the
// near plane and t = 1 at the far plane, so a hit's eye depth is t * far. Orthographic: from the
// near plane's point to the far plane's, t from 0 to 1, the window depth itself. `--cull` and
// `--front-face` decide which side of a triangle a ray may hit (the notes' N . V test, as seen
// from the eye).
//
// The hits: a bounding volume hierarchy (geometry/bvh.hpp: binned SAH, eight boxes a node, the
// watertight ray/triangle test of Woop, Benthin & Wald 2013), built once per scene and kept
// while the scene is unchanged, the same one hsr::RayScene answers queries with. The pixels are
// cast in 16x16 tiles, each in groups of 4x4 neighbours that share a box test wherever all of
// them pass beside a box (each ray's answer is still its own).
//
// Ties: hits whose window depths lie within a few float steps of the nearest are settled as the
// z-buffer settles them, by THE fragment depth (the polygon's depth plane at the pixel centre,
// raster/depth.hpp), equal floats going to the polygon submitted first; the depth written is
// that fragment depth too. So where the z-buffer cannot tell two surfaces apart, the ray caster
// answers as it does, and wherever the two show the same polygon they store the same depth.
//
// Guarantee: ids equal the z-buffer's wherever a pixel centre lies clearly inside one polygon
// and clearly nearest (the agreement suite's unambiguous pixels): rays meet the polygons as
// the scene gives them, the z-buffer their snapped projections, so they may differ within
// 1/256 pixel of an edge. See-through polygons are blended afterwards and outlines drawn over,
// as the z-buffer does.
//
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
#include "core/trace.hpp"
#include "raster/depth.hpp"
#include "raster/fragment.hpp"
#include "raster/lines.hpp"
#include "raster/triangle.hpp"
#include "geometry/ray_scene_data.hpp"
#include "visibility/algorithm.hpp"

namespace hsr::detail {
namespace {

// What the ray caster keeps between frames: the hierarchy of the scene it was built for.
struct Scratch {
  std::shared_ptr<const RayScene> rays;
  const Scene* scene = nullptr;
  std::uint64_t fingerprint = 0;
  std::vector<std::uint8_t> see_through;  // per material, when it was built
  // Per polygon, refilled each frame from the pipeline's triangles
  std::vector<DepthPlane> plane;
  std::vector<std::uint32_t> colour;
  std::vector<std::uint8_t> state;  // kKnown, kOnePlane bits
};
constexpr std::uint8_t kKnown = 1, kOnePlane = 2;

// Hits whose window depths lie within this many float steps of the nearest one's are settled
// as the z-buffer settles them: by their float depth (THE fragment depth, raster/depth.hpp),
// equal floats going to the polygon submitted first. Far from the eye a float step of window
// depth spans a long way in the scene (a 2% of the distance on a real model with near 0.05 and
// far 2236), and there the z-buffer cannot tell two surfaces apart: neither can we, then.
constexpr int kTieSteps = 4;

struct Band {
  bool ortho;
  double near, far;
};

// The end of the band of ties behind a hit at t: the t whose window depth is kTieSteps float
// steps beyond the hit's.
float bandLimit(const void* context, float t) {
  const Band& b = *static_cast<const Band*>(context);
  const double z = b.ortho ? t : (t * b.far - b.near) / (t * (b.far - b.near));
  float z_end = static_cast<float>(z);
  for (int i = 0; i < kTieSteps; ++i) z_end = std::nextafter(z_end, 2.0f);
  if (b.ortho) return std::max(t, z_end);
  const double denominator = b.far - static_cast<double>(z_end) * (b.far - b.near);
  if (!(denominator > 0.0)) return INFINITY;
  return std::max(t, std::nextafter(static_cast<float>(b.near / denominator), INFINITY));
}

constexpr int kTile = 16;  // pixels are cast in 16x16 tiles: neighbouring rays visit the same nodes
constexpr int kGroup = 4;  // and in groups of 4x4 (kBvhGroupSize) within a tile
static_assert(kGroup * kGroup == kBvhGroupSize && kTile % kGroup == 0);

// The sides of a triangle a ray from the eye may hit under the cull mode and front-face rule.
bool sidesFor(const RenderOptions& o, HitSides* sides) {
  const bool ccw_front = o.front_face == FrontFace::Ccw;
  switch (o.cull) {
    case CullMode::None:
      *sides = HitSides::kBoth;
      return true;
    case CullMode::Back:  // only front faces remain
      *sides = ccw_front ? HitSides::kCounterClockwiseOnly : HitSides::kClockwiseOnly;
      return true;
    case CullMode::Front:
      *sides = ccw_front ? HitSides::kClockwiseOnly : HitSides::kCounterClockwiseOnly;
      return true;
    case CullMode::FrontAndBack:
      break;
  }
  return false;  // nothing can be hit
}

struct TileCounts {
  std::uint64_t rays = 0, hits = 0, nodes = 0, triangles = 0, tie_sets = 0;
};

constexpr std::string_view kStepBuild = "build";
constexpr std::string_view kStepCast = "cast";
constexpr std::string_view kStepLevel = "boxes by level";
constexpr std::string_view kStepRay = "one ray";
constexpr std::string_view kStepDone = "done";

// The twelve edges of a world box on the picture, where all its corners are in front of the eye.
void outlineBox(const glm::dmat4& device_from_world, const glm::vec3& lo, const glm::vec3& hi,
                std::vector<TraceOutline>& out) {
  glm::vec2 c[8];
  for (int i = 0; i < 8; ++i) {
    const glm::dvec4 h =
        device_from_world *
        glm::dvec4((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z, 1.0);
    if (!(h.w > 1e-9)) return;
    c[i] = glm::vec2(static_cast<float>(h.x / h.w), static_cast<float>(h.y / h.w));
  }
  for (int i = 0; i < 8; ++i)
    for (int a = 0; a < 3; ++a)
      if (!(i & (1 << a))) out.push_back({c[i], c[i | (1 << a)]});
}

// The teaching view: the hierarchy's boxes over the picture level by level, then a few
// pixels' rays with the boxes each entered and the triangle it kept.
void explainHierarchy(const AlgorithmInput& in, const Frame& frame, const RaySceneData& data,
                      HitSides sides) {
  const Bvh& bvh = data.bvh;
  const glm::dmat4 device_from_world = deviceFromWorld(in.camera);
  // Boxes by level: the root's children are level 1
  std::vector<std::uint32_t> level{bvh.root}, next;
  constexpr int kLevels = 4;
  constexpr std::size_t kMostBoxes = 256;  // a level with more is shown in part
  for (int l = 1; l <= kLevels && !level.empty(); ++l) {
    std::vector<TraceOutline> outlines;
    std::size_t boxes = 0;
    next.clear();
    for (const std::uint32_t ref : level) {
      if (ref & BvhNode::kLeaf) continue;
      const BvhNode& node = bvh.nodes[ref];
      for (int i = 0; i < kBvhWidth; ++i) {
        if (node.child[i] == BvhNode::kEmpty) continue;
        ++boxes;
        if (boxes <= kMostBoxes)
          outlineBox(device_from_world, {node.lo[0][i], node.lo[1][i], node.lo[2][i]},
                     {node.hi[0][i], node.hi[1][i], node.hi[2][i]}, outlines);
        next.push_back(node.child[i]);
      }
    }
    if (boxes == 0) break;  // only leaves below: the tree ends here
    if (in.trace->wants(kStepLevel, static_cast<std::uint64_t>(l - 1), kLevels))
      in.trace->record(
          {kStepLevel,
           "Level " + std::to_string(l) +
               " of the bounding volume hierarchy: " + std::to_string(boxes) + " boxes" +
               (boxes > kMostBoxes ? " (the first " + std::to_string(kMostBoxes) + " drawn)" : "") +
               ". Each box holds up to " + std::to_string(kBvhWidth) +
               " smaller ones; a ray tests them side by side and enters only those it meets.",
           &frame, std::move(outlines)});
    level.swap(next);
  }
  // A few rays: three pixels that show a polygon (a quarter, half and three quarters through
  // them in row order), or the centre when none does
  const PixelRays pixel_rays(in.camera);
  const Band band{in.camera.ortho, in.camera.near, in.camera.far};
  std::vector<std::size_t> shown;
  for (std::size_t i = 0; i < frame.ids.size(); ++i)
    if (frame.ids[i] != kNoPolygon) shown.push_back(i);
  int picks[3][2];
  for (int k = 0; k < 3; ++k) {
    const std::size_t i =
        shown.empty() ? static_cast<std::size_t>(frame.height / 2) * frame.width + frame.width / 2
                      : shown[shown.size() * static_cast<std::size_t>(k + 1) / 4];
    picks[k][0] = static_cast<int>(i % frame.width),
    picks[k][1] = static_cast<int>(i / frame.width);
  }
  for (int k = 0; k < 3; ++k) {
    const PixelRay ray = pixel_rays.at(picks[k][0], picks[k][1]);
    std::vector<std::pair<glm::vec3, glm::vec3>> entered;
    BvhTraversalCounts counts;
    counts.entered = &entered;
    BvhCandidates found;
    intersectNearestBand(bvh, ray.org, ray.dir, ray.tmin, ray.tmax, sides, &bandLimit, &band,
                         &found, &counts);
    std::vector<TraceOutline> outlines;
    for (const auto& [lo, hi] : entered) outlineBox(device_from_world, lo, hi, outlines);
    std::string kept = "it meets nothing";
    if (found.count > 0) {
      const std::uint32_t t = found.hit[0].triangle;
      TraceOutline tri;
      for (const glm::vec3& v : {data.a[t], data.b[t], data.c[t]}) {
        const glm::dvec4 h = device_from_world * glm::dvec4(glm::dvec3(v), 1.0);
        if (h.w > 1e-9)
          tri.push_back(glm::vec2(static_cast<float>(h.x / h.w), static_cast<float>(h.y / h.w)));
      }
      if (tri.size() == 3) outlines.push_back(std::move(tri));
      kept = "it keeps polygon " + std::to_string(data.polygon[t]) +
             " at t = " + std::to_string(found.hit[0].t);
    }
    if (in.trace->wants(kStepRay, static_cast<std::uint64_t>(k), 3))
      in.trace->record({kStepRay,
                        "The ray through pixel (" + std::to_string(picks[k][0]) + ", " +
                            std::to_string(picks[k][1]) + ") enters " +
                            std::to_string(entered.size()) +
                            (entered.size() == 1 ? " box" : " boxes") + " and tests " +
                            std::to_string(counts.triangles) + " triangles of " +
                            std::to_string(bvh.stats.triangles) + "; " + kept + ", the nearest.",
                        &frame, std::move(outlines)});
  }
}

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
  if (in.trace && in.trace->wants(kStepBuild, 0, 1)) {
    std::vector<TraceOutline> outlines;
    if (data.bvh.root != BvhNode::kEmpty && !(data.bvh.root & BvhNode::kLeaf))
      outlineBox(deviceFromWorld(in.camera), data.bvh.lo, data.bvh.hi, outlines);
    in.trace->record({kStepBuild,
                      "The bounding volume hierarchy, built once in world space for every view: " +
                          std::to_string(data.bvh.stats.triangles) + " triangles in " +
                          std::to_string(data.bvh.stats.leaves) + " leaves under " +
                          std::to_string(data.bvh.stats.nodes) + " boxes of up to " +
                          std::to_string(kBvhWidth) + ", depth " +
                          std::to_string(data.bvh.stats.depth) +
                          " (binned surface-area heuristic).",
                      &frame, std::move(outlines)});
  }
  t0.restart();

  // Each polygon's colour and depth plane, as the pipeline made them
  const Scene& scene = in.scene;
  const ScreenTriangles& tris = in.prepared.triangles;
  s.plane.resize(scene.polygonCount());
  s.colour.resize(scene.polygonCount());
  s.state.assign(scene.polygonCount(), 0);
  for (const ScreenTriangle& t : tris) {
    if (t.id >= s.state.size()) continue;
    std::uint8_t& st = s.state[t.id];
    if (!(st & kKnown)) {
      st = kKnown | kOnePlane, s.plane[t.id] = t.depth, s.colour[t.id] = t.rgba;
    } else if (s.plane[t.id].dzdx != t.depth.dzdx || s.plane[t.id].dzdy != t.depth.dzdy ||
               s.plane[t.id].z0 != t.depth.z0) {
      st &= static_cast<std::uint8_t>(~kOnePlane);  // a non-planar polygon: a plane per triangle
    }
  }

  // The rays: pixel centres carried back from device space to the far plane
  const Camera& cam = in.camera;
  const PixelRays pixel_rays(cam);
  const double near = cam.near, far = cam.far;
  const Band band{cam.ortho, near, far};
  HitSides sides = HitSides::kBoth;
  const bool can_hit = sidesFor(in.options, &sides);

  const FrameView fb(frame);
  const int tiles_x = (frame.width + kTile - 1) / kTile,
            tiles_y = (frame.height + kTile - 1) / kTile;
  std::vector<TileCounts> per_tile(static_cast<std::size_t>(tiles_x) * tiles_y);
  std::atomic<std::uint64_t> unshaded{0};
  // A pixel's hits (the nearest and its ties, the nearest first) made its fragment
  auto settle = [&](int x, int y, const BvhCandidates& found, TileCounts& c) {
    if (found.count == 0) return;
    // Of the hits, the nearest fragment depth wins; of equal floats, the polygon submitted first
    const std::size_t k = fb.index(x, y);
    PolygonId id = kNoPolygon;
    float z = INFINITY;
    for (int i = 0; i < found.count; ++i) {
      const BvhHit& h = found.hit[i];
      const PolygonId p = data.polygon[h.triangle];
      const double t = h.t;
      const float zi =
          (s.state[p] & kOnePlane)
              ? fragmentDepth(s.plane[p], x, y)
              : static_cast<float>(cam.ortho ? t : (t * far - near) / (t * (far - near)));
      if (zi < z || (zi == z && p < id)) z = zi, id = p;
    }
    if (!(z < fb.depth[k])) return;  // LESS against the cleared depth
    if (found.count > 1) ++c.tie_sets;
    fb.depth[k] = z;
    fb.ids[k] = id;
    if (s.state[id] & kKnown) {
      fb.rgba[k] = s.colour[id];
    } else {  // no snapped triangle of it made a pixel: shaded as the pipeline would
      fb.rgba[k] = shadedColour(scene, cam, in.options, id);
      unshaded.fetch_add(1, std::memory_order_relaxed);
    }
    fb.overdraw[k] = 1;
    ++c.hits;
  };
  auto castTile = [&](int tx, int ty) {
    TileCounts& c = per_tile[static_cast<std::size_t>(ty) * tiles_x + tx];
    BvhTraversalCounts work;
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
        intersectNearestBandGroup(data.bvh, org, dir, n, tmin, tmax, sides, &bandLimit, &band,
                                  found, &work);
        for (int i = 0; i < n; ++i) settle(px[i], py[i], found[i], c);
      }
    }
    c.nodes += work.nodes + work.group_nodes;
    c.triangles += work.triangles;
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
  if (in.trace && in.trace->wants(kStepCast, 0, 1))
    in.trace->record({kStepCast,
                      "A ray from the eye through every pixel centre: " + std::to_string(c.rays) +
                          " rays, " + std::to_string(c.hits) +
                          " hit a polygon; each pixel shows the nearest hit.",
                      &frame,
                      {}});
  if (in.trace) explainHierarchy(in, frame, data, sides);
  frame.stats.addStage("raycast cast", t0.ms());

  // See-through polygons over the finished picture, in submission order, as the z-buffer
  FragmentCounts fragments;
  const PixelBox viewport{0, 0, frame.width - 1, frame.height - 1};
  const SpanFn span = spanFunction(DepthFunc::Less);
  for (const ScreenTriangle& t : tris)
    if (t.transparent()) rasterTriangle<DepthFunc::Less>(t, viewport, fb, true, span, fragments);
  for (const ScreenLine& o : in.prepared.outline) drawOutlinePen(o, viewport, fb);

  if (in.trace && in.trace->wants(kStepDone, 0, 1))
    in.trace->record({kStepDone,
                      "Done: " + std::to_string(c.hits) +
                          " pixels show their ray's nearest polygon; " + std::to_string(c.nodes) +
                          " nodes of up to " + std::to_string(kBvhWidth) + " boxes visited and " +
                          std::to_string(c.triangles) + " ray/triangle tests in all.",
                      &frame,
                      {}});
  frame.stats.fragments_tested += c.hits + fragments.tested;
  frame.stats.fragments_written += c.hits + fragments.written;
  frame.stats.state_bytes += s.rays->stats().bytes;
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
