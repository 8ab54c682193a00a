// Ray casting (raycast.cpp). Rays meet the polygons as the scene gives them and the z-buffer
// their snapped projections, so the two may differ within 1/256 pixel of an edge and where two
// surfaces tie in depth; elsewhere they must agree. Row 4 (unambiguous pixels identical) runs
// through the registry in cross/agreement_test.cpp; here: the real models of the Mesa test,
// culling and the front-face rule, the near and far planes, glass and outlines, the hierarchy
// kept across views, and the same frame at any thread count.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "cross/compare_with_zbuffer.hpp"
#include "cross/figures.hpp"
#include "hsr/error.hpp"
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
  std::uint64_t tie = 0;    // two polygons within kTie of each other in depth
  std::uint64_t edge = 0;   // else: a ray 1/64 pixel away meets the z-buffer's polygon, or
                            // another than the centre's: the snapped and exact edges disagree
  std::uint64_t wrong = 0;  // neither: a clearly different answer
  std::uint64_t depth_differs = 0;  // the same polygon, another depth
  std::string first_wrong;
};

constexpr float kTie = 1e-5f;  // window depth: as the object-order tests' "clearly deeper"
constexpr std::pair<int, int> kJitter[] = {{1, 0}, {-1, 0},  {0, 1},  {0, -1},
                                           {1, 1}, {-1, -1}, {1, -1}, {-1, 1}};

// The polygon a ray through device point (x, y) meets first, as the ray caster's rays go.
PolygonId polygonAt(const RayScene& rays, const detail::PixelRays& pixel_rays, double x, double y,
                    RaySides sides) {
  const detail::PixelRay r = pixel_rays.at(x, y);
  return rays.intersect(r.org, r.dir, r.tmax, r.tmin, sides).polygon;
}

RayComparison compareRays(const Scene& scene, const Camera& cam, const RenderOptions& o,
                          const Frame& z, const Frame& r) {
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
    if (z.ids[k] != kNoPolygon && r.ids[k] != kNoPolygon &&
        std::abs(z.depth[k] - r.depth[k]) <= kTie) {
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
                      std::to_string(r.ids[k]) + " at " + std::to_string(r.depth[k]) +
                      ", z-buffer " + std::to_string(z.ids[k]) + " at " +
                      std::to_string(z.depth[k]);
    }
  }
  return c;
}

std::string describe(const RayComparison& c) {
  return grouped(c.differ) + " of " + grouped(c.drawn) + " drawn pixels differ (" +
         percent(c.drawn - c.differ, c.drawn) + " agree): " + grouped(c.tie) + " depth ties, " +
         grouped(c.edge) + " within 1/64 pixel of an edge, " + grouped(c.wrong) +
         " otherwise; the same polygon at another depth: " + grouped(c.depth_differs);
}

TEST(Raycast, RealModelsAgreeWithTheZBuffer) {
  testing::forEachMesaModelView(
      [](const std::string& label, const Scene& scene, const Camera& camera, RenderOptions o) {
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

// A tie at the nearest hit found so far: triangles at the same t in different leaves of the
// hierarchy. 48 stacks of six overlapping triangles in one plane facing an orthographic camera
// (every hit of a pixel's ray at the same t and window depth, exactly); a leaf holds four
// triangles, so every stack spans two leaves or more, and each stack's six are submitted in a
// shuffled order, so that in some stacks the first submitted lies in a leaf the walk reaches
// after another. Each stack is wrapped in a cloud of small triangles behind the plane. Wherever
// they overlap the ray caster must show the first submitted, as the z-buffer's LESS does,
// whichever leaf its walk reaches first.
TEST(Raycast, ATieBetweenLeavesGoesToTheFirstSubmittedAsInTheZBuffer) {
  constexpr int kW = 384, kH = 256, kStacks = 48, kPerStack = 6;
  testing::Rng rng(47);
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  struct Tri {
    glm::vec3 a, b, c;
  };
  std::vector<Tri> front, cloud;
  for (int p = 0; p < kStacks; ++p) {
    const glm::vec3 centre(26.0f + 46.0f * (p % 8), 26.0f + 40.0f * (p / 8),
                           0.25f);  // the plane z = 0.25
    // Six triangles inscribed in a circle of radius 16 around the centre, each turned 20 degrees
    // (and up to 6 more) from the last: each covers the disc of radius 8 around the centre
    std::vector<Tri> stack;
    for (int k = 0; k < kPerStack; ++k) {
      const double start = k * (2 * std::numbers::pi / 3 / kPerStack) + rng.uniform(0.0f, 0.1f);
      glm::vec3 v[3];
      for (int i = 0; i < 3; ++i) {
        const double angle = start + i * (2 * std::numbers::pi / 3);
        v[i] = centre + glm::vec3(static_cast<float>(16 * std::cos(angle)),
                                  static_cast<float>(16 * std::sin(angle)), 0.0f);
      }
      stack.push_back({v[0], v[1], v[2]});
    }
    for (int k = kPerStack - 1; k > 0; --k)  // Fisher-Yates: the submission order
      std::swap(stack[static_cast<std::size_t>(k)],
                stack[static_cast<std::size_t>(rng.next() % (k + 1))]);
    front.insert(front.end(), stack.begin(), stack.end());
    for (int k = 0; k < 24; ++k) {
      const glm::vec3 q = centre + glm::vec3(rng.uniform(-14, 14), rng.uniform(-14, 14),
                                             -1.25f - rng.uniform(0, 2));
      cloud.push_back({q, q + glm::vec3(1.5f, 0, 0), q + glm::vec3(0, 1.5f, 0)});
    }
  }
  // The stacks' triangles keep their order; the clouds come after, so ids are the stacks' order
  for (const Tri& t : front) s.addPolygonVertices({t.a, t.b, t.c}, m);
  for (const Tri& t : cloud) s.addPolygonVertices({t.a, t.b, t.c}, m);
  const Camera camera = testing::pixelCamera(kW, kH);
  RenderOptions o;
  o.cull = CullMode::None;
  const Frame z = render(s, camera, o);
  o.algorithm = "raycast";
  const Frame r = render(s, camera, o);
  // A pixel centre within 0.01 px of an edge of its stack is left out (counted): there the
  // ray caster's watertight test and the z-buffer's fill rule may cover it differently (the ray
  // caster lacks exact-coverage), which is not a tie
  const auto nearAnEdge = [&](std::size_t stack, double px, double py) {
    for (std::size_t t = stack * kPerStack; t < (stack + 1) * kPerStack; ++t) {
      const glm::vec3 v[3] = {front[t].a, front[t].b, front[t].c};
      for (int e = 0; e < 3; ++e) {
        const double ax = v[e].x, ay = v[e].y, bx = v[(e + 1) % 3].x, by = v[(e + 1) % 3].y;
        const double d =
            std::abs((bx - ax) * (py - ay) - (by - ay) * (px - ax)) / std::hypot(bx - ax, by - ay);
        if (d < 0.01) return true;
      }
    }
    return false;
  };
  std::size_t tied = 0, not_lowest = 0, differ = 0, on_edges = 0;
  for (std::size_t k = 0; k < z.ids.size(); ++k) {
    if (z.ids[k] == kNoPolygon || z.ids[k] >= front.size()) continue;
    const std::size_t stack = z.ids[k] / kPerStack;
    const double px = static_cast<double>(k % kW) + 0.5, py = static_cast<double>(k / kW) + 0.5;
    if (nearAnEdge(stack, px, py) || nearAnEdge(stack, px, kH - py)) {  // rows either way up
      on_edges++;
      continue;
    }
    tied++;
    // Where the z-buffer shows a stack's triangle other than its first, the first does not cover
    // the pixel: the test's scenes must also have pixels of later triangles in the lead
    not_lowest += z.ids[k] % kPerStack != 0;
    differ += r.ids[k] != z.ids[k];
  }
  EXPECT_GT(tied, 20000u);
  EXPECT_GT(not_lowest, 1000u);
  EXPECT_EQ(differ, 0u)
      << "pixels of the stacks where the ray caster shows another polygon than the z-buffer";
  testing::printFigures("raycast ties between leaves: " + grouped(kStacks) + " stacks of " +
                        grouped(kPerStack) + " triangles at one depth, " + grouped(tied) +
                        " pixels, " + grouped(differ) + " differ from the z-buffer (" +
                        grouped(on_edges) + " on an edge left out)");
}

// The textbook ray caster looks at every triangle whose screen extent holds a ray's row; a frame
// that would take more than 4·10⁹ such looks is refused in one line that names the fast
// sibling, before any ray is cast: here 2,000 triangles that each cover the whole 1920x1080
// picture (4.1·10⁹ looks).
TEST(Raycast, TheTextbookRefusesAFrameOfTooManyTestsAndNamesTheFastOne) {
  Scene scene;
  scene.beginObject("layers");
  const std::uint32_t m = scene.addMaterial({{0.5f, 0.6f, 0.7f}, 1.0f});
  constexpr int kLayers = 2000;
  for (int i = 0; i < kLayers; ++i) {
    const float z = -1.0f - 0.001f * static_cast<float>(i);
    scene.addPolygonVertices({{-4.0f, -4.0f, z}, {8.0f, -4.0f, z}, {-4.0f, 8.0f, z}}, m);
  }
  Camera camera;
  camera.eye = {0.0f, 0.0f, 1.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  camera.width = 1920;
  camera.height = 1080;
  RenderOptions o;
  o.algorithm = "raycast-textbook";
  try {
    (void)render(scene, camera, o);
    ADD_FAILURE() << "1920x1080 rays x 2,000 full-screen triangles drawn";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("draw it with raycast"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  // The same frame smaller is drawn, and is the fast sibling's
  camera.width = 40;
  camera.height = 30;
  const Frame textbook = render(scene, camera, o);
  o.algorithm = "raycast";
  const Frame fast = render(scene, camera, o);
  EXPECT_EQ(textbook.ids, fast.ids);
  EXPECT_EQ(textbook.ids.front(), 0u) << "the nearest layer, the first submitted";
}

}  // namespace
}  // namespace hsr
