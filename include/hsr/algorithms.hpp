#pragma once
// The registry of visibility algorithms: one table that the CLI, the tests, the benchmarks
// and `hsr explain` loop over. An entry says what the algorithm is, what it needs and what it
// can do; property suites run every algorithm whose capabilities their property needs.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hsr {

enum class Precision { kImage, kObject };

// What the algorithm starts from (every kind comes from the same pipeline).
enum class InputKind {
  kScreenTriangles,  // culled, clipped triangles snapped to the sub-pixel grid
  kWindowPolygons,   // clipped polygons in window space (double), with their planes
  kWorldPolygons,    // world-space polygons and the camera (ray casting, BSP)
  kMap2D,            // a 2D map (Doom levels)
};

// What the algorithm can do. Each is a promise the property suites hold it to.
enum Capability : std::uint32_t {
  kExactSharedCoverage = 1u << 0,  // covers pixel centres by the shared edge setup and fill
                                   // rule: shared edges exactly once, as Mesa
  kDepthFuncs = 1u << 1,           // the eight glDepthFunc comparisons, and depth test off
  kDepthMask = 1u << 2,            // glDepthMask(GL_FALSE)
  kPolygonModes = 1u << 3,         // glPolygonMode LINE and POINT
  kOutline = 1u << 4,              // silhouette outlines over the fill (--outline)
  kTransparency = 1u << 5,         // polygons with alpha < 1 blended over what they cover
  kVisibleSet = 1u << 6,           // the exact visible parts of polygons, as geometry
  kExplain = 1u << 7,              // shows its steps to `hsr explain`
  kDrawOver = 1u << 8,             // draws into buffers it did not clear (the GL facade)
  kBackToFront = 1u << 9,          // blends transparent polygons in depth order, farthest
                                   // first (without it: in submission order, after the
                                   // opaque ones, as the z-buffer)
  kAntialiasing = 1u << 10,        // covers sub-pixel samples (--samples): antialiased colour
                                   // and a coverage buffer; ids and depth at pixel centres
  kTieRule = 1u << 11,             // settles coplanar polygons as the z-buffer's depth test: of
                                   // those whose own float depths at a pixel centre are equal,
                                   // the first submitted stays (LESS; the last with LEQUAL where
                                   // it has depth-funcs); the nearer float depth wins otherwise
  kZBufferFrame = 1u << 12,        // draws the z-buffer's frame bit for bit: ids, depths and
                                   // colours at every pixel (an antialiasing one at one sample)
};

struct AlgorithmInfo {
  std::string_view name;     // what --algorithm takes
  std::string_view summary;  // one line
  std::string_view source;   // where it comes from in the literature
  Precision precision = Precision::kImage;
  InputKind input = InputKind::kScreenTriangles;
  std::uint32_t capabilities = 0;
  std::uint64_t max_pixels = 0;  // a slow algorithm refuses larger images (0: no limit)
  bool reference = false;        // the row others are compared with (hsr compare)
  bool demonstration = false;    // wrong on purpose, to show a failure the notes describe
                                 // (painter-naive): in compare and explain, not held to the
                                 // visibility suites
  // The textbook pair: an algorithm written as the notes teach it (one core, one polygon, ray
  // or row at a time, to be read beside them) and its sibling reorganised for speed (tiles,
  // bands, hierarchies, compression, SIMD, all cores), which draws the same frame bit for bit
  // (tests/cross/textbook_test.cpp). `textbook` marks the first; `sibling` names the other of
  // the pair in both ("" where an algorithm has none). `hsr explain` of a fast sibling that
  // does not explain itself walks its textbook one.
  bool textbook = false;
  std::string_view sibling = {};

  bool has(Capability c) const { return (capabilities & c) != 0; }
};

const std::vector<AlgorithmInfo>& algorithms();
// The entry named `name`; throws hsr::Error naming the known algorithms otherwise.
const AlgorithmInfo& findAlgorithm(std::string_view name);
// The reference entry (exactly one has reference = true).
const AlgorithmInfo& referenceAlgorithm();
// The entry whose steps `hsr explain` shows for `info`: itself where it explains its own
// (kExplain), its textbook sibling where a fast one leaves that to it, nullptr otherwise.
const AlgorithmInfo* explainedBy(const AlgorithmInfo& info);

std::string_view toString(Precision p);  // "image", "object"
std::string_view toString(InputKind k);  // "screen triangles", ...
// "exact-coverage, depth-funcs, ..." for the capabilities set in `caps`.
std::string capabilityList(std::uint32_t caps);

}  // namespace hsr
