#pragma once
// THE definition of a fragment's depth, shared by every renderer in hsr.
//
// The notes: a polygon has the plane equation A x + B y + C z + D = 0 in device coordinates,
// so at pixel (x, y) its depth is z = (-A x - B y - D) / C, and one pixel to the right
// z' = z - A/C. hsr keeps the three quotients of that equation per polygon, in double:
//
//     z(x, y) = (z0 + dzdy * y) + dzdx * x      dzdx = -A/C, dzdy = -B/C, z0 = -D/C
//
// with (x, y) the pixel's integer column and row (rows counted from the top, pixel centres at
// integers) and that order of operations, then rounded once to float and clamped to [0, 1]
// as OpenGL clamps window depth. A fragment's depth is therefore a function of its polygon
// and its pixel alone: every path (scalar or SIMD lane), every tile and every algorithm that
// fills the polygon computes the same float there. Stepping z' = z - A/C in floating point
// would round at every step and make the depth depend on where the span began (which is
// what once made two builds of hsr disagree on 27,246 depth values of the demo scene).

#include <cmath>

namespace hsr::detail {

// A plain struct (no initialisers, so arrays of primitives holding it can be allocated
// without a zero fill): DepthPlane{} is the plane z = 0.
struct DepthPlane {
  double dzdx;  // -A/C: change of depth per pixel to the right
  double dzdy;  // -B/C: change per row downwards
  double z0;    // -D/C: the plane at pixel (0, 0)
};

// The row's part of the sum, computed once per row: z0 + dzdy * y.
inline double depthRowStart(const DepthPlane& p, int y) {
  return p.z0 + p.dzdy * static_cast<double>(y);
}

// Depth at column x of a row whose depthRowStart is `row`.
inline float depthInRow(double row, const DepthPlane& p, int x) {
  const float z = static_cast<float>(row + p.dzdx * static_cast<double>(x));
  // Clamped as written (not std::clamp) because the SIMD sibling must match it bit for bit,
  // -0.0 included: max(0, z) and min(1, z) with z as the second operand.
  return z > 1.0f ? 1.0f : (0.0f > z ? 0.0f : z);
}

inline float fragmentDepth(const DepthPlane& p, int x, int y) {
  return depthInRow(depthRowStart(p, y), p, x);
}

// The depth at a sub-pixel sample (ox, oy) sub-pixel units (1/256) from pixel (x, y)'s centre
// (the A-buffer's samples): the same plane, order of operations and clamp, at the sample's
// position. At offset (0, 0) it is fragmentDepth, bit for bit (y + 0.0 is y exactly).
inline float sampleDepth(const DepthPlane& p, int x, int y, int ox, int oy) {
  const double row = p.z0 + p.dzdy * (static_cast<double>(y) + static_cast<double>(oy) / 256.0);
  const float z =
      static_cast<float>(row + p.dzdx * (static_cast<double>(x) + static_cast<double>(ox) / 256.0));
  return z > 1.0f ? 1.0f : (0.0f > z ? 0.0f : z);
}

// Comparing two planes over a box of pixels (a scan-line span, a Warnock area) instead of
// pixel by pixel. The plane's depth in double at pixel (x, y), before fragmentDepth rounds it:
inline double planeDepth(const DepthPlane& p, int x, int y) {
  return depthRowStart(p, y) + p.dzdx * static_cast<double>(x);
}
// Plane P is in front of plane Q on a whole box when at each corner (a difference of planes is
// extreme at a corner) P's planeDepth is in [0, 1] and below Q's by kSafeDepthGap: depths are
// in [0, 1], where a float's spacing is at most 2^-24, so the gap survives the rounding at
// every pixel in between, and P's fragment depth is strictly smaller there too...
inline constexpr double kSafeDepthGap = 0x1p-20;
// ... provided planeDepth is itself good to far better than the gap: its terms stay below
// this bound (then its error is below 2^-33).
inline bool planeDepthIsSafe(const DepthPlane& p, int x, int y) {
  constexpr double kTermLimit = 0x1p+18;
  return std::abs(p.z0) + std::abs(p.dzdy * y) + std::abs(p.dzdx * x) < kTermLimit;
}

// The depth plane of the device-space plane A x + B y + C z + D = 0 (x, y in the pixel
// coordinates above, z window depth). Returns false for a plane seen edge-on (C = 0) or so
// steep that its depth could leave float's range within the largest viewport: such a polygon
// covers next to no pixels, and the caller gives it a constant depth (flatDepthPlane).
inline bool depthPlaneFromDevicePlane(double a, double b, double c, double d, DepthPlane* out) {
  // |coefficients| <= 1e30 keeps z0 + dzdy*y + dzdx*x below 1e35 for any x, y < 2^15, far
  // inside float's range, so the conversion to float is always defined.
  constexpr double kLimit = 1e30;
  if (c == 0.0) return false;
  const DepthPlane p{-a / c, -b / c, -d / c};
  if (!(std::abs(p.dzdx) <= kLimit && std::abs(p.dzdy) <= kLimit && std::abs(p.z0) <= kLimit))
    return false;  // also for NaN
  *out = p;
  return true;
}
// The constant depth z, clamped to [0, 1] (1 when z is not finite).
DepthPlane flatDepthPlane(double z);

}  // namespace hsr::detail
