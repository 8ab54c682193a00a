// The pipeline's second product (clipped window polygons with their planes) filled through the
// shared routine (raster/fill_polygons) is what the object-precision algorithms will draw
// their answers with. Filled whole, in submission order, with the z-buffer's depth test, it
// must give the z-buffer's frame: the same pixels, ids and depths, so that those algorithms
// are compared with the rest on ids, through the same edge setup and depth definition.

#include <gtest/gtest.h>

#include <bit>

#include "core/frame.hpp"
#include "cross/figures.hpp"
#include "cross/random_scenes.hpp"
#include "hsr/clipping.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "pipeline/pipeline.hpp"
#include "raster/fill_polygons.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

// The window polygons of the scene filled in id order, opaque ones first (as the z-buffer
// draws), with LESS.
Frame fillWindowPolygons(const Scene& scene, const Camera& camera, const RenderOptions& o) {
  const detail::PreparedScene ps = detail::prepare(scene, camera, o, {.window_polygons = true});
  Frame f;
  detail::clearFrame(f, camera.width, camera.height, o);
  const detail::FrameView fb(f);
  detail::FragmentCounts counts;
  for (const bool transparent : {false, true})
    for (const detail::WindowPolygon& p : ps.polygons)
      if (p.transparent == transparent)
        detail::fillPolygon(p, fb, detail::effectiveDepthFunc(o), detail::depthWrites(o), counts);
  return f;
}

struct Diff {
  std::uint64_t pixels = 0, ids = 0, depth = 0, colour = 0;
};

Diff compare(const Frame& a, const Frame& b) {
  Diff d;
  for (std::size_t k = 0; k < a.ids.size(); ++k) {
    d.pixels++;
    d.ids += a.ids[k] != b.ids[k];
    d.colour += a.color[k] != b.color[k];
    d.depth += std::bit_cast<std::uint32_t>(a.depth[k]) != std::bit_cast<std::uint32_t>(b.depth[k]);
  }
  return d;
}

TEST(FillPolygons, WindowPolygonsFilledInOrderAreTheZBufferFrame) {
  Diff total;
  const int scenes = 100 * testing::countScale();
  for (int i = 0; i < scenes; ++i) {
    const std::uint64_t seed = 1 + static_cast<std::uint64_t>(i);
    const Scene scene = testing::agreementScene(seed);
    const Camera camera = testing::agreementCamera(seed);
    RenderOptions o;
    o.cull = i % 3 == 0 ? CullMode::Back : CullMode::None;
    const Diff d = compare(render(scene, camera, o), fillWindowPolygons(scene, camera, o));
    EXPECT_EQ(d.ids + d.depth + d.colour, 0u)
        << "scene " << seed << ": " << d.ids << " ids, " << d.depth << " depths differ";
    total.pixels += d.pixels;
    total.ids += d.ids;
    total.depth += d.depth;
  }
  for (const char* spec : {"demo", "cyclic", "penetrating", "soup:2000:3"}) {
    const Scene scene = loadScene(spec);
    const Camera camera = frameScene(scene, 320, 240);
    const Diff d = compare(render(scene, camera, {}), fillWindowPolygons(scene, camera, {}));
    EXPECT_EQ(d.ids + d.depth + d.colour, 0u) << spec;
    total.pixels += d.pixels;
  }
  testing::printFigures("window polygons filled whole vs the z-buffer: " +
                        testing::grouped(total.pixels) + " pixels, " + testing::grouped(total.ids) +
                        " ids and " + testing::grouped(total.depth) + " depths differ");
}

// The Weiler-Atherton algorithm's pieces are exact regions on the sub-pixel grid, painted by
// paintExactRegion: a whole polygon's snapped outline, painted so, must cover exactly the pixels
// fillPolygon's triangles cover (the fill rule's ownership of centres on edges included) and
// write the same depths. Each polygon painted over the last with no depth test, in both frames:
// the same fragment count per polygon and the same final frame.
TEST(FillPolygons, ExactRegionsPaintWhatTheFillRuleCovers) {
  std::uint64_t polygons = 0, fragments = 0, differ = 0;
  auto check = [&](const Scene& scene, const Camera& camera, const RenderOptions& o,
                   const std::string& what) {
    const detail::PreparedScene ps = detail::prepare(scene, camera, o, {.window_polygons = true});
    Frame a, b;
    detail::clearFrame(a, camera.width, camera.height, o);
    detail::clearFrame(b, camera.width, camera.height, o);
    const detail::FrameView fa(a), fb(b);
    for (const detail::WindowPolygon& p : ps.polygons) {
      GridRing ring;
      for (const glm::dvec3& v : p.vertices)
        ring.push_back(
            {std::llrint(v.x * detail::kSubpixelOne), std::llrint(v.y * detail::kSubpixelOne)});
      const GridRegion region{{ring, {}}};
      if (!invalidRegionReason(region).empty()) continue;  // zero area or folded on the grid
      detail::FragmentCounts ca, cb;
      detail::fillPolygon(p, fa, DepthFunc::Always, true, ca);
      const std::size_t painted =
          detail::paintExactRegion(exactRegion(region), p.depth, p.id, p.rgba, fb, cb);
      polygons++, fragments += painted;
      if (ca.written != painted && differ++ < 5)
        ADD_FAILURE() << what << " polygon " << p.id << ": fillPolygon " << ca.written
                      << " fragments, paintExactRegion " << painted;
    }
    const Diff d = compare(a, b);
    EXPECT_EQ(d.ids + d.depth + d.colour, 0u)
        << what << ": " << d.ids << " ids, " << d.depth << " depths differ";
  };
  // Vertices on pixel centres and half-way between them: edges, horizontal ones included, run
  // through centres, where only the fill rule decides.
  {
    testing::Rng rng(7);
    Frame a, b;
    detail::clearFrame(a, 24, 20, {});
    detail::clearFrame(b, 24, 20, {});
    const detail::FrameView fa(a), fb(b);
    for (int i = 0; i < 3000; ++i) {
      auto coordinate = [&](int size) {
        return static_cast<double>(rng.next() % static_cast<std::uint64_t>(2 * size + 1)) / 2 - 0.5;
      };
      std::vector<glm::dvec2> xy;
      if (i % 3 == 0) {  // an axis-aligned rectangle
        const double x0 = coordinate(24), x1 = coordinate(24), y0 = coordinate(20),
                     y1 = coordinate(20);
        xy = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
      } else {
        for (int k = 0; k < 3; ++k) xy.emplace_back(coordinate(24), coordinate(20));
      }
      GridRing ring;
      for (const glm::dvec2& v : xy)
        ring.push_back(
            {std::llrint(v.x * detail::kSubpixelOne), std::llrint(v.y * detail::kSubpixelOne)});
      const GridRegion region{{ring, {}}};
      if (!invalidRegionReason(region).empty()) continue;
      const detail::DepthPlane plane{0.001, -0.002, 0.5};
      detail::FragmentCounts ca, cb;
      const auto id = static_cast<PolygonId>(i);
      detail::fillPolygon(xy, plane, id, 0xff000000u | static_cast<std::uint32_t>(i), fa,
                          DepthFunc::Always, true, ca);
      const std::size_t painted = detail::paintExactRegion(
          exactRegion(region), plane, id, 0xff000000u | static_cast<std::uint32_t>(i), fb, cb);
      polygons++, fragments += painted;
      if (ca.written != painted && differ++ < 5)
        ADD_FAILURE() << "polygon on centres " << i << ": fillPolygon " << ca.written
                      << " fragments, paintExactRegion " << painted;
    }
    const Diff d = compare(a, b);
    EXPECT_EQ(d.ids + d.depth + d.colour, 0u) << "polygons on centres: " << d.ids << " ids differ";
  }
  for (int i = 0; i < 30 * testing::countScale(); ++i) {
    const std::uint64_t seed = 1 + static_cast<std::uint64_t>(i);
    check(testing::agreementScene(seed), testing::agreementCamera(seed), {},
          "scene " + std::to_string(seed));
  }
  for (const char* spec : {"demo", "cyclic", "penetrating", "soup:2000:3"}) {
    const Scene scene = loadScene(spec);
    check(scene, frameScene(scene, 320, 240), {}, spec);
  }
  EXPECT_EQ(differ, 0u);
  testing::printFigures("exact regions painted vs the fill rule: " + testing::grouped(polygons) +
                        " polygons, " + testing::grouped(fragments) + " fragments, " +
                        testing::grouped(differ) + " polygons differ");
}

// Seen from inside (the near plane cuts many polygons), a polygon clipped whole and one cut
// into clipped triangles may snap the ends of their near-plane edges differently; everything
// else, and every depth where both draw the same polygon, is the same.
TEST(FillPolygons, NearPlaneClippedPolygonsDifferOnlyAlongTheirClipEdges) {
  std::uint64_t pixels = 0, ids = 0, depth_where_same_id = 0, clipped = 0;
  for (int i = 0; i < 20; ++i) {
    const std::uint64_t seed = 500 + static_cast<std::uint64_t>(i);
    const Scene scene = testing::agreementScene(seed);
    Camera camera = testing::agreementCamera(seed);
    camera.eye = glm::vec3(0.1f, 0.2f, 0.3f);
    camera.near = 0.05f;
    camera.fov_deg = 100.0f;
    const Frame z = render(scene, camera, {}), f = fillWindowPolygons(scene, camera, {});
    clipped += z.stats.clipped;
    for (std::size_t k = 0; k < z.ids.size(); ++k) {
      ++pixels;
      ids += z.ids[k] != f.ids[k];
      if (z.ids[k] == f.ids[k])
        depth_where_same_id +=
            std::bit_cast<std::uint32_t>(z.depth[k]) != std::bit_cast<std::uint32_t>(f.depth[k]);
    }
  }
  EXPECT_GT(clipped, 100u) << "the near plane should cut many triangles";
  EXPECT_EQ(depth_where_same_id, 0u);
  EXPECT_LE(ids, pixels / 1000);
  testing::printFigures("window polygons seen from inside: " + testing::grouped(clipped) +
                        " triangles clipped, " + testing::grouped(pixels) + " pixels, " +
                        testing::grouped(ids) + " ids differ, 0 depths where the ids agree");
}

}  // namespace
}  // namespace hsr
