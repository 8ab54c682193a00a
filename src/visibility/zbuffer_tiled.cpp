// The same algorithm as zbuffer.cpp, reorganised for cores: the z-buffer (Catmull 1974) with
// the screen cut into 64x64 tiles that are filled in parallel, as Mesa's llvmpipe does.
//   1. bin: each primitive is listed in every tile its bounding box touches, keeping
//      submission order inside each tile (raster/bins.hpp);
//   2. fill tiles: tiles are independent (each owns its pixels), so they are filled in
//      parallel; inside a tile every triangle is scan-converted with the shared exact edge
//      setup, each row's span written by the span path chosen once for the process (scalar or
//      SIMD, raster/span.hpp), every fragment's depth by THE depth definition
//      (raster/depth.hpp).
//   Opaque triangles first, then transparent ones blended over them, then LINE/POINT
//   primitives, then the outline: per tile, the order zbuffer.cpp draws the whole frame in.
// Guarantee: bit-identical to zbuffer.cpp, and so at any thread count and on any instruction
// set (tests/visibility/zbuffer_test.cpp). Cost: O(triangles + tiles touched + pixels
// covered); memory 16 bytes per pixel plus the projected triangles and 4 bytes per tile entry.

#include <string>

#include "core/frame.hpp"
#include "core/parallel.hpp"
#include "hsr/error.hpp"
#include "core/stopwatch.hpp"
#include "raster/bins.hpp"
#include "raster/lines.hpp"
#include "raster/triangle.hpp"
#include "visibility/algorithm.hpp"

namespace hsr::detail {
namespace {

// Step names: what `hsr explain zbuffer` shows.
constexpr std::string_view kStepBin = "bin";
constexpr std::string_view kStepFillTile = "fill tile";
constexpr std::string_view kStepDone = "done";

// Reused between frames rendered into the same Frame.
struct Scratch {
  Bins tri_bins, line_bins, point_bins, outline_bins;
  std::vector<std::size_t> counts;
  std::vector<FragmentCounts> per_tile;
};

struct TileJob {
  const PreparedScene& ps;
  const Scratch& bins;
  const FrameView& fb;
  DepthFunc func;
  bool depth_mask;
  RasterPath path;
  float point_size;
};

template <class Fn>
void forEachInTile(const Bins& b, std::size_t tile, Fn fn) {
  for (std::size_t k = b.start[tile]; k < b.start[tile + 1]; ++k) fn(b.items[k]);
}

// The same over the tile's triangles, asking for each one's cache line a few entries ahead: a
// tile's triangles lie anywhere in the array when the scene's order is not the screen's (a soup
// of a million random triangles, where this halves the time spent waiting on memory).
constexpr std::size_t kPrefetchAhead = 16;
template <class Fn>
void forEachTriangleInTile(const Bins& b, std::size_t tile, const ScreenTriangles& tris, Fn fn) {
  const std::size_t begin = b.start[tile], end = b.start[tile + 1];
  for (std::size_t k = begin; k < end; ++k) {
    if (k + kPrefetchAhead < end) __builtin_prefetch(&tris[b.items[k + kPrefetchAhead]]);
    fn(b.items[k]);
  }
}

// Fill one tile: every primitive binned there, in the whole frame's drawing order.
template <DepthFunc F>
FragmentCounts fillTile(const TileJob& job, std::size_t tile) {
  const PreparedScene& ps = job.ps;
  const PixelBox box = job.bins.tri_bins.tileBox(tile, ps.width, ps.height);
  FragmentCounts c;
  bool any_transparent = false;
  forEachTriangleInTile(job.bins.tri_bins, tile, ps.triangles, [&](std::uint32_t i) {
    const ScreenTriangle& t = ps.triangles[i];
    if (t.transparent())
      any_transparent = true;
    else
      rasterTriangle<F>(t, box, job.fb, job.depth_mask, job.path, c);
  });
  if (any_transparent) {
    forEachInTile(job.bins.tri_bins, tile, [&](std::uint32_t i) {
      const ScreenTriangle& t = ps.triangles[i];
      if (t.transparent()) rasterTriangle<F>(t, box, job.fb, job.depth_mask, job.path, c);
    });
  }
  forEachInTile(job.bins.line_bins, tile, [&](std::uint32_t i) {
    drawLine(ps.lines[i], box, job.fb, job.func, job.depth_mask, c);
  });
  forEachInTile(job.bins.point_bins, tile, [&](std::uint32_t i) {
    drawPoint(ps.points[i], job.point_size, box, job.fb, job.func, job.depth_mask, c);
  });
  forEachInTile(job.bins.outline_bins, tile,
                [&](std::uint32_t i) { drawOutlinePen(ps.outline[i], box, job.fb); });
  return c;
}

}  // namespace

void drawZBufferTiled(const AlgorithmInput& in, Frame& frame) {
  const PreparedScene& ps = in.prepared;
  const int w = ps.width, h = ps.height;
  if (frame.width != w || frame.height != h) throw Error("frame size differs from the camera's");

  // 1. Bin.
  detail::Stopwatch t0;
  std::unique_ptr<Scratch> own;
  Scratch& z = algorithmScratch(in, own);
  binPrimitives(ps.triangles, w, h, z.tri_bins, z.counts);
  binPrimitives(ps.lines, w, h, z.line_bins, z.counts);
  binPrimitives(ps.points, w, h, z.point_bins, z.counts,
                std::max(1.0f, 0.5f * in.options.point_size + 1.0f));
  binPrimitives(ps.outline, w, h, z.outline_bins, z.counts);
  frame.stats.addStage("bin", t0.ms());
  const std::size_t tiles = z.tri_bins.tiles();
  if (in.trace && in.trace->wants(kStepBin, 0, 1)) {
    std::vector<TraceOutline> grid;
    std::size_t busy = 0;
    for (std::size_t t = 0; t < tiles; ++t) {
      grid.push_back(pixelBoxOutline(z.tri_bins.tileBox(t, w, h)));
      busy += z.tri_bins.start[t + 1] > z.tri_bins.start[t];
    }
    in.trace->record({kStepBin,
                      "Bin: the screen is cut into " + std::to_string(tiles) + " tiles of " +
                          std::to_string(kTile) + "x" + std::to_string(kTile) + " pixels; " +
                          std::to_string(ps.triangles.size()) + " triangles are listed in " +
                          std::to_string(z.tri_bins.items.size()) + " tile entries (" +
                          std::to_string(busy) + " tiles hold any), in drawing order.",
                      &frame, std::move(grid)});
  }

  // 2. Fill tiles, in parallel (in tile order when explaining, so the pictures can follow).
  t0.restart();
  const FrameView fb(frame);
  const DepthFunc func = effectiveDepthFunc(in.options);
  const TileJob job{
      ps, z, fb, func, depthWrites(in.options), rasterPath(func), in.options.point_size};
  using TileFn = FragmentCounts (*)(const TileJob&, std::size_t);
  const TileFn fill = withDepthFunc(func, []<DepthFunc F>() -> TileFn { return &fillTile<F>; });
  z.per_tile.assign(tiles, FragmentCounts{});
  if (!in.trace) {
    tbb::parallel_for(std::size_t(0), tiles, [&](std::size_t t) { z.per_tile[t] = fill(job, t); });
  } else {
    for (std::size_t t = 0; t < tiles; ++t) {
      z.per_tile[t] = fill(job, t);
      if (in.trace->wants(kStepFillTile, t, tiles))
        in.trace->record(
            {kStepFillTile,
             "Tile " + std::to_string(t + 1) + " of " + std::to_string(tiles) + ": its " +
                 std::to_string(z.tri_bins.start[t + 1] - z.tri_bins.start[t]) +
                 " triangles scan-converted against its part of the z-buffer; " +
                 std::to_string(z.per_tile[t].written) + " of " +
                 std::to_string(z.per_tile[t].tested) + " pixels passed the depth test.",
             &frame,
             {pixelBoxOutline(z.tri_bins.tileBox(t, w, h))}});
    }
  }
  FragmentCounts total;
  for (const FragmentCounts& c : z.per_tile) total += c;
  frame.stats.fragments_tested += total.tested;
  frame.stats.fragments_written += total.written;
  frame.stats.addStage("raster", t0.ms());
  if (in.trace && in.trace->wants(kStepDone, 0, 1))
    in.trace->record({kStepDone,
                      "Done: the same picture, depths and ids as drawing polygon by polygon on "
                      "one core (zbuffer-textbook), bit for bit.",
                      &frame,
                      {}});

  frame.stats.state_bytes += frameBufferBytes(frame) + z.tri_bins.bytes() + z.line_bins.bytes() +
                             z.point_bins.bytes() + z.outline_bins.bytes() +
                             ps.triangles.capacity() * sizeof(ScreenTriangle);
}

}  // namespace hsr::detail
