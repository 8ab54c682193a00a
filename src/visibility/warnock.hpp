#pragma once
// Warnock's area subdivision (warnock.cpp), open to the tests: they watch where it stops to
// check the invariants the notes state.

#include <cstdint>

#include "raster/primitives.hpp"
#include "visibility/algorithm.hpp"

namespace hsr::detail {

// Why an area needed no further subdivision.
enum class WarnockStop : std::uint8_t {
  kNothing,            // every polygon lies outside it: background
  kOnePolygon,         // one polygon alone is not outside: drawn within the area
  kSurrounderInFront,  // a surrounding polygon is in front of every other: drawn on the area
  kPixel,              // one pixel: the polygon nearest at its centre
};
inline constexpr int kWarnockStops = 4;

// Told where the subdivision stops. With an observer it runs on one thread.
class WarnockObserver {
 public:
  virtual ~WarnockObserver() = default;
  // A leaf: `area` at `level` (the viewport is level 0) and why it stopped.
  virtual void leaf(const PixelBox& area, int level, WarnockStop why) = 0;
};

// The deepest level a width x height viewport can need: ceil(log2(max(width, height))).
int warnockDeepestLevel(int width, int height);

// drawWarnock with an observer (nullptr: as drawWarnock).
void drawWarnockObserved(const AlgorithmInput& in, Frame& frame, WarnockObserver* observer);

}  // namespace hsr::detail
