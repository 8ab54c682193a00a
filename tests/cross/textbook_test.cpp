// The textbook pairs of the registry (hsr/algorithms.hpp): an algorithm written as the notes
// teach it (`textbook`) and its sibling reorganised for speed draw the same frame bit for bit.
// One suite over the table: every entry marked textbook is rendered beside its sibling on the
// built-in scenes, the agreement scenes (tests/cross/random_scenes.hpp), the same scenes with
// every third material made glass, and real models, in every render state both take, at one
// thread and at two (and the A-buffer at 1, 4 and 8 samples); ids, depth bits, colours and
// coverage must be equal at every pixel, and the fragment counts too, but for the A-buffer,
// whose fast sibling never lists a fragment hidden behind a whole-pixel polygon (its overdraw
// counts the fragments kept, the textbook's every fragment listed).

#include <gtest/gtest.h>

#include <bit>
#include <filesystem>
#include <string>
#include <vector>

#include "cross/figures.hpp"
#include "cross/random_scenes.hpp"
#include <glm/vec3.hpp>

#include "hsr/algorithms.hpp"
#include "hsr/camera.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

std::vector<std::string> textbookEntries() {
  std::vector<std::string> names;
  for (const AlgorithmInfo& a : algorithms())
    if (a.textbook) names.emplace_back(a.name);
  return names;
}

// What the pair is compared on: the first pixel that differs, and how many do.
struct Difference {
  std::uint64_t pixels = 0;
  std::string first;
};

Difference compareFrames(const Frame& a, const Frame& b, bool overdraw) {
  Difference d;
  if (a.width != b.width || a.height != b.height || a.coverage.size() != b.coverage.size()) {
    d.pixels = ~0ull;
    d.first = "the frames differ in size or in having coverage";
    return d;
  }
  for (std::size_t k = 0; k < a.ids.size(); ++k) {
    const char* what =
        a.ids[k] != b.ids[k]       ? "id"
        : a.color[k] != b.color[k] ? "colour"
        : std::bit_cast<std::uint32_t>(a.depth[k]) != std::bit_cast<std::uint32_t>(b.depth[k])
            ? "depth"
        : !a.coverage.empty() && std::bit_cast<std::uint32_t>(a.coverage[k]) !=
                                     std::bit_cast<std::uint32_t>(b.coverage[k])
            ? "coverage"
        : overdraw && a.overdraw[k] != b.overdraw[k] ? "overdraw"
                                                     : nullptr;
    if (!what) continue;
    if (d.pixels++ == 0)
      d.first = std::string(what) + " at (" + std::to_string(k % a.width) + ", " +
                std::to_string(k / a.width) + ")";
  }
  return d;
}

// The render states a pair is compared in: the default and each one both take.
std::vector<RenderOptions> statesFor(const AlgorithmInfo& info) {
  std::vector<RenderOptions> states(1);
  if (info.has(kOutline)) states.emplace_back().outline = true;
  if (info.has(kDepthFuncs)) {
    states.emplace_back().depth_func = DepthFunc::LEqual;
    states.back().cull = CullMode::Back;
    states.emplace_back().depth_func = DepthFunc::Greater;
    states.back().clear_depth = 0.0f;
    states.emplace_back().depth_test = false;
  }
  if (info.has(kDepthMask)) states.emplace_back().depth_mask = false;
  if (info.has(kPolygonModes)) {
    states.emplace_back().polygon_mode = PolygonMode::Line;
    states.emplace_back().polygon_mode = PolygonMode::Point;
  }
  std::vector<RenderOptions> out;
  for (const RenderOptions& s : states) {
    if (info.has(kAntialiasing)) {
      for (const int samples : {1, 4, 8}) {
        out.push_back(s);
        out.back().samples = samples;
      }
    } else {
      out.push_back(s);
    }
  }
  return out;
}

struct PairTally {
  std::uint64_t renders = 0, pixels = 0, drawn = 0, differ = 0;
};

// The textbook entry `name` and its sibling on one scene, in every state, at 1 and 2 threads.
void expectPairAgrees(const std::string& name, const Scene& scene, const Camera& camera,
                      const std::string& what, PairTally& t, bool every_state = true) {
  const AlgorithmInfo& textbook = findAlgorithm(name);
  const AlgorithmInfo& fast = findAlgorithm(textbook.sibling);
  const bool overdraw = !textbook.has(kAntialiasing);
  const std::vector<RenderOptions> states = statesFor(textbook);
  // Rendered into again from state to state and scene to scene (no fresh memory per render:
  // under the sanitizers every buffer over 128 KiB is mapped and faulted in afresh)
  thread_local Frame want, got;
  for (std::size_t s = 0; s < states.size(); ++s) {
    if (!every_state && s > 0 && states[s].samples == states[0].samples) continue;
    RenderOptions o = states[s];
    o.algorithm = name;
    o.threads = 1;
    if (!unsupported(textbook, camera, o).empty()) continue;
    render(scene, camera, o, want);
    for (const int threads : {1, 2}) {
      RenderOptions f = o;
      f.algorithm = std::string(fast.name);
      f.threads = threads;
      ASSERT_EQ(unsupported(fast, camera, f), "") << what;
      render(scene, camera, f, got);
      const Difference d = compareFrames(want, got, overdraw);
      EXPECT_EQ(d.pixels, 0u) << name << " against " << fast.name << " on " << what << ", state "
                              << s << " (samples " << o.samples << "), " << threads
                              << " threads: " << d.pixels << " pixels differ, the first "
                              << d.first;
      t.renders++;
      t.pixels += want.ids.size();
      t.differ += d.pixels;
      for (const PolygonId id : want.ids) t.drawn += id != kNoPolygon;
    }
  }
}

// Every third material glass (alpha 0.5), so that blending is compared on random overlaps.
Scene withGlass(Scene scene) {
  for (std::size_t m = 0; m < scene.materials.size(); m += 3) scene.materials[m].alpha = 0.5f;
  return scene;
}

class TextbookPair : public ::testing::TestWithParam<std::string> {};

TEST_P(TextbookPair, NamesItsSiblingAndTheSiblingNamesIt) {
  const AlgorithmInfo& textbook = findAlgorithm(GetParam());
  ASSERT_FALSE(textbook.sibling.empty());
  const AlgorithmInfo& fast = findAlgorithm(textbook.sibling);
  EXPECT_FALSE(fast.textbook) << "a pair has one textbook entry";
  EXPECT_EQ(fast.sibling, textbook.name);
  EXPECT_TRUE(textbook.has(kExplain)) << "the textbook file is the one hsr explain walks";
  // The same promises, but for explaining: the fast sibling may leave that to the textbook one
  EXPECT_EQ(fast.capabilities & ~kExplain, textbook.capabilities & ~kExplain);
  EXPECT_EQ(fast.precision, textbook.precision);
  EXPECT_EQ(fast.input, textbook.input);
  EXPECT_FALSE(fast.demonstration || textbook.demonstration);
}

TEST_P(TextbookPair, DrawsItsSiblingsFrameOnTheBuiltinScenes) {
  PairTally t;
  for (const char* spec : {"demo", "solids", "cyclic", "penetrating", "spheres:2000", "soup:400"}) {
    const Scene scene = makeBuiltinScene(spec);
    expectPairAgrees(GetParam(), scene, frameScene(scene, 200, 150), spec, t);
  }
  EXPECT_GT(t.drawn, t.pixels / 20) << "the scenes draw something";
}

TEST_P(TextbookPair, DrawsItsSiblingsFrameOnTheAgreementScenes) {
  PairTally t;
  const int scenes = testing::legCases(24 * testing::countScale(), 3);
  for (int i = 0; i < scenes; ++i) {
    const std::uint64_t seed = 1 + static_cast<std::uint64_t>(i);
    const Scene scene = testing::agreementScene(seed);
    const Camera camera = testing::agreementCamera(seed, 160, 160);
    expectPairAgrees(GetParam(), scene, camera, "agreement scene " + std::to_string(seed), t,
                     seed % 4 == 1);
    if (findAlgorithm(GetParam()).has(kTransparency))
      expectPairAgrees(GetParam(), withGlass(scene), camera,
                       "agreement scene " + std::to_string(seed) + " with glass", t, false);
  }
  testing::printFigures(GetParam() + ": " + std::to_string(t.renders) + " renders beside " +
                        std::string(findAlgorithm(GetParam()).sibling) + ", " +
                        std::to_string(t.pixels) + " pixels, " + std::to_string(t.differ) +
                        " differ");
  EXPECT_GT(t.drawn, t.pixels / 10);
}

TEST_P(TextbookPair, DrawsItsSiblingsFrameOnRealModels) {
  for (const char* model : {"OBJ/spider.obj", "PLY/Wuson.ply",
                            "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"}) {
    PairTally t;
    const Scene scene = loadScene((std::filesystem::path(HSR_TEST_MODELS) / model).string());
    expectPairAgrees(GetParam(), scene, frameScene(scene, 160, 120), model, t, false);
    EXPECT_GT(t.drawn, t.pixels / 50) << model << " draws something";
  }
}

// Far from the origin, where a float step is a large share of a pixel, and in parallel
// projection, whose rays start on the near plane rounded to float: wherever the textbook file
// saves work (the ray caster's screen extents), it must still find what its sibling finds.
TEST_P(TextbookPair, DrawsItsSiblingsFrameFarFromTheOriginAndInParallelProjection) {
  for (const glm::vec3 centre : {glm::vec3(0.0f), glm::vec3(148376.0f, 1234.0f, -223423.0f)}) {
    Scene scene;
    testing::Rng rng(11);
    scene.beginObject("triangles");
    const std::uint32_t m = scene.addMaterial({{0.7f, 0.5f, 0.3f}, 1.0f});
    auto near = [&](const glm::vec3& c, float r) {
      return c + r * glm::vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    };
    for (int i = 0; i < 300; ++i) {
      const glm::vec3 c = near(centre, 1.0f);
      scene.addPolygonVertices({near(c, 0.3f), near(c, 0.3f), near(c, 0.3f)}, m);
    }
    for (const bool ortho : {false, true}) {
      PairTally t;
      Camera camera = frameScene(scene, 160, 120);
      camera.ortho = ortho;
      camera.ortho_half_height = 1.5f;
      const std::string what = std::string(ortho ? "parallel" : "perspective") + " view of " +
                               "300 triangles at (" + std::to_string(centre.x) + ", " +
                               std::to_string(centre.y) + ", " + std::to_string(centre.z) + ")";
      expectPairAgrees(GetParam(), scene, camera, what, t, false);
      EXPECT_GT(t.drawn, t.pixels / 10) << what;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(, TextbookPair, ::testing::ValuesIn(textbookEntries()),
                         testing::testNameOf);

TEST(TextbookPairs, EveryBigImageAlgorithmHasOne) {
  // The notes' image-precision algorithms whose fast machinery would hide the algorithm
  for (const char* name : {"zbuffer", "scanline", "raycast", "abuffer"}) {
    const AlgorithmInfo& a = findAlgorithm(name);
    ASSERT_FALSE(a.sibling.empty()) << name;
    EXPECT_TRUE(findAlgorithm(a.sibling).textbook) << name;
  }
  for (const AlgorithmInfo& a : algorithms()) {
    if (!a.sibling.empty()) {
      EXPECT_EQ(findAlgorithm(a.sibling).sibling, a.name);
    }
  }
}

}  // namespace
}  // namespace hsr
