// Depth planes from device-space planes (see depth.hpp for the definition they serve).

#include "raster/depth.hpp"

#include <algorithm>
#include <cmath>

namespace hsr::detail {

bool depthPlaneFromDevicePlane(double a, double b, double c, double d, DepthPlane* out) {
  // |coefficients| <= 1e30 keeps z0 + dzdy*y + dzdx*x below 1e35 for any x, y < 2^15, far
  // inside float's range, so the conversion to float is always defined.
  constexpr double kLimit = 1e30;
  if (c == 0.0) return false;
  DepthPlane p{-a / c, -b / c, -d / c};
  if (!(std::abs(p.dzdx) <= kLimit && std::abs(p.dzdy) <= kLimit && std::abs(p.z0) <= kLimit))
    return false;  // also for NaN
  *out = p;
  return true;
}

DepthPlane flatDepthPlane(double z) {
  return {0.0, 0.0, std::isfinite(z) ? std::clamp(z, 0.0, 1.0) : 1.0};
}

}  // namespace hsr::detail
