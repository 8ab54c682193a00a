// Choosing the span path once per process (and on request, for the test that compares them).

#include "raster/span.hpp"

#include <atomic>

namespace hsr::detail {
namespace {

SpanPath detectPath() {
  if (sse41SpanFunction(DepthFunc::Less) == nullptr) return SpanPath::kScalar;
#if defined(__x86_64__) || defined(__i386__)
  if (!__builtin_cpu_supports("sse4.1")) return SpanPath::kScalar;
  if (avx2SpanFunction(DepthFunc::Less) != nullptr && __builtin_cpu_supports("avx2"))
    return SpanPath::kAvx2;
#endif
  return SpanPath::kSse41;
}

std::atomic<SpanPath>& currentPath() {
  static std::atomic<SpanPath> path{detectPath()};
  return path;
}

}  // namespace

RasterPath rasterPath(DepthFunc f) {
  return {spanFunction(f), activeSpanPath() != SpanPath::kScalar};
}

SpanPath activeSpanPath() { return currentPath().load(std::memory_order_relaxed); }

bool spanPathAvailable(SpanPath path) {
  // Each path's processor also runs the narrower ones.
  return static_cast<int>(path) <= static_cast<int>(detectPath());
}

SpanPath setSpanPath(SpanPath path) {
  if (!spanPathAvailable(path)) return activeSpanPath();
  return currentPath().exchange(path);
}

SpanFn spanFunction(DepthFunc f) {
  if (activeSpanPath() == SpanPath::kAvx2) return avx2SpanFunction(f);
  if (activeSpanPath() == SpanPath::kSse41) return sse41SpanFunction(f);
  return withDepthFunc(f, []<DepthFunc F>() -> SpanFn { return &fillSpanScalar<F>; });
}

}  // namespace hsr::detail
