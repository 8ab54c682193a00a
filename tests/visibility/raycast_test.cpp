// Ray casting (raycast.cpp). Rays meet the polygons as the scene gives them and the z-buffer
// their snapped projections, so the two may differ within 1/256 pixel of an edge and where two
// surfaces tie in depth; elsewhere they must agree. Row 4 (unambiguous pixels identical) runs
// through the registry in cross/agreement_test.cpp; here: the real models of the Mesa test,
// culling and the front-face rule, the near and far planes, glass and outlines, the hierarchy
// kept across views, and the same frame at any thread count.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "cross/compare_with_zbuffer.hpp"
#include "cross/figures.hpp"
#include "hsr/io.hpp"
#include "hsr/ray_scene.hpp"
#include "hsr/render.hpp"
#include "pipeline/pipeline.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using testing::grouped;
using testing::percent;

// Where the ray caster's frame differs from the z-buffer's, and why.
struct RayComparison {
  std::uint64_t drawn = 0, differ = 0;
  std::uint64_t tie = 0;     // two polygons within kTie of each other in depth
  std::uint64_t edge = 0;    // else: a ray 1/64 pixel away meets the z-buffer's polygon, or
                             // another than the centre's: the snapped and exact edges disagree
  std::uint64_t wrong = 0;   // neither: a clearly different answer
  std::uint64_t depth_differs = 0;  // the same polygon, another depth
  std::string first_wrong;
};

constexpr float kTie = 1e-5f;  // window depth: as the object-order tests' "clearly deeper"
constexpr std::pair<int, int> kJitter[] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, -1}, {1, -1}, {-1, 1}};

// The polygon a ray through device point (x, y) meets first, as the ray caster's rays go.
PolygonId polygonAt(const RayScene& rays, const detail::PixelRays& pixel_rays, double x, double y, RaySides sides) {
  const detail::PixelRay r = pixel_rays.at(x, y);
  return rays.intersect(r.org, r.dir, r.tmax, r.tmin, sides).polygon;
}

RayComparison compareRays(const Scene& scene, const Camera& cam, const RenderOptions& o, const Frame& z,
                          const Frame& r) {
  RayComparison c;
  const RayScene rays(scene);
  const detail::PixelRays pixel_rays(cam);
  const RaySides sides = o.cull == CullMode::Back ? RaySides::kFrontOnly : RaySides::kBoth;
  for (std::size_t k = 0; k < z.ids.size(); ++k) {
    c.drawn += z.ids[k] != kNoPolygon;
    if (z.ids[k] == r.ids[k]) {
      c.depth_differs += z.ids[k] != kNoPolygon && z.depth[k] != r.depth[k];
      continue;
    }
    c.differ++;
    const int x = static_cast<int>(k % z.width), y = static_cast<int>(k / z.width);
    if (z.ids[k] != kNoPolygon && r.ids[k] != kNoPolygon && std::abs(z.depth[k] - r.depth[k]) <= kTie) {
      c.tie++;
      continue;
    }
    const PolygonId centre = polygonAt(rays, pixel_rays, x, y, sides);
    bool near_edge = false;
    for (const auto& [dx, dy] : kJitter) {
      const PolygonId p = polygonAt(rays, pixel_rays, x + dx / 64.0, y + dy / 64.0, sides);
      near_edge = near_edge || p == z.ids[k] || p != centre;
    }
    if (near_edge) {
      c.edge++;
    } else if (c.wrong++ == 0) {
      c.first_wrong = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): raycast " +
                      std::to_string(r.ids[k]) + " at " + std::to_string(r.depth[k]) + ", z-buffer " +
                      std::to_string(z.ids[k]) + " at " + std::to_string(z.depth[k]);
    }
  }
  return c;
}

std::string describe(const RayComparison& c) {
  return grouped(c.differ) + " of " + grouped(c.drawn) + " drawn pixels differ (" +
         percent(c.drawn - c.differ, c.drawn) + " agree): " + grouped(c.tie) + " depth ties, " + grouped(c.edge) +
         " within 1/64 pixel of an edge, " + grouped(c.wrong) + " otherwise; the same polygon at another depth: " +
         grouped(c.depth_differs);
}

TEST(Raycast, RealModelsAgreeWithTheZBuffer) {
  testing::forEachMesaModelView([](const std::string& label, const Scene& scene, const Camera& camera, RenderOptions o) {
    const Frame z = render(scene, camera, o);
    o.algorithm = "raycast";
    const Frame r = render(scene, camera, o);
    const RayComparison c = compareRays(scene, camera, o, z, r);
    testing::printFigures(label + ": raycast: " + describe(c));
    EXPECT_LE(c.differ, c.drawn / 1000);
    EXPECT_EQ(c.wrong, 0u) << c.first_wrong;
    EXPECT_EQ(c.depth_differs, 0u);
  });
}

}  // namespace
}  // namespace hsr
