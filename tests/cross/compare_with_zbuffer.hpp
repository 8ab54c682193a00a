#pragma once
// An algorithm's frame against the z-buffer's, pixel by pixel: what the object-order tests
// (painter, BSP) measure. A pixel is wrong when the algorithm shows a surface deeper than the
// nearest one there (the z-buffer's depth) by more than kClearlyDeeper plus the z-buffer's
// depth step to a neighbouring pixel, or shows nothing where the z-buffer shows something (or
// the reverse): not a tie of two depths, a wrong answer. The neighbour step is the depth one
// pixel's move can change: where a nearly edge-on polygon folds behind its neighbour, the
// snapped vertices decide which of the two the pixel centre sees, and that is a tie at the
// picture's precision (measured: 2CylinderEngine's own camera, one pixel 5.4e-5 apart at a
// crease whose triangles the exact plane test orders the other way).

#include <algorithm>
#include <bit>
#include <cmath>
#include <utility>
#include <cstdint>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "cross/figures.hpp"
#include "cross/random_scenes.hpp"
#include "cross/reference_zbuffer.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"

namespace hsr::testing {

inline constexpr float kClearlyDeeper = 1e-5f;  // window depth

struct Comparison {
  std::uint64_t pixels = 0, drawn = 0, ids_differ = 0, wrong = 0, depth_differs_same_id = 0;
  std::string first_wrong;  // the first clearly wrong pixel, spelled out

  void add(const Comparison& o) {
    pixels += o.pixels, drawn += o.drawn, ids_differ += o.ids_differ, wrong += o.wrong;
    depth_differs_same_id += o.depth_differs_same_id;
    if (first_wrong.empty()) first_wrong = o.first_wrong;
  }
};

// Frame `p`, drawn by `algorithm`, against the z-buffer's frame `z` of the same view.
inline Comparison compareFrames(const Frame& z, const Frame& p, const std::string& algorithm) {
  Comparison c;
  c.pixels = z.ids.size();
  for (std::size_t k = 0; k < z.ids.size(); ++k) {
    c.drawn += z.ids[k] != kNoPolygon;
    if (p.ids[k] == z.ids[k]) {
      // The same polygon: the same plane at the same pixel, the same float.
      c.depth_differs_same_id += p.depth[k] != z.depth[k];
      continue;
    }
    c.ids_differ++;
    const int x = static_cast<int>(k % z.width), y = static_cast<int>(k / z.width);
    float step = 0.0f;
    for (const auto& [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
      if (x + dx < 0 || x + dx >= z.width || y + dy < 0 || y + dy >= z.height) continue;
      const std::size_t n = static_cast<std::size_t>(y + dy) * z.width + (x + dx);
      if (z.ids[n] != kNoPolygon) step = std::max(step, std::abs(z.depth[n] - z.depth[k]));
    }
    const bool wrong = p.ids[k] == kNoPolygon || z.ids[k] == kNoPolygon ||
                       p.depth[k] > z.depth[k] + kClearlyDeeper + step;
    if (wrong && c.wrong++ == 0)
      c.first_wrong = "pixel (" + std::to_string(k % z.width) + ", " + std::to_string(k / z.width) +
                      ") [top row 0]: " + algorithm + " shows " + std::to_string(p.ids[k]) +
                      " at " + std::to_string(p.depth[k]) + ", the z-buffer " +
                      std::to_string(z.ids[k]) + " at " + std::to_string(z.depth[k]);
  }
  return c;
}

// Renders into one of two frames kept by the calling thread and returns it: the suites that
// draw hundreds of scenes render into the same buffers again (the contract of render() into a
// Frame, which tests/cross/determinism_test.cpp holds to a fresh frame's), instead of a fresh
// frame each time, whose buffers the sanitizers' allocator maps and faults in afresh when over
// 128 KiB. The frame stays valid until the next call with the same slot.
inline const Frame& renderKept(const Scene& scene, const Camera& camera, const RenderOptions& o,
                               int slot) {
  thread_local Frame frames[2];
  Frame& f = frames[slot];
  render(scene, camera, o, f);
  return f;
}

// The frame `algorithm` renders with options `o` against the z-buffer's with the same options.
inline Comparison compareWithZBuffer(const Scene& scene, const Camera& camera,
                                     const std::string& algorithm, RenderOptions o = {}) {
  o.algorithm = "zbuffer";
  const Frame& z = renderKept(scene, camera, o, 0);
  o.algorithm = algorithm;
  return compareFrames(z, renderKept(scene, camera, o, 1), algorithm);
}

inline std::string describe(const Comparison& c) {
  return grouped(c.ids_differ) + " of " + grouped(c.drawn) +
         " drawn pixels show another polygon than the z-buffer, " + grouped(c.wrong) +
         " clearly wrong";
}

// The real models of the Mesa test, under HSR_TEST_MODELS.
inline constexpr const char* kMesaTestModels[] = {
    "OBJ/spider.obj", "PLY/Wuson.ply", "STL/Spider_binary.stl",
    "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"};

// Each real model of the Mesa test at 640x480, cull none and back (the default options
// otherwise): f(label, scene, camera, options), the label naming model and cull mode. In the
// sanitizer leg's tier cull back alone: the same code on half the faces (the back faces' extra
// overlaps are Release's; cull none runs under the sanitizers in the conformance suites).
#ifdef HSR_SANITIZER_BUILD
inline constexpr CullMode kMesaTestCulls[] = {CullMode::Back};
#else
inline constexpr CullMode kMesaTestCulls[] = {CullMode::None, CullMode::Back};
#endif
template <class F>
void forEachMesaModelView(F&& f) {
  for (const char* model : kMesaTestModels) {
    SCOPED_TRACE(model);
    const Scene scene = loadScene((std::filesystem::path(HSR_TEST_MODELS) / model).string());
    const Camera camera = frameScene(scene, 640, 480);
    for (const CullMode cull : kMesaTestCulls) {
      RenderOptions o;
      o.cull = cull;
      f(std::string(model) + (cull == CullMode::None ? " cull none" : " cull back"), scene, camera,
        o);
    }
  }
}

// The real models of the Mesa test at 640x480, cull none and back: the frame `draw(scene,
// camera, options)` gives against the z-buffer's: no pixel clearly wrong, ids agreeing on at
// least 99.9% of the drawn pixels, equal depths wherever the ids agree. `more(frame)` adds to
// the printed line.
template <class Draw, class More>
void expectRealModelsAgreeWithTheZBuffer(const std::string& algorithm, Draw&& draw, More&& more) {
  forEachMesaModelView([&](const std::string& label, const Scene& scene, const Camera& camera,
                           const RenderOptions& o) {
    const Frame z = render(scene, camera, o);
    const Frame f = draw(scene, camera, o);
    const Comparison c = compareFrames(z, f, algorithm);
    printFigures(label + ": " + algorithm + ": " + describe(c) + " (" +
                 percent(c.drawn - c.ids_differ, c.drawn) + " agree)" + more(f));
    EXPECT_EQ(c.wrong, 0u) << c.first_wrong;
    EXPECT_LE(c.ids_differ, c.drawn / 1000);
    EXPECT_EQ(c.depth_differs_same_id, 0u);
  });
}

// The same for an algorithm of the registry, drawn by render().
inline void expectRealModelsAgreeWithTheZBuffer(const std::string& algorithm) {
  expectRealModelsAgreeWithTheZBuffer(
      algorithm,
      [&](const Scene& scene, const Camera& camera, RenderOptions o) {
        o.algorithm = algorithm;
        return render(scene, camera, o);
      },
      [](const Frame&) { return std::string(); });
}

// Row 4's seeded random scenes (60 x the count scale, seeds 1000...) against the z-buffer:
// no clearly wrong pixel, and equal depths wherever the ids agree. `each(scene, camera)` is
// called for every scene too (for the algorithm's own counters). Returns the sum.
template <class Each>
Comparison expectNoWrongPixelOnRandomScenes(const std::string& algorithm, Each&& each) {
  Comparison total;
  const int scenes = 60 * countScale();
  for (int i = 0; i < scenes; ++i) {
    const std::uint64_t seed = 1000 + static_cast<std::uint64_t>(i);
    const Scene scene = agreementScene(seed);
    const Camera camera = agreementCamera(seed);
    const Comparison c = compareWithZBuffer(scene, camera, algorithm);
    EXPECT_EQ(c.wrong, 0u) << "seed " << seed << ": " << c.first_wrong;
    EXPECT_EQ(c.depth_differs_same_id, 0u) << "seed " << seed;
    total.add(c);
    each(scene, camera);
  }
  return total;
}

// ---------------------------------------------------------------------------------------------
// Bit for bit: the algorithms that share the z-buffer's coverage, fragment depth and tie rule
// (scan-line, Warnock) must give its very frame: the same id, depth and colour at every pixel.

struct Identity {
  std::uint64_t pixels = 0, differ = 0, ids_differ = 0, depths_differ = 0, colours_differ = 0;
  std::uint64_t unambiguous = 0, unambiguous_differ = 0;  // by the agreement oracle
  std::string first;                                      // the first differing pixel

  void add(const Identity& o) {
    pixels += o.pixels, differ += o.differ, ids_differ += o.ids_differ;
    depths_differ += o.depths_differ, colours_differ += o.colours_differ;
    unambiguous += o.unambiguous, unambiguous_differ += o.unambiguous_differ;
    if (first.empty()) first = o.first;
  }
};

// `p` against the z-buffer's frame `z`; `ambiguous` (the oracle's flags, GL rows: bottom row
// first) may be null.
inline Identity compareBitForBit(const Frame& z, const Frame& p,
                                 const std::vector<std::uint8_t>* ambiguous,
                                 const std::string& label) {
  Identity c;
  c.pixels = z.ids.size();
  for (std::size_t k = 0; k < z.ids.size(); ++k) {
    const int x = static_cast<int>(k % z.width), y = static_cast<int>(k / z.width);
    const bool unambiguous =
        ambiguous && (*ambiguous)[static_cast<std::size_t>(z.height - 1 - y) * z.width + x] == 0;
    c.unambiguous += unambiguous;
    const bool id = p.ids[k] != z.ids[k];
    const bool depth =
        std::bit_cast<std::uint32_t>(p.depth[k]) != std::bit_cast<std::uint32_t>(z.depth[k]);
    const bool colour = p.color[k] != z.color[k];
    if (!id && !depth && !colour) continue;
    c.differ++, c.ids_differ += id, c.depths_differ += depth, c.colours_differ += colour;
    c.unambiguous_differ += unambiguous;
    if (c.first.empty())
      c.first = label + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                ") [top row 0] shows " + std::to_string(p.ids[k]) + " at depth " +
                std::to_string(p.depth[k]) + ", the z-buffer " + std::to_string(z.ids[k]) + " at " +
                std::to_string(z.depth[k]);
  }
  return c;
}

inline std::string describe(const Identity& c) {
  return grouped(c.differ) + " of " + grouped(c.pixels) + " pixels differ from the z-buffer (ids " +
         grouped(c.ids_differ) + ", depths " + grouped(c.depths_differ) + ", colours " +
         grouped(c.colours_differ) + "); of " + grouped(c.unambiguous) + " unambiguous pixels " +
         grouped(c.unambiguous_differ) + " differ";
}

// The agreement scene set (row 4's seeds and cameras, culling off, 1 and 2 threads) and the
// real models of the Mesa test (culling off and back): `algorithm` must give the z-buffer's
// frame on every unambiguous pixel; returns the tally so the caller can print the rest.
// `samples`: RenderOptions::samples for an antialiasing algorithm.
inline Identity expectBitForBitWithZBuffer(const std::string& algorithm, int samples = 0) {
  Identity total;
  const int scenes = 200 * countScale();
  for (int i = 0; i < scenes; ++i) {
    const std::uint64_t seed = 1 + static_cast<std::uint64_t>(i);
    const Scene scene = agreementScene(seed);
    const Camera camera = agreementCamera(seed);
    const ReferenceFrame ref = referenceZBuffer(scene, camera);
    RenderOptions o;
    o.cull = CullMode::None;
    o.threads = 1 + static_cast<int>(seed % 2);
    o.algorithm = "zbuffer";
    const Frame& z = renderKept(scene, camera, o, 0);
    o.algorithm = algorithm;
    o.samples = samples;
    const Identity c =
        compareBitForBit(z, renderKept(scene, camera, o, 1), ref.valid ? &ref.ambiguous : nullptr,
                         algorithm + ", seed " + std::to_string(seed));
    EXPECT_EQ(c.unambiguous_differ, 0u) << c.first;
    total.add(c);
  }
  return total;
}

inline Identity expectBitForBitOnRealModels(const std::string& algorithm, int width = 640,
                                            int height = 480, int samples = 0) {
  Identity total;
  for (const char* model : kMesaTestModels) {
    const Scene scene = loadScene((std::filesystem::path(HSR_TEST_MODELS) / model).string());
    const Camera camera = frameScene(scene, width, height);
    for (const CullMode cull : {CullMode::None, CullMode::Back}) {
      RenderOptions o;
      o.cull = cull;
      const Frame z = render(scene, camera, o);
      o.algorithm = algorithm;
      o.samples = samples;
      const Identity c =
          compareBitForBit(z, render(scene, camera, o), nullptr, algorithm + " on " + model);
      printFigures(std::string(model) + (cull == CullMode::None ? " cull none" : " cull back") +
                   ": " + algorithm + ": " + describe(c));
      total.add(c);
    }
  }
  return total;
}

// Glass over opaque polygons (the demo) and the outline pen: colours too are the z-buffer's.
inline void expectBlendsAndOutlinesAsTheZBuffer(const std::string& algorithm) {
  const Scene scene = makeBuiltinScene("demo");
  const Camera camera = frameScene(scene, 320, 240);
  for (const bool outline : {false, true}) {
    RenderOptions o;
    o.outline = outline;
    const Frame z = render(scene, camera, o);
    o.algorithm = algorithm;
    const Identity c = compareBitForBit(z, render(scene, camera, o), nullptr, "demo");
    EXPECT_EQ(c.differ, 0u) << c.first;
  }
}

// spheres:20000 at 400x300 on 1, 2 and 4 threads: the same picture and every count the same.
// Returns the 1-thread frame.
inline Frame expectSameFrameAndCountsAtAnyThreadCount(const std::string& algorithm) {
  const Scene scene = makeBuiltinScene("spheres:20000");
  const Camera camera = frameScene(scene, 400, 300);
  RenderOptions o;
  o.algorithm = algorithm;
  o.threads = 1;
  Frame one = render(scene, camera, o);
  for (const int threads : {2, 4}) {
    o.threads = threads;
    const Frame many = render(scene, camera, o);
    const Identity c = compareBitForBit(one, many, nullptr, "threads");
    EXPECT_EQ(c.differ, 0u) << c.first;
    for (const Counter& k : one.stats.counters)
      EXPECT_EQ(many.stats.counter(k.name), k.value) << k.name;
  }
  return one;
}

}  // namespace hsr::testing
