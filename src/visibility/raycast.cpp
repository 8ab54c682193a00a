// Ray casting, as the notes teach it (Appel 1968; the notes' "ray casting"): the one algorithm
// of the notes that works before the perspective transformation.
//
//     for all pixels (i, j):
//       cast a ray from the eye through the centre of pixel (i, j)
//       for all polygons P:
//         if the ray meets P nearer than anything met so far:  remember P and where
//       Image[i, j] = the colour of the nearest polygon met (the background if none)
//
// This file is that loop, one ray and one triangle at a time on one core, to be read beside
// the notes, with the one economy the notes pair it with: a triangle's extent on the screen
// (the box around its projected corners, widened by a margin that no rounding of the rays can
// cross). A ray through a pixel outside a triangle's extent cannot meet it, so the two are not
// tested; the triangles whose extents hold a row are kept in a list as the rows go by. The renderer
// registered as "raycast" (raycast_fast.cpp) finds the same hits through a bounding volume
// hierarchy on all cores; tests/cross/textbook_test.cpp proves the two equal bit for bit.
//
// The rays: the pixel centre carried back through the pipeline's own device-from-world matrix,
// to the far plane. Perspective: from the eye, t = near / far at the near plane and t = 1 at
// the far plane, so a hit's eye depth is t * far. Orthographic: from the near plane's point to
// the far plane's, t from 0 to 1, the window depth itself. `--cull` and `--front-face` decide
// which side of a triangle a ray may hit (the notes' N . V test, as seen from the eye).
//
// The polygons: as the scene gives them, in world space, cut into triangles (the pipeline's
// triangulation); each is met by the watertight ray/triangle test of Woop, Benthin & Wald 2013
// (geometry/ray_triangle.hpp), so no ray slips between two triangles that share an edge.
//
// Ties: hits whose window depths lie within a few float steps of the nearest are settled as the
// z-buffer settles them, by THE fragment depth (the polygon's depth plane at the pixel centre,
// raster/depth.hpp), equal floats going to the polygon submitted first; the depth written is
// that fragment depth too (raycast_hits.hpp). So where the z-buffer cannot tell two surfaces
// apart, the ray caster answers as it does, and wherever the two show the same polygon they
// store the same depth.
//
// Guarantee: ids equal the z-buffer's wherever a pixel centre lies clearly inside one polygon
// and clearly nearest (the agreement suite's unambiguous pixels): rays meet the polygons as
// the scene gives them, the z-buffer their snapped projections, so they may differ within
// 1/256 pixel of an edge. See-through polygons are blended afterwards and outlines drawn over,
// as the z-buffer does.
//
// Cost: O(rows x triangles crossing them x width) extent checks and one ray/triangle test per
// pixel of each extent (a frame that would check more than kMostChecks is refused: "raycast"
// draws it); memory 52 bytes a triangle, no depth buffer of its own. Tests:
// tests/visibility/raycast_test.cpp and every suite its capabilities join.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/frame.hpp"
#include "core/stopwatch.hpp"
#include "geometry/ray_triangle.hpp"
#include "geometry/triangulate.hpp"
#include "hsr/error.hpp"
#include "raster/fragment.hpp"
#include "visibility/raycast_hits.hpp"

namespace hsr::detail {
namespace {

// Step names: what `hsr explain raycast-textbook` (and `hsr explain raycast`) shows.
constexpr std::string_view kStepPolygons = "polygons";
constexpr std::string_view kStepRow = "cast row";
constexpr std::string_view kStepRay = "one ray";
constexpr std::string_view kStepDone = "done";

// Every ray of a row looks at every triangle whose extent holds the row: more looks than this in
// a frame (several seconds) are refused.
constexpr std::uint64_t kMostChecks = 4'000'000'000;

// The scene's opaque polygons as world-space triangles (see-through ones are blended after).
struct WorldTriangles {
  std::vector<glm::vec3> a, b, c;
  std::vector<PolygonId> polygon;
};

WorldTriangles opaqueTriangles(const Scene& scene) {
  WorldTriangles out;
  std::vector<Triangle> tris;
  for (PolygonId p = 0; p < scene.polygonCount(); ++p) {
    const std::uint32_t m = scene.material(p);
    if (m < scene.materials.size() && materialSeeThrough(scene.materials[m])) continue;
    triangulatePolygon(scene, p, tris);
  }
  for (const Triangle& t : tris) {
    out.a.push_back(scene.position(t.v[0]));
    out.b.push_back(scene.position(t.v[1]));
    out.c.push_back(scene.position(t.v[2]));
    out.polygon.push_back(t.id);
  }
  return out;
}

// A triangle's extent on the screen: the pixel centres (x0..x1, y0..y1) its projection may
// reach. Empty (x0 > x1) when it lies wholly outside the picture.
struct Extent {
  int x0, x1, y0, y1;
};

// The extents of the triangles: their corners through the pipeline's device-from-world
// matrix, widened by `margin` pixels. A ray's hit projects onto its pixel centre, so the
// triangle it meets holds that centre in its projection; the margin covers the float rounding
// of the rays' origins and directions. A triangle with a corner at or behind the eye's plane has
// no bounded projection: its extent is the whole picture.
std::vector<Extent> screenExtents(const WorldTriangles& w, const Camera& cam, int width, int height,
                                  double margin) {
  const glm::dmat4 device_from_world = deviceFromWorld(cam);
  const Extent whole{0, width - 1, 0, height - 1};
  std::vector<Extent> out(w.a.size());
  for (std::size_t i = 0; i < w.a.size(); ++i) {
    double lo_x = INFINITY, hi_x = -INFINITY, lo_y = INFINITY, hi_y = -INFINITY;
    bool bounded = true;
    for (const glm::vec3& v : {w.a[i], w.b[i], w.c[i]}) {
      const glm::dvec4 h = device_from_world * glm::dvec4(glm::dvec3(v), 1.0);
      if (!(h.w > 1e-9)) {
        bounded = false;
        break;
      }
      lo_x = std::min(lo_x, h.x / h.w), hi_x = std::max(hi_x, h.x / h.w);
      lo_y = std::min(lo_y, h.y / h.w), hi_y = std::max(hi_y, h.y / h.w);
    }
    if (!bounded) {
      out[i] = whole;
      continue;
    }
    // Pixel centres are at integers; clamped to the picture (an extent wholly outside it is
    // left empty)
    auto clampTo = [](double v, int lo, int hi) {
      return static_cast<int>(std::clamp(v, double(lo), double(hi)));
    };
    out[i] = {clampTo(std::ceil(lo_x - margin), 0, width),
              clampTo(std::floor(hi_x + margin), -1, width - 1),
              clampTo(std::ceil(lo_y - margin), 0, height),
              clampTo(std::floor(hi_y + margin), -1, height - 1)};
  }
  return out;
}

// The margin of the extents, in pixels. In perspective every ray starts at the eye itself (a
// float) and its direction is rounded once: a hit lies a few float steps of its distance off the
// exact ray, far under a pixel. An orthographic ray starts at its pixel's point on the near
// plane, rounded to float: up to half a float step of the coordinates off, which may be many
// pixels where the view is small and far from the origin.
double extentMargin(const Camera& cam, const PixelRays& rays) {
  constexpr double kPixels = 2.0;
  if (!cam.ortho) return kPixels;
  const glm::vec3 corners[] = {rays.at(0, 0).org, rays.at(cam.width - 1, cam.height - 1).org};
  double largest = 0;
  for (const glm::vec3& c : corners)
    for (int k = 0; k < 3; ++k) largest = std::max(largest, double(std::abs(c[k])));
  const double pixel = 2.0 * double(cam.ortho_half_height) / cam.height;  // world units
  const double step = largest * std::ldexp(1.0, -23) +
                      4 * (double(cam.far) - double(cam.near)) * std::ldexp(1.0, -24);
  return kPixels + step / pixel;
}

// Whether hit x comes before hit y: nearer, or as near and the lower triangle number.
bool before(const BvhHit& x, const BvhHit& y) {
  return x.t < y.t || (x.t == y.t && x.triangle < y.triangle);
}

// The ray through pixel column x against every triangle of its row's list whose extent holds x:
// the nearest hit and the hits in the band of ties behind it (rayBandLimit), nearest first, at
// most kBvhCandidates. `tests` counts the ray/triangle tests made.
BvhCandidates castRay(const WorldTriangles& w, const std::vector<Extent>& extents,
                      const std::vector<std::uint32_t>& row, int x, const PixelRay& ray,
                      HitSides sides, const RayDepthBand& band, std::vector<BvhHit>& hits,
                      std::uint64_t& tests) {
  BvhCandidates out;
  if (!rayIsValid(ray.org, ray.dir)) return out;
  const ShearedRay r = shearRay(ray.org, ray.dir);
  // For all polygons P (their triangles): where the ray meets it, past the near plane. A hit a
  // little beyond the far plane may still tie with one before it, so none is turned away yet.
  hits.clear();
  for (const std::uint32_t i : row) {
    if (x < extents[i].x0 || x > extents[i].x1) continue;
    ++tests;
    TriangleHit h;
    if (intersectTriangle(r, w.a[i], w.b[i], w.c[i], ray.tmin, INFINITY, sides, &h))
      hits.push_back({h.t, h.u, h.v, i, h.counter_clockwise});
  }
  // The nearest before the far plane
  const BvhHit* nearest = nullptr;
  for (const BvhHit& h : hits)
    if (h.t < ray.tmax && (!nearest || before(h, *nearest))) nearest = &h;
  if (!nearest) return out;
  // And those within the band of ties behind it, nearest first
  const float limit = rayBandLimit(&band, nearest->t);
  std::erase_if(hits, [&](const BvhHit& h) { return !(h.t <= limit); });
  std::sort(hits.begin(), hits.end(), before);
  out.count = static_cast<int>(std::min<std::size_t>(hits.size(), kBvhCandidates));
  std::copy_n(hits.begin(), out.count, out.hit);
  return out;
}

// The outline of a world triangle on the picture, where its corners are in front of the eye.
TraceOutline outlineOf(const glm::dmat4& device_from_world, const glm::vec3& a, const glm::vec3& b,
                       const glm::vec3& c) {
  TraceOutline out;
  for (const glm::vec3& v : {a, b, c}) {
    const glm::dvec4 h = device_from_world * glm::dvec4(glm::dvec3(v), 1.0);
    if (!(h.w > 1e-9)) return {};
    out.emplace_back(static_cast<float>(h.x / h.w), static_cast<float>(h.y / h.w));
  }
  return out;
}

}  // namespace

void drawRaycastTextbook(const AlgorithmInput& in, Frame& frame) {
  const detail::Stopwatch t0;
  const Camera& cam = in.camera;
  const WorldTriangles world = opaqueTriangles(in.scene);
  const PixelRays pixel_rays(cam);
  const std::vector<Extent> extents =
      screenExtents(world, cam, frame.width, frame.height, extentMargin(cam, pixel_rays));
  // The edge table's counterpart: the triangles listed by the first row of their extents
  std::vector<std::vector<std::uint32_t>> starting(static_cast<std::size_t>(frame.height));
  std::uint64_t checks = 0;  // a ray looks at each triangle of its row's list
  for (std::uint32_t i = 0; i < extents.size(); ++i) {
    if (extents[i].x0 > extents[i].x1 || extents[i].y0 > extents[i].y1) continue;
    starting[static_cast<std::size_t>(extents[i].y0)].push_back(i);
    checks += static_cast<std::uint64_t>(extents[i].y1 - extents[i].y0 + 1) *
              static_cast<std::uint64_t>(frame.width);
  }
  if (checks > kMostChecks)
    throw Error("raycast-textbook looks at every triangle whose screen extent holds a ray's row: " +
                std::to_string(frame.width) + "x" + std::to_string(frame.height) + " rays and " +
                std::to_string(world.a.size()) + " triangles make " + std::to_string(checks) +
                " looks, more than the " + std::to_string(kMostChecks) +
                " it takes on; draw it with raycast (the same picture, bit for bit, through a "
                "bounding volume hierarchy) or at a smaller --size");
  PolygonLooks looks;  // each polygon's colour and depth plane, as the pipeline made them
  looks.build(in.scene, in.prepared.triangles);
  if (in.trace && in.trace->wants(kStepPolygons, 0, 1))
    in.trace->record(
        {kStepPolygons,
         "The polygons in world space, before any projection: " + std::to_string(world.a.size()) +
             " opaque triangles, each with its extent on the screen (the box its corners "
             "project into). Every ray will be tested against every triangle whose extent holds "
             "its pixel; see-through polygons are blended over the picture afterwards.",
         &frame,
         {}});

  const RayDepthBand band{cam.ortho, cam.near, cam.far};
  HitSides sides = HitSides::kBoth;
  const bool can_hit = raySidesFor(in.options, &sides);
  const FrameView fb(frame);
  std::vector<BvhHit> hits;
  std::vector<std::uint32_t> row;  // the triangles whose extents hold the current row
  std::uint64_t rays = 0, shown = 0, ties = 0, unshaded = 0, tests = 0;
  // For all pixels: a ray from the eye through its centre; the nearest polygon it meets is shown
  for (int y = 0; y < frame.height; ++y) {
    std::erase_if(row, [&](std::uint32_t i) { return extents[i].y1 < y; });
    row.insert(row.end(), starting[static_cast<std::size_t>(y)].begin(),
               starting[static_cast<std::size_t>(y)].end());
    for (int x = 0; x < frame.width; ++x) {
      ++rays;
      if (!can_hit) continue;
      const BvhCandidates found =
          castRay(world, extents, row, x, pixel_rays.at(x, y), sides, band, hits, tests);
      if (!looks.settle(in, fb, x, y, world.polygon, found, &unshaded)) continue;
      ++shown;
      ties += found.count > 1;
    }
    if (in.trace && in.trace->wants(kStepRow, static_cast<std::uint64_t>(y),
                                    static_cast<std::uint64_t>(frame.height)))
      in.trace->record({kStepRow,
                        "Row " + std::to_string(y) + ": a ray through each of its " +
                            std::to_string(frame.width) + " pixel centres; " +
                            std::to_string(row.size()) + " of the " +
                            std::to_string(world.a.size()) +
                            " triangles have extents that hold the row, and each ray is tested "
                            "against those whose extent holds its pixel; each pixel shows the "
                            "nearest polygon its ray met. Rows below are still empty.",
                        &frame,
                        {pixelBoxOutline(PixelBox{0, y, frame.width - 1, y})}});
  }

  // A few rays, each with the triangle it kept: three pixels that show a polygon (a quarter, half
  // and three quarters through them in row order)
  if (in.trace) {
    const glm::dmat4 device_from_world = deviceFromWorld(cam);
    std::vector<std::size_t> lit;
    for (std::size_t i = 0; i < frame.ids.size(); ++i)
      if (frame.ids[i] != kNoPolygon) lit.push_back(i);
    for (int k = 0; k < 3 && !lit.empty(); ++k) {
      const std::size_t i = lit[lit.size() * static_cast<std::size_t>(k + 1) / 4];
      const int x = static_cast<int>(i % frame.width), y = static_cast<int>(i / frame.width);
      // The ray again, against every triangle whose extent holds its pixel
      std::vector<std::uint32_t> holding;
      for (std::uint32_t j = 0; j < extents.size(); ++j)
        if (extents[j].y0 <= y && y <= extents[j].y1) holding.push_back(j);
      std::uint64_t tested = 0;
      const BvhCandidates found =
          castRay(world, extents, holding, x, pixel_rays.at(x, y), sides, band, hits, tested);
      if (found.count == 0 || !in.trace->wants(kStepRay, static_cast<std::uint64_t>(k), 3))
        continue;
      const std::uint32_t t = found.hit[0].triangle;
      in.trace->record(
          {kStepRay,
           "The ray through pixel (" + std::to_string(x) + ", " + std::to_string(y) +
               ") is tested against the " + std::to_string(tested) + " of " +
               std::to_string(world.a.size()) +
               " triangles whose extents hold its pixel and meets " + std::to_string(hits.size()) +
               " of them near the front; it keeps polygon " + std::to_string(world.polygon[t]) +
               " at t = " + std::to_string(found.hit[0].t) + ", the nearest (outlined).",
           &frame,
           {outlineOf(device_from_world, world.a[t], world.b[t], world.c[t]),
            pixelBoxOutline(PixelBox{x - 2, y - 2, x + 2, y + 2})}});
    }
  }
  frame.stats.addStage("raycast cast", t0.ms());

  // See-through polygons over the finished picture, in submission order, and the outline pen
  FragmentCounts fragments;
  rayFinishFrame(in, fb, fragments);
  if (in.trace && in.trace->wants(kStepDone, 0, 1))
    in.trace->record({kStepDone,
                      "Done: " + std::to_string(shown) + " of " + std::to_string(rays) +
                          " pixels show their ray's nearest polygon, after " +
                          std::to_string(tests) + " ray/triangle tests (" +
                          std::to_string(rays * world.a.size()) +
                          " without the extents: every ray against every triangle).",
                      &frame,
                      {}});
  frame.stats.fragments_tested += shown + fragments.tested;
  frame.stats.fragments_written += shown + fragments.written;
  frame.stats.state_bytes +=
      world.a.size() * (3 * sizeof(glm::vec3) + sizeof(PolygonId) + sizeof(Extent)) +
      looks.bytes() + hits.capacity() * sizeof(BvhHit);
  frame.stats.addCounter("raycast: rays", rays);
  frame.stats.addCounter("raycast: hits", shown);
  frame.stats.addCounter("raycast: ray/triangle tests", tests);
  frame.stats.addCounter("raycast: pixels with hits in one depth band, settled by float depth",
                         ties);
  frame.stats.addCounter("raycast: hits shaded without a screen triangle", unshaded);
}

}  // namespace hsr::detail
