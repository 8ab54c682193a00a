// The painter's algorithm with a plain depth sort, and nothing more: sort the polygons by
// their depth (here the mean depth of their vertices, as SVG renderers and many quick tools
// sort), paint them farthest first with no depth test. It is here to show what the notes say
// no plain order can do: on cyclic overlaps (the three sticks of `cyclic`) and interpenetrating
// polygons (`penetrating`) some order is always wrong somewhere, and so is this one; and two
// polygons whose mean depths rank them differently from their overlap paint in the wrong order
// even without a cycle. painter.cpp (Newell, Newell & Sancha) adds the tests, swaps and splits
// that fix it. Guarantee: none beyond each polygon's own pixels (the shared fill rule) and
// depths (its plane, as the z-buffer's). Cost: O(n log n) plus the pixels painted.
// Tests: tests/visibility/painter_test.cpp measures its wrong pixels.

#include <algorithm>
#include <numeric>
#include <vector>

#include "core/frame.hpp"
#include "core/stopwatch.hpp"
#include "raster/fill_polygons.hpp"
#include "visibility/algorithm.hpp"

namespace hsr::detail {

void drawPainterNaive(const AlgorithmInput& in, Frame& frame) {
  const detail::Stopwatch t0;
  const std::vector<WindowPolygon>& polygons = in.prepared.polygons;
  // Sort by mean depth, farthest first (ties: the later polygon first, as painter.cpp).
  std::vector<double> depth(polygons.size(), 0.0);
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    for (const glm::dvec3& v : polygons[i].vertices) depth[i] += v.z;
    depth[i] /= static_cast<double>(std::max<std::size_t>(polygons[i].vertices.size(), 1));
  }
  std::vector<std::uint32_t> order(polygons.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    if (depth[a] != depth[b]) return depth[a] > depth[b];
    return polygons[a].id > polygons[b].id;
  });
  // Paint, no depth test: each polygon over whatever is there.
  const FrameView fb(frame);
  FragmentCounts fragments;
  for (const std::uint32_t i : order)
    fillPolygon(polygons[i], fb, DepthFunc::Always, /*depth_mask=*/true, fragments);
  frame.stats.fragments_tested += fragments.tested;
  frame.stats.fragments_written += fragments.written;
  frame.stats.state_bytes += frameBufferBytes(frame) + order.capacity() * 12;
  frame.stats.addStage("sort + paint", t0.ms());
}

}  // namespace hsr::detail
