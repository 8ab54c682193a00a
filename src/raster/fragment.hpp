#pragma once
// Writing one fragment: the depth test (glDepthFunc), then depth (if glDepthMask allows), the
// polygon id and the colour; a transparent polygon blends its colour over what is there and
// leaves depth and id alone. Every renderer writes its fragments through here.

#include <cstddef>
#include <cstdint>

#include "hsr/render.hpp"
#include "raster/primitives.hpp"

namespace hsr::detail {

// The frame's buffers, as raw pointers (width * height each, top row first).
struct FrameView {
  int width = 0, height = 0;
  std::uint32_t* rgba = nullptr;
  float* depth = nullptr;
  PolygonId* ids = nullptr;
  std::uint32_t* overdraw = nullptr;

  explicit FrameView(Frame& f)
      : width(f.width),
        height(f.height),
        rgba(f.color.data()),
        depth(f.depth.data()),
        ids(f.ids.data()),
        overdraw(f.overdraw.data()) {}
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * width + x; }
};

// Fragments that reached the depth test, and those that passed and were written.
struct FragmentCounts {
  std::uint64_t tested = 0, written = 0;
  FragmentCounts& operator+=(const FragmentCounts& o) {
    tested += o.tested;
    written += o.written;
    return *this;
  }
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

// The same test with the function chosen at run time (for the few fragments of lines).
bool depthPasses(DepthFunc f, float z, float stored);

// The depth func in effect: with GL_DEPTH_TEST disabled every fragment passes (and, see
// depthWrites, none writes depth).
inline DepthFunc effectiveDepthFunc(const RenderOptions& o) {
  return o.depth_test ? o.depth_func : DepthFunc::Always;
}
inline bool depthWrites(const RenderOptions& o) { return o.depth_test && o.depth_mask; }

// src over dst with src's alpha, per channel rounded to nearest; the result is opaque.
std::uint32_t blendOver(std::uint32_t src, std::uint32_t dst);

// One fragment of triangle t at buffer index idx with depth z.
template <DepthFunc F>
inline void writeFragment(const ScreenTriangle& t, const FrameView& fb, std::size_t idx, float z,
                          bool depth_mask, FragmentCounts& c) {
  c.tested++;
  if (!depthPasses<F>(z, fb.depth[idx])) return;
  c.written++;
  fb.overdraw[idx]++;
  if (t.transparent()) {
    fb.rgba[idx] = blendOver(t.rgba, fb.rgba[idx]);
    return;
  }
  if (depth_mask) fb.depth[idx] = z;
  fb.ids[idx] = t.id;
  fb.rgba[idx] = t.rgba;
}

// Calls f.template operator()<F>() with the depth func as a template argument, so inner
// loops are compiled once per function with the comparison inlined.
template <class Fn>
decltype(auto) withDepthFunc(DepthFunc func, Fn&& f) {
  switch (func) {
    case DepthFunc::Never:
      return f.template operator()<DepthFunc::Never>();
    case DepthFunc::Less:
      return f.template operator()<DepthFunc::Less>();
    case DepthFunc::Equal:
      return f.template operator()<DepthFunc::Equal>();
    case DepthFunc::LEqual:
      return f.template operator()<DepthFunc::LEqual>();
    case DepthFunc::Greater:
      return f.template operator()<DepthFunc::Greater>();
    case DepthFunc::NotEqual:
      return f.template operator()<DepthFunc::NotEqual>();
    case DepthFunc::GEqual:
      return f.template operator()<DepthFunc::GEqual>();
    case DepthFunc::Always:
      break;
  }
  return f.template operator()<DepthFunc::Always>();
}

}  // namespace hsr::detail
