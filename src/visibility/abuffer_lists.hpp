#pragma once
// What the two A-buffers share: abuffer.cpp (the notes' loop, one list per pixel of the whole
// frame) and abuffer_fast.cpp (the same in tiles on all cores, hidden fragments never listed).
// The fragment, and how a pixel's fragments resolve into its colour, id and depth, sample by
// sample: so the two cannot resolve a pixel differently.
//
// Tests: tests/visibility/abuffer_test.cpp; tests/cross/textbook_test.cpp pins the two files.

#include <cstdint>
#include <string>
#include <vector>

#include "core/trace.hpp"
#include "raster/primitives.hpp"
#include "raster/samples.hpp"

namespace hsr::detail {

inline constexpr int kABufferDefaultSamples = 4;
inline constexpr std::uint32_t kEndOfList = 0xFFFFFFFFu;

// One polygon's share of one pixel. Its depth at the centre and at each sample comes from its
// polygon's plane (THE depth definition) when the list is resolved.
struct Fragment {
  std::uint64_t mask;     // the samples it covers
  float nearest;          // no nearer than this anywhere in the pixel (-infinity: not known)
  std::uint32_t polygon;  // its first triangle: plane, colour, alpha and id
  std::uint32_t next;     // the next fragment of the pixel's list, or kEndOfList
  bool centre;            // covers the pixel centre (by the fill rule, as the z-buffer)
};
static_assert(sizeof(Fragment) == 24, "24 bytes a fragment");

// The error for a frame whose fragments would pass the memory budget of `limit` fragments.
std::string fragmentBudgetMessage(std::uint64_t limit);

// Whether opaque fragment a hides b at a sample where they lie at depths za and zb: nearer, or
// as near and drawn first (the z-buffer's LESS keeps the first of equals).
inline bool inFront(float za, const Fragment& a, float zb, const Fragment& b) {
  return za < zb || (za == zb && a.polygon < b.polygon);
}

// What one sample of a pixel shows: its colour, and the depth of the nearest opaque fragment
// covering it (NaN where none does).
struct SampleResult {
  std::uint32_t colour;
  float depth;
  PolygonId id;  // the nearest opaque fragment's polygon (kNoPolygon where none)
};

// The resolve, for sample s of pixel (x, y) whose fragments are `list`: the nearest opaque
// fragment covering the sample hides everything behind it; the see-through ones in front of it
// are laid over it, farthest first.
SampleResult resolveSample(const ScreenTriangles& tris, const SamplePattern& pattern,
                           const std::vector<const Fragment*>& list, int x, int y, int s,
                           std::uint32_t background);

// The mean of a pixel's samples from their channel sums, rounded to nearest (opaque).
std::uint32_t meanOfSamples(const std::uint32_t sum[3], int count);

// The nearest opaque fragment of `list` covering the pixel centre, and its depth there (the
// pixel's id and depth); nullptr where none does.
const Fragment* nearestAtCentre(const ScreenTriangles& tris,
                                const std::vector<const Fragment*>& list, int x, int y,
                                float* depth);

// The teaching view. A pixel's fragments in words, before they are resolved: each one's polygon,
// opacity, samples covered (sample 0 first) and depth at the centre, nearest first. `held`, if
// one of them, is the polygon the pixel holds without a list (abuffer_fast.cpp).
std::string describeList(const ScreenTriangles& tris, const SamplePattern& pattern,
                         const std::vector<const Fragment*>& list, int x, int y,
                         const Fragment* held = nullptr);
// The pixel close up (src/explain/ draws it): what each sample resolves to, and the true edges
// of the triangles of every polygon listed there. `polygon_of` numbers the triangles' polygons.
// Returns the pixel's colour, the mean of its samples.
std::uint32_t closeUp(const ScreenTriangles& tris, const std::vector<std::uint32_t>& polygon_of,
                      const SamplePattern& pattern, const std::vector<const Fragment*>& list, int x,
                      int y, std::uint32_t background, TracePixel& out);

}  // namespace hsr::detail
