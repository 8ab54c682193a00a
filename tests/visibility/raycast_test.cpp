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

// A tie at the nearest hit found so far: two triangles at the same t in different leaves of the
// hierarchy. 48 pairs of overlapping triangles in one plane facing an orthographic camera (every
// hit of a pixel's ray at the same t and window depth, exactly), each triangle of a pair wrapped
// in a cloud of small triangles behind the plane so that the two land in different leaves, and
// the pair's ids in either order (the left one first, or the right one): wherever the two
// overlap the ray caster must show the first submitted, as the z-buffer's LESS does, whichever
// leaf its walk reaches first.
TEST(Raycast, ATieBetweenLeavesGoesToTheFirstSubmittedAsInTheZBuffer) {
  constexpr int kW = 384, kH = 256;
  testing::Rng rng(47);
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  struct Tri {
    glm::vec3 a, b, c;
  };
  std::vector<Tri> front, cloud;
  for (int p = 0; p < 48; ++p) {
    const float x0 = 8.0f + 46.0f * (p % 8), y0 = 8.0f + 40.0f * (p / 8);
    const float z = 0.25f;  // the plane facing the camera
    const Tri left{{x0, y0, z}, {x0 + 30, y0 + 4, z}, {x0 + 4, y0 + 30, z}};
    const Tri right{{x0 + 40, y0 + 30, z}, {x0 + 10, y0 + 26, z}, {x0 + 36, y0, z}};
    // Which one is submitted first alternates from pair to pair
    front.push_back(p % 2 ? right : left);
    front.push_back(p % 2 ? left : right);
    for (const Tri& t : {left, right}) {
      const glm::vec3 centre = (t.a + t.b + t.c) / 3.0f;
      for (int k = 0; k < 12; ++k) {
        const glm::vec3 q = centre + glm::vec3(rng.uniform(-6, 6), rng.uniform(-6, 6), -1.0f - rng.uniform(0, 2));
        cloud.push_back({q, q + glm::vec3(1.5f, 0, 0), q + glm::vec3(0, 1.5f, 0)});
      }
    }
  }
  // The pairs' triangles keep their order; the clouds come after, so ids are the pairs' order
  for (const Tri& t : front) s.addPolygonVertices({t.a, t.b, t.c}, m);
  for (const Tri& t : cloud) s.addPolygonVertices({t.a, t.b, t.c}, m);
  const Camera camera = testing::pixelCamera(kW, kH);
  RenderOptions o;
  o.cull = CullMode::None;
  const Frame z = render(s, camera, o);
  o.algorithm = "raycast";
  const Frame r = render(s, camera, o);
  std::size_t overlap = 0, differ = 0;
  for (std::size_t k = 0; k < z.ids.size(); ++k) {
    if (z.ids[k] == kNoPolygon || z.ids[k] >= front.size()) continue;
    // Covered by both of a pair: the z-buffer shows the pair's first (even id) there
    overlap += z.ids[k] % 2 == 0 && r.ids[k] != kNoPolygon;
    differ += r.ids[k] != z.ids[k];
  }
  EXPECT_GT(overlap, 3000u);
  EXPECT_EQ(differ, 0u) << "pixels of the pairs where the ray caster shows another polygon than the z-buffer";
  testing::printFigures("raycast ties between leaves: 48 pairs at one depth, " + grouped(overlap) +
                        " pixels, " + grouped(differ) + " differ from the z-buffer");
}

}  // namespace
}  // namespace hsr
