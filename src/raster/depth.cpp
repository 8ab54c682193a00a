// Depth planes from device-space planes (see depth.hpp for the definition they serve).

#include "raster/depth.hpp"

#include <algorithm>
#include <cmath>

namespace hsr::detail {

DepthPlane flatDepthPlane(double z) {
  return {0.0, 0.0, std::isfinite(z) ? std::clamp(z, 0.0, 1.0) : 1.0};
}

}  // namespace hsr::detail
