#pragma once
// The scan-line algorithm's inner workings (scanline_fast.cpp), open to the tests: they watch its
// spans and its active edge list to check the invariants the notes state.

#include <cstddef>

#include "visibility/algorithm.hpp"

namespace hsr::detail {

// Told what the scan-line pass does, row by row. With an observer the pass runs on one
// thread, as one band from the top row to the bottom row.
class ScanlineObserver {
 public:
  virtual ~ScanlineObserver() = default;
  // A span of row y, columns [x_begin, x_end), inside `polygons` polygons (0: background).
  // Called left to right along each row, rows top to bottom.
  virtual void span(int y, int x_begin, int x_end, std::size_t polygons) = 0;
  // After the last row: how many edges were still in the active edge list.
  virtual void finished(std::size_t edges_left) = 0;
};

// drawScanline with an observer (nullptr: as drawScanline).
void drawScanlineObserved(const AlgorithmInput& in, Frame& frame, ScanlineObserver* observer);

}  // namespace hsr::detail
