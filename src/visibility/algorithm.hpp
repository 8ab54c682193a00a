#pragma once
// What every visibility algorithm implements, and the registry's entries (registry.cpp holds
// the table). An algorithm draws the prepared scene into a frame that render() has sized and
// cleared (or, for the GL facade, left as the previous draws made it).

#include <memory>
#include <vector>

#include "core/trace.hpp"
#include "hsr/render.hpp"
#include "pipeline/pipeline.hpp"

namespace hsr::detail {

struct AlgorithmInput {
  const Scene& scene;
  const Camera& camera;
  const RenderOptions& options;
  const PreparedScene& prepared;
  std::shared_ptr<void>* scratch = nullptr;  // the algorithm's own reusable memory, if any
  Trace* trace = nullptr;                    // non-null only when explaining
  const void* given = nullptr;               // built beforehand by the caller: render(const Bsp&)
                                             // passes its detail::BspTree to "bsp"
};

using AlgorithmFn = void (*)(const AlgorithmInput& input, Frame& frame);

struct AlgorithmEntry {
  AlgorithmInfo info;
  AlgorithmFn draw;
};

const std::vector<AlgorithmEntry>& algorithmTable();
const AlgorithmEntry& findEntry(std::string_view name);  // throws hsr::Error when unknown

// The algorithm's scratch of type T, created on first use (a fresh one without a cache).
template <class T>
T& algorithmScratch(const AlgorithmInput& in, std::unique_ptr<T>& fallback) {
  if (in.scratch) {
    if (!*in.scratch) *in.scratch = std::make_shared<T>();
    return *static_cast<T*>(in.scratch->get());
  }
  fallback = std::make_unique<T>();
  return *fallback;
}

// The algorithms (one file each in src/visibility/).
void drawZBufferTextbook(const AlgorithmInput& input, Frame& frame);   // zbuffer.cpp
void drawZBufferTiled(const AlgorithmInput& input, Frame& frame);      // zbuffer_tiled.cpp
void drawPainter(const AlgorithmInput& input, Frame& frame);           // painter.cpp
void drawPainterNaive(const AlgorithmInput& input, Frame& frame);      // painter_naive.cpp
void drawBsp(const AlgorithmInput& input, Frame& frame);               // bsp.cpp
void drawScanlineTextbook(const AlgorithmInput& input, Frame& frame);  // scanline.cpp
void drawScanline(const AlgorithmInput& input, Frame& frame);          // scanline_fast.cpp
void drawWarnock(const AlgorithmInput& input, Frame& frame);           // warnock.cpp
void drawOctree(const AlgorithmInput& input, Frame& frame);            // octree.cpp
void drawRaycastTextbook(const AlgorithmInput& input, Frame& frame);   // raycast.cpp
void drawRaycast(const AlgorithmInput& input, Frame& frame);           // raycast_fast.cpp
void drawABufferTextbook(const AlgorithmInput& input, Frame& frame);   // abuffer.cpp
void drawABuffer(const AlgorithmInput& input, Frame& frame);           // abuffer_fast.cpp
void drawWeilerAtherton(const AlgorithmInput& input, Frame& frame);    // weiler_atherton.cpp
void drawRoberts(const AlgorithmInput& input, Frame& frame);           // roberts.cpp

}  // namespace hsr::detail
