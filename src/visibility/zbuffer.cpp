// Z-buffer, tiled and binned for many cores (DESIGN.md "Speed"):
//   1. bin: each primitive is listed in every 64x64 screen tile its bounding box touches,
//      by a counting sort that keeps submission order inside each tile;
//   2. raster: tiles are filled in parallel; inside a tile each triangle is walked row by row,
//      the exact span of a row comes from the integer edge functions (core/raster), and depth
//      is stepped incrementally along the span, z' = z + dz/dx, as the notes show.
//   Opaque triangles first, then transparent ones blended over them (depth tested, no depth
//   or id write), then LINE/POINT primitives, then the outline.

#include "visibility/zbuffer.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>

#if defined(__SSE4_1__)
#include <smmintrin.h>
#endif

#include "core/raster.hpp"
#include "hsr/error.hpp"

namespace hsr::detail {
namespace {

constexpr int kTileShift = 6;  // 64x64 pixel tiles: 16 KiB of depth, fits in L1/L2
constexpr int kTile = 1 << kTileShift;

struct PixelBox {
  int x0, y0, x1, y1;  // inclusive; empty when x0 > x1 or y0 > y1
};

PixelBox triangleBox(const ScreenTriangle& t, int, int) { return {t.x0, t.y0, t.x1, t.y1}; }

PixelBox lineBox(const ScreenLine& l, int w, int h) {
  auto lo = [](float a, float b) { return std::floor(std::min(a, b)) - 1.0f; };
  auto hi = [](float a, float b) { return std::ceil(std::max(a, b)) + 1.0f; };
  const float x0 = std::max(lo(l.x0, l.x1), 0.0f), y0 = std::max(lo(l.y0, l.y1), 0.0f);
  const float x1 = std::min(hi(l.x0, l.x1), float(w - 1)), y1 = std::min(hi(l.y0, l.y1), float(h - 1));
  if (!(x0 <= x1) || !(y0 <= y1)) return {1, 1, 0, 0};
  return {int(x0), int(y0), int(x1), int(y1)};
}

struct Counters {
  std::uint64_t tested = 0, written = 0;
};

// Per-tile lists of primitive indices, in submission order.
struct Bins {
  int tiles_x = 0, tiles_y = 0;
  std::vector<std::size_t> start;  // tiles + 1
  std::vector<std::uint32_t> items;
  std::size_t bytes() const { return start.size() * sizeof(std::size_t) + items.size() * 4; }
};

template <class T, class BoxFn>
void binPrimitives(const std::vector<T>& prims, int w, int h, BoxFn box, Bins& bins,
                   std::vector<std::size_t>& counts) {
  bins.tiles_x = (w + kTile - 1) >> kTileShift;
  bins.tiles_y = (h + kTile - 1) >> kTileShift;
  const std::size_t tiles = static_cast<std::size_t>(bins.tiles_x) * bins.tiles_y;
  const std::size_t n = prims.size();
  // Chunks only split the work; the result (sorted by tile, then index) does not depend on them.
  const std::size_t chunk = std::max<std::size_t>(8192, n / 64 + 1);
  const std::size_t chunks = (n + chunk - 1) / chunk;
  counts.assign(chunks * tiles, 0);
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    std::size_t* cnt = &counts[c * tiles];
    for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) {
      const PixelBox b = box(prims[i], w, h);
      if (b.x0 > b.x1 || b.y0 > b.y1) continue;
      for (int ty = b.y0 >> kTileShift; ty <= b.y1 >> kTileShift; ++ty)
        for (int tx = b.x0 >> kTileShift; tx <= b.x1 >> kTileShift; ++tx)
          cnt[static_cast<std::size_t>(ty) * bins.tiles_x + tx]++;
    }
  });
  // Exclusive prefix sum in (tile, chunk) order: tile-major keeps each tile's list contiguous
  // and, within a tile, chunk order = submission order.
  bins.start.assign(tiles + 1, 0);
  std::size_t running = 0;
  for (std::size_t t = 0; t < tiles; ++t) {
    bins.start[t] = running;
    for (std::size_t c = 0; c < chunks; ++c) {
      const std::size_t k = counts[c * tiles + t];
      counts[c * tiles + t] = running;
      running += k;
    }
  }
  bins.start[tiles] = running;
  if (running > (std::size_t(1) << 31))
    throw Error("scene too heavy to bin: " + std::to_string(running) + " tile entries");
  bins.items.resize(running);
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    std::size_t* off = &counts[c * tiles];
    for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) {
      const PixelBox b = box(prims[i], w, h);
      if (b.x0 > b.x1 || b.y0 > b.y1) continue;
      for (int ty = b.y0 >> kTileShift; ty <= b.y1 >> kTileShift; ++ty)
        for (int tx = b.x0 >> kTileShift; tx <= b.x1 >> kTileShift; ++tx)
          bins.items[off[static_cast<std::size_t>(ty) * bins.tiles_x + tx]++] =
              static_cast<std::uint32_t>(i);
    }
  });
}

// Reused between frames rendered into the same Frame.
struct ZBufferScratch {
  Bins tri_bins, line_bins, point_bins, outline_bins;
  std::vector<std::size_t> counts;
  std::vector<Counters> per_tile;
};

struct Buffers {
  int width;
  std::uint32_t* rgba;
  float* depth;
  PolygonId* ids;
  std::uint32_t* overdraw;
};


template <DepthFunc F>
inline bool depthPasses(float z, float stored) {
  if constexpr (F == DepthFunc::Never) return false;
  if constexpr (F == DepthFunc::Less) return z < stored;
  if constexpr (F == DepthFunc::Equal) return z == stored;
  if constexpr (F == DepthFunc::LEqual) return z <= stored;
  if constexpr (F == DepthFunc::Greater) return z > stored;
  if constexpr (F == DepthFunc::NotEqual) return z != stored;
  if constexpr (F == DepthFunc::GEqual) return z >= stored;
  return true;  // Always
}

std::uint32_t blend(std::uint32_t src, std::uint32_t dst) {
  const std::uint32_t a = src >> 24;
  std::uint32_t out = 0xFF000000u;
  for (int s = 0; s < 24; s += 8) {
    const std::uint32_t cs = (src >> s) & 0xFF, cd = (dst >> s) & 0xFF;
    out |= ((cs * a + cd * (255 - a) + 127) / 255) << s;
  }
  return out;
}

#if defined(__SSE4_1__)
template <DepthFunc F>
inline __m128 depthPasses4(__m128 z, __m128 stored) {
  if constexpr (F == DepthFunc::Never) return _mm_setzero_ps();
  if constexpr (F == DepthFunc::Less) return _mm_cmplt_ps(z, stored);
  if constexpr (F == DepthFunc::Equal) return _mm_cmpeq_ps(z, stored);
  if constexpr (F == DepthFunc::LEqual) return _mm_cmple_ps(z, stored);
  if constexpr (F == DepthFunc::Greater) return _mm_cmpgt_ps(z, stored);
  if constexpr (F == DepthFunc::NotEqual) return _mm_cmpneq_ps(z, stored);
  if constexpr (F == DepthFunc::GEqual) return _mm_cmpge_ps(z, stored);
  return _mm_castsi128_ps(_mm_set1_epi32(-1));  // Always
}

// Four pixels of an opaque span at once: the same depth test, with depth still stepped
// incrementally (four lanes, each advanced by 4 dz/dx). Returns fragments written.
template <DepthFunc F>
inline int spanOpaque4(float* depth, PolygonId* ids, std::uint32_t* rgba, std::uint32_t* overdraw,
                       __m128 z, const ScreenTriangle& t, bool depth_mask) {
  const __m128 zc = _mm_min_ps(_mm_max_ps(z, _mm_setzero_ps()), _mm_set1_ps(1.0f));
  const __m128 stored = _mm_loadu_ps(depth);
  const __m128 pass = depthPasses4<F>(zc, stored);
  const int bits = _mm_movemask_ps(pass);
  if (bits == 0) return 0;
  const __m128i m = _mm_castps_si128(pass);
  if (depth_mask) _mm_storeu_ps(depth, _mm_blendv_ps(stored, zc, pass));
  auto blendStore = [&](void* p, std::uint32_t value) {
    const __m128i old = _mm_loadu_si128(static_cast<const __m128i*>(p));
    _mm_storeu_si128(static_cast<__m128i*>(p),
                     _mm_blendv_epi8(old, _mm_set1_epi32(static_cast<int>(value)), m));
  };
  blendStore(ids, t.id);
  blendStore(rgba, t.rgba);
  const __m128i od = _mm_loadu_si128(reinterpret_cast<const __m128i*>(overdraw));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(overdraw), _mm_sub_epi32(od, m));  // mask = -1
  return __builtin_popcount(static_cast<unsigned>(bits));
}
#endif

// One fragment: the depth test, then depth (if the mask allows), id and colour; a
// transparent polygon blends its colour and leaves depth and id alone.
template <DepthFunc F>
inline void writeFragment(const ScreenTriangle& t, const Buffers& fb, std::size_t idx, float z,
                          bool depth_mask, Counters& c) {
  const float zc = std::clamp(z, 0.0f, 1.0f);  // GL clamps window depth to [0,1]
  if (!depthPasses<F>(zc, fb.depth[idx])) return;
  c.written++;
  fb.overdraw[idx]++;
  if (t.transparent) {
    fb.rgba[idx] = blend(t.rgba, fb.rgba[idx]);
    return;
  }
  if (depth_mask) fb.depth[idx] = zc;
  fb.ids[idx] = t.id;
  fb.rgba[idx] = t.rgba;
}

// One triangle clipped to one tile: the notes' scan conversion with incremental depth.
template <DepthFunc F>
void rasterTriangle(const ScreenTriangle& t, const PixelBox& tile, const Buffers& fb,
                    bool depth_mask, Counters& c) {
  TriangleSetup s = setupTriangle(t, tile.y0);
  const int j0 = std::max(tile.y0, s.y0), j1 = std::min(tile.y1, s.y1);
  const int i0 = std::max(tile.x0, s.x0), i1 = std::min(tile.x1, s.x1);
  if (j0 > j1 || i0 > i1) return;
  for (EdgeSetup& e : s.edge) e.row += e.step_y * (j0 - tile.y0);
  const bool transparent = t.transparent != 0;
  if (i1 - i0 < 8) {
    // Few columns (most triangles of a dense mesh): walk the bounding box, stepping the three
    // edge functions and the depth incrementally; no divisions, no multiplications.
    for (int j = j0; j <= j1; ++j, nextRow(s)) {
      std::int64_t e0 = s.edge[0].row + s.edge[0].step_x * i0;
      std::int64_t e1 = s.edge[1].row + s.edge[1].step_x * i0;
      std::int64_t e2 = s.edge[2].row + s.edge[2].step_x * i0;
      float z = t.z0 + t.dzdy * (static_cast<float>(j) - t.yr) +
                t.dzdx * (static_cast<float>(i0) - t.xr);
      std::size_t idx = static_cast<std::size_t>(j) * fb.width + i0;
      for (int i = i0; i <= i1; ++i, ++idx, z += t.dzdx, e0 += s.edge[0].step_x,
               e1 += s.edge[1].step_x, e2 += s.edge[2].step_x) {
        if ((e0 | e1 | e2) < 0) continue;  // outside some edge (sign bit set)
        c.tested++;
        writeFragment<F>(t, fb, idx, z, depth_mask, c);
      }
    }
    return;
  }
  for (int j = j0; j <= j1; ++j, nextRow(s)) {
    int lo = i0, hi = i1;
    if (!spanOfRow(s, &lo, &hi)) continue;
    // Depth at the span's first pixel from the plane, then one add per pixel.
    float z = t.z0 + t.dzdy * (static_cast<float>(j) - t.yr) +
              t.dzdx * (static_cast<float>(lo) - t.xr);
    std::size_t idx = static_cast<std::size_t>(j) * fb.width + lo;
    c.tested += static_cast<std::uint64_t>(hi - lo + 1);
    int i = lo;
#if defined(__SSE4_1__)
    if (!transparent && hi - lo >= 7) {
      __m128 z4 = _mm_add_ps(_mm_set1_ps(z), _mm_mul_ps(_mm_set1_ps(t.dzdx),
                                                        _mm_setr_ps(0.0f, 1.0f, 2.0f, 3.0f)));
      const __m128 step = _mm_set1_ps(4.0f * t.dzdx);
      for (; i + 3 <= hi; i += 4, idx += 4, z4 = _mm_add_ps(z4, step))
        c.written += spanOpaque4<F>(fb.depth + idx, fb.ids + idx, fb.rgba + idx,
                                    fb.overdraw + idx, z4, t, depth_mask);
      z = _mm_cvtss_f32(z4);  // the tail continues from the next lane's depth
    }
#endif
    for (; i <= hi; ++i, ++idx, z += t.dzdx) writeFragment<F>(t, fb, idx, z, depth_mask, c);
  }
}

// A line by DDA through pixel centres (one pixel per step along the major axis), depth
// interpolated linearly. `outline` lines only colour pixels whose stored depth they reach.
template <DepthFunc F>
void rasterLine(const ScreenLine& l, const PixelBox& tile, const Buffers& fb, bool depth_mask,
                bool outline, Counters& c) {
  const float dx = l.x1 - l.x0, dy = l.y1 - l.y0;
  const float len = std::max(std::abs(dx), std::abs(dy));
  const int steps = std::isfinite(len) ? static_cast<int>(std::min(std::ceil(len), 1e6f)) : 0;
  // Only the steps that can land in this tile (3 px of margin for rounding and the pen):
  // each tile walks its own piece of the line, the same steps as a walk of the whole line.
  int k0 = 0, k1 = steps;
  auto limit = [&](float a, float d, int lo, int hi) {
    if (d == 0.0f || steps == 0) return;
    double ka = (static_cast<double>(lo) - 3.0 - a) * steps / d;
    double kb = (static_cast<double>(hi) + 3.0 - a) * steps / d;
    if (ka > kb) std::swap(ka, kb);
    k0 = std::max(k0, static_cast<int>(std::max(std::floor(ka), -1.0)));
    k1 = std::min(k1, static_cast<int>(std::min(std::ceil(kb), static_cast<double>(steps))));
  };
  limit(l.x0, dx, tile.x0, tile.x1);
  limit(l.y0, dy, tile.y0, tile.y1);
  k0 = std::max(k0, 0);
  for (int k = k0; k <= k1; ++k) {
    const float t = steps == 0 ? 0.0f : static_cast<float>(k) / static_cast<float>(steps);
    const int i = static_cast<int>(std::lround(l.x0 + dx * t));
    const int j = static_cast<int>(std::lround(l.y0 + dy * t));
    const float z = std::clamp(l.z0 + (l.z1 - l.z0) * t, 0.0f, 1.0f);
    if (outline) {
      // A 2x2 pen, so the outline reads at any size. A silhouette pixel shows when nothing
      // is drawn there, when one of the edge's own two polygons is the visible one, or when
      // it is nearer than what is there (with a small tolerance); hidden ones stay hidden.
      for (int pj = j - 1; pj <= j; ++pj)
        for (int pi = i - 1; pi <= i; ++pi) {
          if (pi < tile.x0 || pi > tile.x1 || pj < tile.y0 || pj > tile.y1) continue;
          const std::size_t pk = static_cast<std::size_t>(pj) * fb.width + pi;
          const PolygonId there = fb.ids[pk];
          if (there == kNoPolygon || there == l.id || there == l.other ||
              z <= fb.depth[pk] + 2e-4f)
            fb.rgba[pk] = l.rgba;
        }
      continue;
    }
    if (i < tile.x0 || i > tile.x1 || j < tile.y0 || j > tile.y1) continue;
    const std::size_t idx = static_cast<std::size_t>(j) * fb.width + i;
    c.tested++;
    if (!depthPasses<F>(z, fb.depth[idx])) continue;
    c.written++;
    fb.overdraw[idx]++;
    if (depth_mask) fb.depth[idx] = z;
    fb.ids[idx] = l.id;
    fb.rgba[idx] = l.rgba;
  }
}

struct TileJob {
  const PreparedScene& ps;
  const Bins& tri_bins;
  const Bins& line_bins;
  const Bins& point_bins;
  const Bins& outline_bins;
  const Buffers& fb;
  bool depth_mask;
};

template <DepthFunc F>
Counters rasterTile(const TileJob& job, std::size_t tile_index) {
  const Bins& tb = job.tri_bins;
  const int tx = static_cast<int>(tile_index % tb.tiles_x);
  const int ty = static_cast<int>(tile_index / tb.tiles_x);
  const PixelBox tile{tx * kTile, ty * kTile, std::min(job.ps.width, (tx + 1) * kTile) - 1,
                      std::min(job.ps.height, (ty + 1) * kTile) - 1};
  Counters c;
  bool any_transparent = false;
  for (std::size_t k = tb.start[tile_index]; k < tb.start[tile_index + 1]; ++k) {
    const ScreenTriangle& t = job.ps.triangles[tb.items[k]];
    if (t.transparent) {
      any_transparent = true;
      continue;
    }
    rasterTriangle<F>(t, tile, job.fb, job.depth_mask, c);
  }
  if (any_transparent) {
    for (std::size_t k = tb.start[tile_index]; k < tb.start[tile_index + 1]; ++k) {
      const ScreenTriangle& t = job.ps.triangles[tb.items[k]];
      if (t.transparent) rasterTriangle<F>(t, tile, job.fb, false, c);
    }
  }
  const Bins& lb = job.line_bins;
  for (std::size_t k = lb.start[tile_index]; k < lb.start[tile_index + 1]; ++k)
    rasterLine<F>(job.ps.lines[lb.items[k]], tile, job.fb, job.depth_mask, false, c);
  const Bins& pb = job.point_bins;
  for (std::size_t k = pb.start[tile_index]; k < pb.start[tile_index + 1]; ++k)
    rasterLine<F>(job.ps.points[pb.items[k]], tile, job.fb, job.depth_mask, false, c);
  const Bins& ob = job.outline_bins;
  for (std::size_t k = ob.start[tile_index]; k < ob.start[tile_index + 1]; ++k)
    rasterLine<F>(job.ps.outline[ob.items[k]], tile, job.fb, false, true, c);
  return c;
}

using TileFn = Counters (*)(const TileJob&, std::size_t);

TileFn tileFunction(DepthFunc f) {
  switch (f) {
    case DepthFunc::Never: return &rasterTile<DepthFunc::Never>;
    case DepthFunc::Less: return &rasterTile<DepthFunc::Less>;
    case DepthFunc::Equal: return &rasterTile<DepthFunc::Equal>;
    case DepthFunc::LEqual: return &rasterTile<DepthFunc::LEqual>;
    case DepthFunc::Greater: return &rasterTile<DepthFunc::Greater>;
    case DepthFunc::NotEqual: return &rasterTile<DepthFunc::NotEqual>;
    case DepthFunc::GEqual: return &rasterTile<DepthFunc::GEqual>;
    case DepthFunc::Always: break;
  }
  return &rasterTile<DepthFunc::Always>;
}

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void renderZBuffer(const AlgorithmInput& in, Frame& frame) {
  // Clear colour, depth and ids, as glClear(COLOR | DEPTH), then draw.
  const auto t0 = std::chrono::steady_clock::now();
  clearFrame(frame, in.prepared.width, in.prepared.height, in.options);
  frame.stats.addStage("clear", msSince(t0));
  drawZBuffer(in, frame);
}

void drawZBuffer(const AlgorithmInput& in, Frame& frame) {
  const PreparedScene& ps = in.prepared;
  const RenderOptions& o = in.options;
  const int w = ps.width, h = ps.height;
  if (frame.width != w || frame.height != h) throw Error("frame size differs from the camera's");
  auto t0 = std::chrono::steady_clock::now();
  std::unique_ptr<ZBufferScratch> own;
  ZBufferScratch& z = algorithmScratch(in, own);
  binPrimitives(ps.triangles, w, h, triangleBox, z.tri_bins, z.counts);
  binPrimitives(ps.lines, w, h, lineBox, z.line_bins, z.counts);
  binPrimitives(ps.points, w, h, lineBox, z.point_bins, z.counts);
  binPrimitives(ps.outline, w, h, lineBox, z.outline_bins, z.counts);
  const Bins& tri_bins = z.tri_bins;
  const Bins& line_bins = z.line_bins;
  const Bins& point_bins = z.point_bins;
  const Bins& outline_bins = z.outline_bins;
  frame.stats.addStage("bin", msSince(t0));
  frame.stats.fragments_tested = frame.stats.fragments_written = 0;

  t0 = std::chrono::steady_clock::now();
  const Buffers fb{w, frame.color.data(), frame.depth.data(), frame.ids.data(), frame.overdraw.data()};
  // GL: with the depth test disabled every fragment passes and the depth buffer is not written.
  const DepthFunc func = o.depth_test ? o.depth_func : DepthFunc::Always;
  const bool depth_mask = o.depth_test && o.depth_mask;
  const TileJob job{ps, tri_bins, line_bins, point_bins, outline_bins, fb, depth_mask};
  const TileFn fn = tileFunction(func);
  const std::size_t tiles = static_cast<std::size_t>(tri_bins.tiles_x) * tri_bins.tiles_y;
  std::vector<Counters>& per_tile = z.per_tile;
  per_tile.assign(tiles, Counters{});
  tbb::parallel_for(std::size_t(0), tiles, [&](std::size_t t) { per_tile[t] = fn(job, t); });
  for (const Counters& c : per_tile) {
    frame.stats.fragments_tested += c.tested;
    frame.stats.fragments_written += c.written;
  }
  frame.stats.addStage("raster", msSince(t0));

  frame.stats.state_bytes = frame.color.size() * 4 + frame.depth.size() * 4 +
                            frame.ids.size() * 4 + frame.overdraw.size() * 4 + tri_bins.bytes() +
                            line_bins.bytes() + point_bins.bytes() + outline_bins.bytes() +
                            ps.triangles.capacity() * sizeof(ScreenTriangle);
}

}  // namespace hsr::detail
