#pragma once
// An algorithm's frame against the z-buffer's, pixel by pixel: what the object-order tests
// (painter, BSP) measure. A pixel is wrong when the algorithm shows a surface deeper than the
// nearest one there (the z-buffer's depth) by more than kClearlyDeeper, or shows nothing where
// the z-buffer shows something (or the reverse): not a tie of two depths, a wrong answer.

#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "cross/figures.hpp"
#include "cross/random_scenes.hpp"
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
    const bool wrong = p.ids[k] == kNoPolygon || z.ids[k] == kNoPolygon ||
                       p.depth[k] > z.depth[k] + kClearlyDeeper;
    if (wrong && c.wrong++ == 0)
      c.first_wrong = "pixel (" + std::to_string(k % z.width) + ", " + std::to_string(k / z.width) +
                      ") [top row 0]: " + algorithm + " shows " + std::to_string(p.ids[k]) + " at " +
                      std::to_string(p.depth[k]) + ", the z-buffer " + std::to_string(z.ids[k]) +
                      " at " + std::to_string(z.depth[k]);
  }
  return c;
}

// The frame `algorithm` renders with options `o` against the z-buffer's with the same options.
inline Comparison compareWithZBuffer(const Scene& scene, const Camera& camera, const std::string& algorithm,
                                     RenderOptions o = {}) {
  o.algorithm = "zbuffer";
  const Frame z = render(scene, camera, o);
  o.algorithm = algorithm;
  return compareFrames(z, render(scene, camera, o), algorithm);
}

inline std::string describe(const Comparison& c) {
  return grouped(c.ids_differ) + " of " + grouped(c.drawn) +
         " drawn pixels show another polygon than the z-buffer, " + grouped(c.wrong) + " clearly wrong";
}

// The real models of the Mesa test, under HSR_TEST_MODELS.
inline constexpr const char* kMesaTestModels[] = {"OBJ/spider.obj", "PLY/Wuson.ply", "STL/Spider_binary.stl",
                                                  "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"};

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

}  // namespace hsr::testing
