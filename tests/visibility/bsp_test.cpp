// The 3D BSP tree (bsp_tree.cpp), rendering from it (bsp.cpp) and its file (io/bsp_file.cpp).
// docs/testing.md row 11, BSP split consistency: every polygon of the tree lies in its node's
// plane, on the right side of every ancestor's plane; a split polygon's pieces add up to it;
// and every way of choosing splitters gives the same picture (different trees, one answer).
// Pictures are measured against the z-buffer as the painter's are
// (cross/compare_with_zbuffer.hpp: no clearly wrong pixel, ties aside).

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>

#include "cross/compare_with_zbuffer.hpp"
#include "cross/random_scenes.hpp"
#include "hsr/bsp.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"
#include "visibility/bsp.hpp"
#include "visibility/bsp_tree.hpp"

namespace hsr {
namespace {

using detail::BspTree;
using testing::compareWithZBuffer;
using testing::Comparison;
using testing::describe;

const char* const kSplitters[] = {"first", "random", "fewest", "balanced", "best-of-k"};

double area(const std::vector<glm::dvec3>& v) {
  glm::dvec3 n(0.0);
  for (std::size_t i = 0; i < v.size(); ++i) n += glm::cross(v[i], v[(i + 1) % v.size()]);
  return 0.5 * glm::length(n);
}

// The largest distance of a vertex from the polygon's own plane (Newell's normal through the
// centroid).
double nonPlanarity(const std::vector<glm::dvec3>& v) {
  glm::dvec3 n(0.0), c(0.0);
  for (std::size_t i = 0; i < v.size(); ++i) {
    const glm::dvec3 &a = v[i], &b = v[(i + 1) % v.size()];
    n +=
        glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    c += a;
  }
  n = glm::normalize(n);
  c /= static_cast<double>(v.size());
  double worst = 0;
  for (const glm::dvec3& p : v) worst = std::max(worst, std::abs(glm::dot(n, p - c)));
  return worst;
}

// Row 11: each polygon lies in its node's plane and on its side of every ancestor's plane,
// within the tree's epsilon; the pieces of every scene polygon add up to its area.
void expectConsistent(const Scene& scene, const BspTree& tree) {
  // Walk down from the root with the path of (node, side) taken.
  struct Item {
    std::int32_t node;
    std::vector<std::pair<std::int32_t, int>> path;
  };
  std::vector<Item> stack{{0, {}}};
  std::map<std::pair<PolygonId, std::uint32_t>, double> piece_area;
  std::uint64_t checked = 0;
  while (!stack.empty() && !tree.nodes.empty()) {
    Item item = std::move(stack.back());
    stack.pop_back();
    const detail::BspNode& n = tree.nodes[item.node];
    for (std::uint32_t k = 0; k < n.polygon_count; ++k) {
      const detail::BspPolygon& p = tree.polygons[n.first_polygon + k];
      piece_area[{p.id, p.piece}] += area(p.vertices);
      // A polygon planar to float precision (the pipeline's test) may be the splitter of its
      // node (or its pieces may be) while its vertices stray from its plane by more than the
      // epsilon: they may stray as far as the scene polygon's vertices do from its plane.
      std::vector<glm::dvec3> whole;
      for (const std::uint32_t i : scene.polygon(p.id)) whole.emplace_back(scene.position(i));
      const double tolerance = 4 * tree.epsilon + nonPlanarity(whole);
      for (const glm::dvec3& v : p.vertices) {
        ASSERT_LE(std::abs(glm::dot(glm::dvec3(n.plane), v) + n.plane.w), tolerance)
            << "polygon " << p.id << " off its node's plane";
        for (const auto& [ancestor, side] : item.path) {
          const glm::dvec4& pl = tree.nodes[ancestor].plane;
          ASSERT_GE(side * (glm::dot(glm::dvec3(pl), v) + pl.w), -4 * tree.epsilon)
              << "polygon " << p.id << " on the wrong side of an ancestor's plane";
        }
        ++checked;
      }
    }
    for (const int side : {1, -1}) {
      const std::int32_t child = side > 0 ? n.front : n.back;
      if (child < 0) continue;
      Item next{child, item.path};
      next.path.emplace_back(item.node, side);
      stack.push_back(std::move(next));
    }
  }
  EXPECT_GT(checked, 0u);
  // Pieces add up to their polygon (planar polygons: piece 0 is the whole).
  for (const auto& [key, a] : piece_area) {
    if (key.second != 0) continue;
    std::vector<glm::dvec3> whole;
    for (const std::uint32_t i : scene.polygon(key.first)) whole.emplace_back(scene.position(i));
    const double expected = area(whole);
    if (expected > 0 && scene.polygon(key.first).size() == 3) {
      EXPECT_NEAR(a, expected, 1e-9 * expected + 1e-12) << "pieces of polygon " << key.first;
    }
  }
}

TEST(Bsp, TreesAreConsistentForEverySplitterChoice) {
  for (const char* name : {"cyclic", "penetrating", "demo", "soup:400:3"}) {
    SCOPED_TRACE(name);
    const Scene scene = makeBuiltinScene(name);
    for (const char* splitter : kSplitters) {
      SCOPED_TRACE(splitter);
      const BspTree tree = detail::buildBspTree(scene, {.splitter = splitter, .seed = 7});
      EXPECT_EQ(tree.stats.polygons, tree.polygons.size());
      EXPECT_EQ(tree.stats.polygons, tree.stats.input_polygons + tree.stats.splits);
      expectConsistent(scene, tree);
    }
  }
  // The notes' case that needs splits: the crossing quads.
  EXPECT_GT(detail::buildBspTree(makeBuiltinScene("penetrating"), {}).stats.splits, 0u);
}

TEST(Bsp, UnknownSplitterOrCandidatesAreRefused) {
  const Scene scene = makeBuiltinScene("cyclic");
  EXPECT_THROW(buildBsp(scene, {.splitter = "greedy"}), Error);
  EXPECT_THROW(buildBsp(scene, {.candidates = 0}), Error);
  RenderOptions o;
  o.algorithm = "bsp";
  o.bsp.splitter = "nope";
  EXPECT_THROW(render(scene, frameScene(scene, 32, 32), o), Error);
}

// The notes' cases (cyclic overlap, interpenetration) and the demo: every splitter choice
// builds another tree, and every one paints the z-buffer's picture.
TEST(Bsp, EverySplitterChoicePaintsTheZBuffersPicture) {
  for (const char* spec : {"cyclic", "penetrating", "demo", "soup:400:3"}) {
    SCOPED_TRACE(spec);
    const Scene scene = loadScene(spec);
    const Camera camera = frameScene(scene, 320, 240);
    for (const char* splitter : kSplitters) {
      SCOPED_TRACE(splitter);
      RenderOptions o;
      o.bsp.splitter = splitter;
      o.bsp.seed = 3;
      const Comparison c = compareWithZBuffer(scene, camera, "bsp", o);
      EXPECT_EQ(c.wrong, 0u) << c.first_wrong;
      EXPECT_EQ(c.depth_differs_same_id, 0u);
      EXPECT_LE(c.ids_differ, c.drawn / 1000);
      if (std::string(splitter) == "balanced")
        testing::printFigures(std::string(spec) + " 320x240: bsp: " + describe(c));
    }
  }
}

// Seeded random scenes with interpenetrating pairs, cyclic overlaps and coplanar polygons.
TEST(Bsp, RandomScenesHaveNoClearlyWrongPixel) {
  std::uint64_t splits = 0;
  const Comparison total = testing::expectNoWrongPixelOnRandomScenes(
      "bsp", [&](const Scene& scene, const Camera&) { splits += buildBsp(scene).stats().splits; });
  EXPECT_GT(splits, 0u);
  testing::printFigures("bsp, " + std::to_string(60 * testing::countScale()) + " random scenes: " +
                        describe(total) + "; " + testing::grouped(splits) + " splits");
}

// The real models of the Mesa test: ids agree with the z-buffer's on at least 99.9% of the
// drawn pixels, and no pixel is clearly wrong.
TEST(Bsp, RealModelsAgreeWithTheZBuffer) {
  // One tree per model for both renders (models told apart by name and size).
  std::string built_for;
  std::optional<Bsp> bsp;
  testing::expectRealModelsAgreeWithTheZBuffer(
      "bsp",
      [&](const Scene& scene, const Camera& camera, const RenderOptions& o) {
        const std::string key = scene.name + "/" + std::to_string(scene.polygonCount()) + "/" +
                                std::to_string(scene.vertexCount());
        if (!bsp || built_for != key) bsp.emplace(buildBsp(scene)), built_for = key;
        return render(*bsp, camera, o);
      },
      [](const Frame&) { return std::string(); });
}

// The notes' traversal: front to back is back to front reversed (no plane holds the eye), and
// from another side of a plane the order changes; subtrees outside the frustum are skipped.
TEST(Bsp, TraversalOrderFollowsTheEye) {
  const Scene scene = makeBuiltinScene("demo");
  const Bsp bsp = buildBsp(scene);
  Camera camera = frameScene(scene, 320, 240);
  std::vector<std::pair<PolygonId, std::uint32_t>> back_to_front, front_to_back;
  auto record = [](auto& into) {
    return [&into](const detail::BspPolygon& p, std::uint32_t) {
      into.emplace_back(p.id, p.first_cut);
    };
  };
  detail::forEachBspPolygon(bsp.tree(), camera, false, record(back_to_front));
  detail::forEachBspPolygon(bsp.tree(), camera, true, record(front_to_back));
  ASSERT_EQ(back_to_front.size(), bsp.stats().polygons);
  std::reverse(front_to_back.begin(), front_to_back.end());
  EXPECT_EQ(back_to_front, front_to_back);
  // The public face of the same: ids in drawing order, either way.
  std::vector<PolygonId> ids = bspOrder(bsp, camera), reversed = bspOrder(bsp, camera, true);
  ASSERT_EQ(ids.size(), back_to_front.size());
  for (std::size_t k = 0; k < ids.size(); ++k) EXPECT_EQ(ids[k], back_to_front[k].first);
  std::reverse(reversed.begin(), reversed.end());
  EXPECT_EQ(ids, reversed);

  // The eye on the other side of the scene: another order, the same picture as the z-buffer.
  camera.eye = camera.target - (camera.eye - camera.target);
  std::vector<std::pair<PolygonId, std::uint32_t>> other;
  detail::forEachBspPolygon(bsp.tree(), camera, false, record(other));
  EXPECT_NE(other, back_to_front);
  EXPECT_EQ(compareWithZBuffer(scene, camera, "bsp").wrong, 0u);

  // Looking at a corner of the scene from close by: whole subtrees lie outside the frustum.
  const Scene spheres = makeBuiltinScene("spheres:2000");
  const Bsp many = buildBsp(spheres);
  Camera close = frameScene(spheres, 320, 240);
  close.fov_deg = 10.0f;
  detail::BspTraversalStats stats;
  detail::forEachBspPolygon(
      many.tree(), close, false, [](const detail::BspPolygon&, std::uint32_t) {}, &stats);
  EXPECT_GT(stats.skipped, 0u);
  EXPECT_LT(stats.drawn, many.stats().polygons);
  EXPECT_EQ(compareWithZBuffer(spheres, close, "bsp").wrong, 0u);
}

// One tree, every viewpoint: saved, loaded and rendered from several eyes, it paints what a
// tree built for each render paints, bit for bit, with the same statistics.
TEST(Bsp, SavedTreeRendersEveryViewAsABuiltOne) {
  const testing::ScratchDir scratch("hsr_bsp_test");
  const Scene scene = makeBuiltinScene("demo");
  const BspOptions options{.splitter = "fewest"};
  const Bsp built = buildBsp(scene, options);
  const std::filesystem::path file = scratch.path() / "demo.bsp";
  saveBsp(built, file);
  const Bsp loaded = loadBsp(file);
  EXPECT_EQ(loaded.options().splitter, "fewest");
  EXPECT_EQ(loaded.stats().nodes, built.stats().nodes);
  EXPECT_EQ(loaded.stats().splits, built.stats().splits);
  EXPECT_EQ(loaded.stats().depth, built.stats().depth);
  EXPECT_EQ(loaded.stats().balance, built.stats().balance);
  EXPECT_EQ(loaded.epsilon(), built.epsilon());
  EXPECT_EQ(loaded.scene().polygonCount(), scene.polygonCount());
  const Camera base = frameScene(scene, 160, 120);
  for (int view = 0; view < 6; ++view) {
    SCOPED_TRACE(view);
    Camera camera = base;
    const float a = 1.047f * static_cast<float>(view);
    const glm::vec3 d = base.eye - base.target;
    camera.eye = base.target + glm::vec3(std::cos(a) * d.x + std::sin(a) * d.z, d.y,
                                         -std::sin(a) * d.x + std::cos(a) * d.z);
    RenderOptions o;
    o.algorithm = "bsp";
    o.bsp = options;
    const Frame fresh = render(scene, camera, o);
    const Frame from_file = render(loaded, camera);
    EXPECT_EQ(from_file.ids, fresh.ids);
    EXPECT_EQ(from_file.depth, fresh.depth);
    EXPECT_EQ(from_file.color, fresh.color);
    // Against the z-buffer, no pixel in a thousand differs. Not none: from some of these
    // eyes a polygon is seen nearly edge-on, its depth changing by 0.03 a pixel, and along
    // the edge it shares with a neighbour the snapped outline (1/256 pixel) decides which of
    // the two covers a pixel centre the exact order puts on the other.
    const Comparison c = compareWithZBuffer(scene, camera, "bsp", o);
    EXPECT_LE(c.ids_differ, c.drawn / 1000) << c.first_wrong;
  }
}

// Where the indices lie in a saved tree's payload (src/visibility/bsp_file.cpp's layout, read here
// on its own): the first polygon's material and first vertex, node 0's front child, the first tree
// polygon's id and its first cut's node; with the length of each one's table.
struct IndexFields {
  std::size_t material = 0, vertex = 0, child = 0, tree_polygon_id = 0, cut_node = 0;
  std::uint32_t materials = 0, object_vertices = 0, nodes = 0, scene_polygons = 0;
};
IndexFields indexFieldsOf(const std::string& p) {
  std::size_t at = 0;
  const auto u32 = [&] {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
      v |= static_cast<std::uint32_t>(static_cast<unsigned char>(p.at(at + i))) << (8 * i);
    at += 4;
    return v;
  };
  const auto skip = [&](std::size_t n) { at += n; };
  const auto str = [&] { skip(u32()); };
  IndexFields f;
  str();                    // splitter
  skip(8 + 4 + 8 + 8 + 8);  // seed, candidates, input polygons, splits, build ms
  skip(8);                  // epsilon
  str();                    // scene name
  f.materials = u32();
  skip(16 * std::size_t{f.materials});
  const bool camera = p.at(at) != 0;
  skip(1);
  if (camera) skip(9 * 4 + 4 + 1 + 4 + 4 + 4);
  const std::uint32_t objects = u32();
  bool first_polygon = true;
  for (std::uint32_t o = 0; o < objects; ++o) {
    str();
    const std::uint32_t vertices = u32();
    skip(12 * std::size_t{vertices});
    const std::uint32_t polygons = u32();
    f.scene_polygons += polygons;
    for (std::uint32_t k = 0; k < polygons; ++k) {
      if (first_polygon) f.material = at, f.vertex = at + 8, f.object_vertices = vertices;
      skip(4);
      const std::uint32_t n = u32();
      skip(4 * std::size_t{n});
      first_polygon = false;
    }
  }
  f.nodes = u32();
  EXPECT_GE(f.nodes, 2u) << "the tree has no child to forge";
  f.child = at + 32 + 8;  // node 0: plane (4 doubles), first polygon, count, then front
  skip(48 * std::size_t{f.nodes});
  const std::uint32_t tree_polygons = u32();
  bool found_cut = false;
  for (std::uint32_t i = 0; i < tree_polygons; ++i) {
    if (i == 0) f.tree_polygon_id = at;
    skip(8);
    const std::uint32_t cuts = u32();
    if (cuts > 0 && !found_cut) f.cut_node = at, found_cut = true;
    skip(5 * std::size_t{cuts});
    skip(24 * std::size_t{u32()});
  }
  EXPECT_TRUE(found_cut) << "no tree polygon was cut: no cut to forge";
  EXPECT_EQ(at, p.size()) << "the payload's layout is not the one this test reads";
  return f;
}

// A file that is not one saveBsp wrote is refused with one line naming it: truncated, a byte
// flipped, another magic or version, and hostile files whose checksum is right but whose
// contents lie (a count beyond the file, a child that makes a loop, an id out of range).
TEST(Bsp, DamagedOrHostileFilesAreRefusedWithOneLine) {
  const testing::ScratchDir scratch("hsr_bsp_test");
  const std::filesystem::path good = scratch.path() / "good.bsp";
  saveBsp(buildBsp(makeBuiltinScene("penetrating")), good);
  std::string bytes;
  {
    std::ifstream in(good, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  ASSERT_GT(bytes.size(), 100u);
  auto refused = [&](const std::string& content, const std::string& expect) {
    const std::filesystem::path bad = scratch.path() / "bad.bsp";
    std::ofstream(bad, std::ios::binary | std::ios::trunc) << content;
    try {
      loadBsp(bad);
      ADD_FAILURE() << "accepted; expected: " << expect;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(bad.string()), std::string::npos) << what;
      EXPECT_NE(what.find(expect), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  };
  // With the payload changed and its checksum made right again.
  auto forged = [&](std::string payload) {
    std::string out = bytes.substr(0, 24);
    const std::uint32_t crc = static_cast<std::uint32_t>(crc32_z(
        crc32_z(0, nullptr, 0), reinterpret_cast<const Bytef*>(payload.data()), payload.size()));
    for (int i = 0; i < 4; ++i) out[12 + i] = static_cast<char>(crc >> (8 * i));
    const std::uint64_t size = payload.size();
    for (int i = 0; i < 8; ++i) out[16 + i] = static_cast<char>(size >> (8 * i));
    return out + payload;
  };
  refused("", "not an hsr BSP file");
  refused("P3\n1 1\n255\n", "not an hsr BSP file");
  for (const std::size_t keep :
       {std::size_t{8}, std::size_t{30}, bytes.size() / 2, bytes.size() - 1})
    refused(bytes.substr(0, keep), keep < 24 ? "not an hsr BSP file" : "truncated");
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  refused(flipped, "checksum mismatch");
  std::string version = bytes;
  version[8] = 2;
  refused(version, "version 2");
  const std::string payload = bytes.substr(24);
  refused(forged(payload.substr(0, payload.size() - 3)), "more bytes than the file has left");
  refused(forged(payload + "x"), "bytes after the tree");
  // The splitter name's length: 4 GiB asked of a small file.
  std::string huge = payload;
  for (int i = 0; i < 4; ++i) huge[i] = '\xff';
  refused(forged(huge), "more bytes than the file has left");
  // Every index the format holds, set to its table's length (the first value past the end: a
  // check written with > in place of >= would read it), is refused with a line naming it.
  const IndexFields at = indexFieldsOf(payload);
  const auto withU32 = [&](std::size_t offset, std::uint32_t v) {
    std::string p = payload;
    for (int i = 0; i < 4; ++i) p[offset + i] = static_cast<char>(v >> (8 * i));
    return forged(p);
  };
  refused(withU32(at.material, at.materials),
          "uses material " + std::to_string(at.materials) + " of");
  refused(withU32(at.vertex, at.object_vertices),
          "uses vertex " + std::to_string(at.object_vertices) + " of an object with");
  refused(withU32(at.child, at.nodes), "names child " + std::to_string(at.nodes));
  refused(withU32(at.tree_polygon_id, at.scene_polygons),
          "names polygon " + std::to_string(at.scene_polygons));
  refused(withU32(at.cut_node, at.nodes), "has a cut by no node");
  // Every byte of the payload changed in turn (the checksum forged): refused or loaded, never
  // a crash; what loads renders.
  std::uint64_t loaded = 0;
  for (std::size_t i = 0; i < payload.size(); i += 3) {
    std::string p = payload;
    p[i] = static_cast<char>(p[i] ^ 0xA5);
    const std::filesystem::path bad = scratch.path() / "mutant.bsp";
    std::ofstream(bad, std::ios::binary | std::ios::trunc) << forged(p);
    try {
      const Bsp bsp = loadBsp(bad);
      render(bsp, frameScene(bsp.scene(), 32, 24));
      ++loaded;
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  }
  testing::printFigures("bsp files: " + std::to_string(payload.size() / 3 + 1) +
                        " single-byte mutants of a " + std::to_string(bytes.size()) +
                        "-byte file, " + std::to_string(loaded) +
                        " loaded and rendered, the rest refused with one line");
}

}  // namespace
}  // namespace hsr
