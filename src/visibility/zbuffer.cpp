// The z-buffer algorithm, as the notes teach it (Catmull 1974; the notes' "Type 2a").
//
// Besides the colour buffer, keep a second buffer of the same size holding one depth per
// pixel, the z-buffer. Before drawing, set every depth to the maximum and every pixel to the
// background colour. Then draw the polygons in any order: for each pixel of a polygon, compare
// its depth with the z-buffer's; if it is nearer, overwrite colour and depth, else draw
// nothing there.
//
//     for all i, j:  Depth[i, j] = MAX_DEPTH;  Image[i, j] = BACKGROUND_COLOUR
//     for all polygons P:
//       for all pixels (i, j) of P:
//         if Z_pixel < Depth[i, j]:  Image[i, j] = C_pixel;  Depth[i, j] = Z_pixel
//
// This file is that loop, scalar and on one core, to be read beside the notes. The renderer
// registered as "zbuffer" (zbuffer_tiled.cpp) is the same algorithm reorganised for many
// cores; tests/visibility/zbuffer_test.cpp proves the two equal bit for bit.
// Guarantee: each pixel shows the nearest polygon whose projection covers its centre (with
// GL's depth functions, depth mask and tie rule: under LESS the first polygon drawn keeps a
// tie). Cost: O(polygons + pixels covered); memory 16 bytes per pixel.

#include <string>

#include "core/frame.hpp"
#include "core/stopwatch.hpp"
#include "raster/edge.hpp"
#include "raster/fragment.hpp"
#include "raster/lines.hpp"
#include "visibility/algorithm.hpp"

namespace hsr::detail {
namespace {

// Step names: what `hsr explain zbuffer-textbook` shows, one picture per step.
constexpr std::string_view kStepInitialise = "initialise";
constexpr std::string_view kStepDrawPolygon = "draw polygon";
constexpr std::string_view kStepDone = "done";

// Scan-convert one triangle of a polygon: for each row of its projection, the span of pixels
// whose centres lie inside it (the shared exact edge setup and fill rule, raster/edge.hpp);
// along the span, compare each pixel's depth with the z-buffer.
template <DepthFunc F>
void scanConvert(const ScreenTriangle& t, const FrameView& fb, bool depth_mask, FragmentCounts& c) {
  TriangleSetup edges = setupTriangle(t, t.y0);
  for (int y = t.y0; y <= t.y1; ++y, nextRow(edges)) {
    int x_left = t.x0, x_right = t.x1;
    if (!spanOfRow(edges, &x_left, &x_right)) continue;  // this row misses the triangle
    // Depth along the span. The polygon's plane A x + B y + C z + D = 0 gives
    // z = (-A x - B y - D) / C at each pixel, and one pixel to the right z' = z - A/C. Adding
    // -A/C pixel after pixel would round at every step, and a pixel's depth would depend on
    // where its span began; so the row's part is computed once and each pixel takes
    // z = z_row + (-A/C) x (raster/depth.hpp): the notes' steps counted from x = 0, the same
    // bits however the span is walked.
    const double z_row = depthRowStart(t.depth, y);
    for (int x = x_left; x <= x_right; ++x) {
      const float z = depthInRow(z_row, t.depth, x);
      const std::size_t k = fb.index(x, y);
      c.tested++;
      if (!depthPasses<F>(z, fb.depth[k])) continue;  // something nearer is already drawn here
      c.written++;
      fb.overdraw[k]++;
      if (t.transparent()) {  // see-through: blend over what is there, keep its depth and id
        fb.rgba[k] = blendOver(t.rgba, fb.rgba[k]);
        continue;
      }
      if (depth_mask) fb.depth[k] = z;  // Depth[i, j] = Z_pixel
      fb.ids[k] = t.id;                 // the polygon now visible here
      fb.rgba[k] = t.rgba;              // Image[i, j] = C_pixel
    }
  }
}

// The triangles of one polygon, as outlines for the explain pictures.
std::vector<TraceOutline> outlinesOf(const ScreenTriangle* first, const ScreenTriangle* last) {
  std::vector<TraceOutline> out;
  for (const ScreenTriangle* t = first; t != last; ++t) {
    TraceOutline o;
    for (int k = 0; k < 3; ++k)
      o.emplace_back(t->x[k] / float(kSubpixelOne), t->y[k] / float(kSubpixelOne));
    out.push_back(std::move(o));
  }
  return out;
}

template <DepthFunc F>
void drawPolygons(const AlgorithmInput& in, Frame& frame) {
  const ScreenTriangles& tris = in.prepared.triangles;
  const FrameView fb(frame);
  const bool depth_mask = depthWrites(in.options);  // glDepthMask
  FragmentCounts counts;

  // Initialise: render() has cleared the buffers, as glClear(COLOR | DEPTH) does: every depth
  // to the clear depth (1.0, the far plane, is the maximum), every pixel to the background.
  std::uint64_t polygons = 0;
  for (std::size_t i = 0; i < tris.size(); ++i) polygons += i == 0 || tris[i].id != tris[i - 1].id;
  if (in.trace && in.trace->wants(kStepInitialise, 0, 1))
    in.trace->record({kStepInitialise,
                      "Initialise: every depth in the z-buffer to the maximum (1.0, the far "
                      "plane), every pixel to the background colour. " +
                          std::to_string(polygons) + " polygons to draw, in any order.",
                      &frame,
                      {}});

  // For all polygons P, in the order they were submitted (the pipeline has cut each polygon
  // into triangles snapped to the sub-pixel grid; they share the polygon's plane). Opaque
  // polygons first; transparent ones are blended over the finished opaque picture.
  std::uint64_t drawn = 0;
  for (const bool transparent_pass : {false, true}) {
    for (std::size_t first = 0; first < tris.size();) {
      std::size_t last = first + 1;
      while (last < tris.size() && tris[last].id == tris[first].id) ++last;
      if (tris[first].transparent() == transparent_pass) {
        const FragmentCounts before = counts;
        // For all pixels of P: its triangles, scan-converted against the z-buffer.
        for (std::size_t k = first; k < last; ++k) scanConvert<F>(tris[k], fb, depth_mask, counts);
        if (in.trace && in.trace->wants(kStepDrawPolygon, drawn, polygons)) {
          const std::uint64_t tested = counts.tested - before.tested;
          const std::uint64_t written = counts.written - before.written;
          in.trace->record({kStepDrawPolygon,
                            "Polygon " + std::to_string(drawn + 1) + " of " +
                                std::to_string(polygons) + " (id " +
                                std::to_string(tris[first].id) + "): of the " +
                                std::to_string(tested) + " pixels of its projection, " +
                                std::to_string(written) +
                                " were nearer than the z-buffer: colour and depth "
                                "written; at " +
                                std::to_string(tested - written) +
                                " something nearer was already drawn: skipped.",
                            &frame, outlinesOf(&tris[first], &tris[last - 1] + 1)});
        }
        ++drawn;
      }
      first = last;
    }
  }

  // Polygon mode LINE and POINT draw edges and vertices instead (raster/lines.hpp), depth
  // tested the same way; the outline pen draws silhouettes over the finished picture.
  const PixelBox viewport{0, 0, frame.width - 1, frame.height - 1};
  const DepthFunc func = effectiveDepthFunc(in.options);
  for (const ScreenLine& l : in.prepared.lines) drawLine(l, viewport, fb, func, depth_mask, counts);
  for (const ScreenLine& p : in.prepared.points)
    drawPoint(p, in.options.point_size, viewport, fb, func, depth_mask, counts);
  for (const ScreenLine& o : in.prepared.outline) drawOutlinePen(o, viewport, fb);

  if (in.trace && in.trace->wants(kStepDone, 0, 1))
    in.trace->record({kStepDone,
                      "Done: every pixel shows the nearest polygon at its centre, whatever the "
                      "drawing order. " +
                          std::to_string(counts.written) + " of the " +
                          std::to_string(counts.tested) +
                          " pixels scan-converted passed the "
                          "depth test (some were overwritten later by nearer ones).",
                      &frame,
                      {}});
  frame.stats.fragments_tested += counts.tested;
  frame.stats.fragments_written += counts.written;
  frame.stats.state_bytes += frameBufferBytes(frame) + tris.capacity() * sizeof(ScreenTriangle);
}

}  // namespace

void drawZBufferTextbook(const AlgorithmInput& in, Frame& frame) {
  const detail::Stopwatch t0;
  // glDepthFunc (LESS by default: "if the depth is smaller, overwrite"); with the depth test
  // disabled every fragment passes.
  withDepthFunc(effectiveDepthFunc(in.options), [&]<DepthFunc F>() { drawPolygons<F>(in, frame); });
  frame.stats.addStage("scan convert", t0.ms());
}

}  // namespace hsr::detail
