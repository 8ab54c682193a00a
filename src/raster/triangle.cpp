// rasterTriangle with the depth func chosen at run time.

#include "raster/triangle.hpp"

namespace hsr::detail {

void rasterTriangle(const ScreenTriangle& t, const PixelBox& clip, const FrameView& fb,
                    DepthFunc func, bool depth_mask, FragmentCounts& c) {
  const RasterPath path = rasterPath(func);
  withDepthFunc(func, [&]<DepthFunc F>() { rasterTriangle<F>(t, clip, fb, depth_mask, path, c); });
}

}  // namespace hsr::detail
