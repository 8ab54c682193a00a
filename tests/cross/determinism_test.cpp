// Determinism, docs/testing.md row 17, for every algorithm: every scene is rendered 3 times with 1
// thread and 3 times with 2 threads, for 3 option sets (plain fill, outline on, back faces
// culled); the FNV-1a hashes of the colour, depth (bit patterns), id and overdraw buffers
// must be identical across all 6. The third render of each thread count reuses one long-lived
// Frame (so the memory kept from earlier, different scenes must not leak into the picture).
// Scenes: the row-4 random scenes, the built-ins, the real models under HSR_TEST_MODELS when
// present, and row 9's watertight UV sphere (200 x 200 segments far from the origin).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "cross/figures.hpp"
#include "cross/random_scenes.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"

namespace hsr {
namespace {

namespace fs = std::filesystem;

struct NamedScene {
  std::string name;
  Scene scene;
  Camera camera;
};

struct Hashes {
  std::uint64_t color, depth, ids, overdraw;
  bool operator==(const Hashes&) const = default;
};

Hashes hashFrame(const Frame& f) {
  return {testing::fnv1a64(f.color), testing::fnv1a64(f.depth), testing::fnv1a64(f.ids),
          testing::fnv1a64(f.overdraw)};
}

std::string differences(const Hashes& a, const Hashes& b) {
  std::string s;
  if (a.color != b.color) s += " colour";
  if (a.depth != b.depth) s += " depth";
  if (a.ids != b.ids) s += " ids";
  if (a.overdraw != b.overdraw) s += " overdraw";
  return s;
}

// Row 9's sphere: a closed UV sphere of `segments` x `segments` quads (triangles at the poles),
// radius 1000, centred far from the origin, where float positions are coarse.
Scene uvSphere(glm::vec3 centre, int segments) {
  Scene s;
  s.name = "uv sphere";
  const std::uint32_t m = s.addMaterial({{0.6f, 0.7f, 0.9f}, 1.0f});
  s.beginObject("sphere");
  constexpr double kPi = 3.14159265358979323846, kRadius = 1000.0;
  // Vertex rings from pole to pole, shared between neighbouring faces.
  s.addVertex(centre + glm::vec3(0, static_cast<float>(kRadius), 0));
  for (int i = 1; i < segments; ++i) {
    const double theta = kPi * i / segments;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2 * kPi * j / segments;
      s.addVertex(centre +
                  glm::vec3(static_cast<float>(kRadius * std::sin(theta) * std::cos(phi)),
                            static_cast<float>(kRadius * std::cos(theta)),
                            static_cast<float>(kRadius * std::sin(theta) * std::sin(phi))));
    }
  }
  s.addVertex(centre - glm::vec3(0, static_cast<float>(kRadius), 0));
  const std::uint32_t south = static_cast<std::uint32_t>(s.vertexCount() - 1);
  auto ring = [&](int i, int j) {  // ring i in 1..segments-1
    return static_cast<std::uint32_t>(1 + (i - 1) * segments + (j % segments));
  };
  for (int j = 0; j < segments; ++j) s.addPolygon({0u, ring(1, j + 1), ring(1, j)}, m);
  for (int i = 1; i + 1 < segments; ++i)
    for (int j = 0; j < segments; ++j)
      s.addPolygon({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1), ring(i + 1, j)}, m);
  for (int j = 0; j < segments; ++j)
    s.addPolygon({ring(segments - 1, j), ring(segments - 1, j + 1), south}, m);
  return s;
}

// Row-4 scenes: twenty, and two in the sanitizer leg's tier (testing::legCases), where row 9's
// sphere also has half the rings and segments and the two large built-ins a quarter of their
// triangles; every built-in scene and every model is kept.
const int kRandomScenes = testing::legCases(20, 10);
const int kSphereSegments = testing::legCases(200, 2);

std::vector<NamedScene> determinismScenes() {
  std::vector<NamedScene> out;
  const int random_scenes = kRandomScenes * testing::countScale();
  for (int i = 0; i < random_scenes; ++i) {
    const std::uint64_t seed = 1 + static_cast<std::uint64_t>(i);  // the first row-4 seeds
    out.push_back({"agreementScene(" + std::to_string(seed) + ")", testing::agreementScene(seed),
                   testing::agreementCamera(seed)});
  }
  // Odd sizes, so that the 64x64 tiles of the z-buffer are cut at the right and bottom.
  constexpr int kW = 301, kH = 227;
  // The two large built-ins at a quarter of their triangles in the sanitizer leg's tier
  const std::string spheres = "spheres:" + std::to_string(testing::legCases(2000, 4));
  const std::string soup = "soup:" + std::to_string(testing::legCases(3000, 4)) + ":7";
  for (const std::string& spec : {std::string("demo"), std::string("solids"), std::string("cyclic"),
                                  std::string("penetrating"), spheres, soup}) {
    Scene s = makeBuiltinScene(spec);
    const Camera c = frameScene(s, kW, kH);
    out.push_back({spec, std::move(s), c});
  }
  const fs::path models = HSR_TEST_MODELS;
  for (const char* f : {"OBJ/spider.obj", "PLY/Wuson.ply", "STL/Spider_binary.stl", "OFF/Cube.off",
                        "glTF2/BoxTextured-glTF/BoxTextured.gltf"}) {
    if (!fs::exists(models / f)) continue;
#ifdef HSR_SANITIZER_BUILD
    // The sanitizer leg's tier: Wuson and the spider again as STL, the models that take Roberts
    // and Weiler-Atherton longest, in Release only (every format still read by the io suite)
    const std::string_view name = f;
    if (name == "PLY/Wuson.ply" || name == "STL/Spider_binary.stl") continue;
#endif
    Scene s = loadMeshFile(models / f);
    const Camera c = frameScene(s, kW, kH);
    out.push_back({f, std::move(s), c});
  }
  Scene sphere = uvSphere({148376.0f, 1234.0f, -223423.0f}, kSphereSegments);
  const Camera c = frameBounds(sphere.bounds(), kW, kH);
  out.push_back({"uv sphere " + std::to_string(kSphereSegments) + "x" +
                     std::to_string(kSphereSegments) + " at (148376, 1234, -223423)",
                 std::move(sphere), c});
  return out;
}

// Per thread count: fresh frames, then one reused frame. The sanitizer build, which runs the
// same code six times slower, keeps one fresh frame per thread count (four renders, not six),
// and renders the outline and cull-back sets at two threads only (a fresh frame and a reused
// one): every path runs under the sanitizers, and every comparison across thread counts is
// made there on the fill set; Release makes them on all three.
#ifdef HSR_SANITIZER_BUILD
constexpr int kRunsPerThreadCount = 2;
constexpr bool kEverySetAtOneThread = false;
#else
constexpr int kRunsPerThreadCount = 3;
constexpr bool kEverySetAtOneThread = true;
#endif

// One test per algorithm (Determinism.SixRendersAtOneAndTwoThreadsHashTheSame/ALGORITHM), so that
// CTest runs them side by side: as one test over every algorithm it was the longest of the suite
// (81 s in Release, 304 s under the sanitizers) and ran alone at the end.
class Determinism : public testing::EveryAlgorithm {};

TEST_P(Determinism, SixRendersAtOneAndTwoThreadsHashTheSame) {
  const std::vector<NamedScene> scenes = determinismScenes();
  ASSERT_GE(scenes.size(), static_cast<std::size_t>(kRandomScenes) + 6);
  struct OptionSet {
    const char* name;
    bool outline;
    CullMode cull;
  };
  const OptionSet sets[] = {{"fill", false, CullMode::None},
                            {"outline", true, CullMode::None},
                            {"cull back", false, CullMode::Back}};
  // Outlines need the capability; the other option sets apply to every algorithm.
  {
    const AlgorithmInfo& algo = findAlgorithm(GetParam());
    SCOPED_TRACE("algorithm " + std::string(algo.name));
    std::uint64_t renders = 0, differing = 0, models = 0, triangles = 0;
    Frame reused;  // lives across scenes and option sets: its kept memory must not matter
    for (const NamedScene& ns : scenes) {
      SCOPED_TRACE("scene " + ns.name);
      models += ns.name.find('/') != std::string::npos;
      triangles += ns.scene.triangleCount();
      for (const OptionSet& set : sets) {
        SCOPED_TRACE(std::string("options: ") + set.name);
        RenderOptions o;
        o.algorithm = std::string(algo.name);
        o.outline = set.outline;
        o.cull = set.cull;
        std::vector<Hashes> h;
        std::vector<int> h_threads;  // the thread count of each hash
        std::size_t drawn = 0;
        const bool one_thread =
            kEverySetAtOneThread || (!set.outline && set.cull == CullMode::None);
        for (int threads : {1, 2}) {
          if (threads == 1 && !one_thread) continue;
          o.threads = threads;
          for (int run = 0; run < kRunsPerThreadCount; ++run) {
            if (run < kRunsPerThreadCount - 1) {
              const Frame f = render(ns.scene, ns.camera, o);
              h.push_back(hashFrame(f));
              if (h.size() == 1)
                for (PolygonId id : f.ids) drawn += id != kNoPolygon;
            } else {
              render(ns.scene, ns.camera, o, reused);
              h.push_back(hashFrame(reused));
            }
            h_threads.push_back(threads);
            renders++;
          }
        }
        EXPECT_GT(drawn, 0u) << "nothing drawn: the scene proves nothing";
        for (std::size_t r = 1; r < h.size(); ++r) {
          if (h[r] == h[0]) continue;
          differing++;
          ADD_FAILURE() << "render " << r << " (threads " << h_threads[r] << ", "
                        << (r % kRunsPerThreadCount == kRunsPerThreadCount - 1 ? "reused frame"
                                                                               : "fresh frame")
                        << ") differs from the first in:" << differences(h[0], h[r]);
        }
      }
    }
    testing::printFigures(
        "row 17 " + std::string(algo.name) + ": " + testing::grouped(scenes.size()) + " scenes (" +
        testing::grouped(kRandomScenes * testing::countScale()) + " row-4, 6 built-in, " +
        testing::grouped(models) + " models, row 9's sphere; " + testing::grouped(triangles) +
        " triangles) x 3 option sets: " + testing::grouped(renders) + " renders, " +
        testing::grouped(differing) + " with a differing hash");
  }
}

HSR_INSTANTIATE_FOR_ALGORITHMS_WITH(Determinism, kOutline);

}  // namespace
}  // namespace hsr
